/* gmonrt estimate: the estimators recomputed on the host from the per-set
 * sums of an EXR written with --write-sets (for example with another Gini
 * mode). */
#ifndef HOST_CLI_ESTIMATE_H
#define HOST_CLI_ESTIMATE_H

#include "cli/options.h"

/* Returns the exit status (0, or 1 after printing the error). */
int estimate_command(const Options *options);

#endif
