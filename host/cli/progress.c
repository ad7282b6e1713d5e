#define _POSIX_C_SOURCE 200809L
#include "cli/progress.h"

#include <stdio.h>
#include <unistd.h>

void progress_init(Progress *p, int quiet, uint64_t pixels, double time_budget)
{
    p->enabled = !quiet && isatty(STDERR_FILENO);
    p->pixels = pixels;
    p->time_budget = time_budget;
    p->drawn = 0;
}

void progress_update(void *user, uint64_t done, uint64_t total, double seconds)
{
    Progress *p = user;
    if (!p->enabled || total == 0)
        return;
    double fraction = (double)done / (double)total;
    double rate = seconds > 0.0 ? (double)done * (double)p->pixels / seconds : 0.0;
    double eta = fraction > 0.0 ? seconds * (1.0 - fraction) / fraction : 0.0;
    if (p->time_budget > 0.0 && p->time_budget - seconds < eta)
        eta = p->time_budget > seconds ? p->time_budget - seconds : 0.0;
    const int width = 30;
    int filled = (int)(fraction * width);
    char bar[31];
    for (int i = 0; i < width; ++i)
        bar[i] = i < filled ? '#' : '.';
    bar[width] = '\0';
    fprintf(stderr, "\r[%s] %3.0f%%  %llu/%llu spp  %.3g Msamples/s  ETA %.0fs   ", bar, 100.0 * fraction,
            (unsigned long long)done, (unsigned long long)total, rate * 1e-6, eta);
    fflush(stderr);
    p->drawn = 1;
}

void progress_finish(Progress *p)
{
    if (p->drawn)
        fputc('\n', stderr);
    p->drawn = 0;
}
