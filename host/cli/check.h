/* gmonrt check SCENE: what a scene needs that gmonrt lacks or that is
 * missing, without rendering it (no OpenCL device needed). */
#ifndef HOST_CLI_CHECK_H
#define HOST_CLI_CHECK_H

#include "cli/options.h"

/* Exit statuses besides 0 (all supported and present), 1 (an unsupported
 * feature, or a scene that cannot be read) and 2 (bad command line). */
#define CHECK_ONLY_FILES_MISSING 3

/* Loads and converts options->input in check mode and prints every
 * diagnostic, one per line, then "N unsupported features, M missing files".
 * Returns the exit status. */
int check_command(const Options *options);

#endif
