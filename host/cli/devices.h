/* Device listing and selection for the command line. */
#ifndef HOST_CLI_DEVICES_H
#define HOST_CLI_DEVICES_H

#include "cl/cl_device.h"

#define DEVICES_MAX 16

/* Prints index, platform, name, type, compute units and memory of every
 * device. Returns the exit status. */
int devices_list(void);

/* Opens the devices `spec` names: "all" (also for NULL), "cpu", "gpu" or
 * comma-separated indices from devices_list. A device that cannot be opened
 * is left out with a warning. Returns the number opened (>= 1), or 0 after
 * printing why none. */
int devices_open(const char *spec, ClDevice *devices, int capacity);

void devices_close(ClDevice *devices, int count);

#endif
