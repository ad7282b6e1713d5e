#define _POSIX_C_SOURCE 200809L
#include "cli/interrupt.h"

#include <stdatomic.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

volatile sig_atomic_t interrupt_signal;
static volatile sig_atomic_t keep_samples;
/* Signals may arrive on several threads at once: one counter decides which
 * is the first (lock-free atomics are async-signal-safe). */
static atomic_int signals_received;
/* The first one's number and time (ms): GNU timeout sends its signal to
 * the command and then to its whole process group, so the command gets it
 * twice within microseconds; the same signal again within
 * REPEAT_WINDOW_MS is that one signal, not a second interrupt. */
static atomic_int first_signal;
static atomic_llong first_signal_ms;
#define REPEAT_WINDOW_MS 100

static long long monotonic_ms(void)
{
    struct timespec now; /* clock_gettime is async-signal-safe */
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (long long)now.tv_sec * 1000 + now.tv_nsec / 1000000;
}
static volatile sig_atomic_t has_temporary;
static char temporary[4096];

/* Only async-signal-safe calls here: write, unlink, _exit. */
static void on_signal(int signal_number)
{
    long long now = monotonic_ms();
    int order = atomic_fetch_add(&signals_received, 1);
    if (order == 0) {
        atomic_store(&first_signal_ms, now);
        atomic_store(&first_signal, signal_number);
    } else if (keep_samples && atomic_load(&first_signal) == signal_number &&
               now - atomic_load(&first_signal_ms) < REPEAT_WINDOW_MS) {
        return; /* the same signal, delivered twice */
    }
    if (order == 0 && keep_samples) {
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
