/* Ctrl-C (SIGINT), SIGTERM and SIGHUP: what a user, `timeout`, Slurm's time
 * limit and a closed terminal send. Until a render has samples to keep, a
 * signal exits at once; once it has, the first signal asks the render to
 * stop after its pass (interrupt_signal), so that the samples done are
 * written, and a second one exits at once (the same signal again within
 * 100 ms counts as the first: `timeout` delivers it twice). Exiting at
 * once removes the
 * temporary file being written, if any, so existing outputs stay as they
 * were. The exit status is 128 + the signal, as shells report. */
#ifndef HOST_CLI_INTERRUPT_H
#define HOST_CLI_INTERRUPT_H

#include <signal.h>

/* The first signal received while samples are kept; 0: none. */
extern volatile sig_atomic_t interrupt_signal;

/* Installs the handlers (exit at once until interrupt_keep_samples). */
void interrupt_install(void);

/* From now on the first signal only sets interrupt_signal. */
void interrupt_keep_samples(void);

/* 128 + interrupt_signal. */
int interrupt_exit_status(void);

/* The temporary file being written (removed on an exit at once); NULL when
 * none. The path is copied. */
void interrupt_temporary_file(const char *path);

#endif
