#define _POSIX_C_SOURCE 200809L
#include "cli/interrupt.h"

#include <stdatomic.h>
#include <string.h>
#include <unistd.h>

volatile sig_atomic_t interrupt_signal;
static volatile sig_atomic_t keep_samples;
/* Signals may arrive on several threads at once: one counter decides which
 * is the first (lock-free atomics are async-signal-safe). */
static atomic_int signals_received;
static volatile sig_atomic_t has_temporary;
static char temporary[4096];

/* Only async-signal-safe calls here: write, unlink, _exit. */
static void on_signal(int signal_number)
{
    if (atomic_fetch_add(&signals_received, 1) == 0 && keep_samples) {
        interrupt_signal = signal_number;
        static const char stopping[] = "\ngmonrt: interrupted: finishing the pass to write the samples done "
                                       "(interrupt again to exit at once)\n";
        ssize_t ignored = write(STDERR_FILENO, stopping, sizeof stopping - 1);
        (void)ignored;
        return;
    }
    if (has_temporary)
        unlink(temporary);
    static const char exiting[] = "\ngmonrt: interrupted: exiting at once, existing files left as they were\n";
    ssize_t ignored = write(STDERR_FILENO, exiting, sizeof exiting - 1);
    (void)ignored;
    _exit(128 + signal_number);
}

void interrupt_install(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    const int signals[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof signals / sizeof signals[0]; ++i)
        sigaddset(&action.sa_mask, signals[i]);
    for (size_t i = 0; i < sizeof signals / sizeof signals[0]; ++i)
        sigaction(signals[i], &action, NULL);
}

void interrupt_keep_samples(void)
{
    keep_samples = 1;
}

int interrupt_exit_status(void)
{
    return 128 + interrupt_signal;
}

void interrupt_temporary_file(const char *path)
{
    has_temporary = 0;
    if (path && strlen(path) < sizeof temporary) {
        memcpy(temporary, path, strlen(path) + 1);
        has_temporary = 1;
    }
}
