/* A progress bar on stderr (only when stderr is a terminal): samples per
 * pixel done, samples/s and the time left. */
#ifndef HOST_CLI_PROGRESS_H
#define HOST_CLI_PROGRESS_H

#include <stdint.h>

typedef struct {
    int enabled;
    uint64_t pixels;
    double time_budget; /* seconds, 0 for none: ETA from it when sooner */
    int drawn;
} Progress;

void progress_init(Progress *progress, int quiet, uint64_t pixels, double time_budget);

/* A RenderSettings.progress callback; `user` is the Progress. */
void progress_update(void *user, uint64_t done, uint64_t total, double seconds);

/* Ends the bar's line, if one was drawn. */
void progress_finish(Progress *progress);

#endif
