/* gmonrt merge: combines EXRs of disjoint sample ranges of one render (same
 * scene, resolution, M and seed, written with --write-sets) into the EXR of
 * a single render over their union. Set sums are exact integers, so the
 * merged sums, and every estimate from them, are bit for bit those of the
 * single render. */
#ifndef HOST_CLI_MERGE_H
#define HOST_CLI_MERGE_H

#include "cli/options.h"

/* Returns the exit status (0, or 1 after printing the error). */
int merge_command(const Options *options);

#endif
