/* Device listing and selection for the command line. */
#ifndef HOST_CLI_DEVICES_H
#define HOST_CLI_DEVICES_H

#include "cl/cl_device.h"
#include "cli/options.h"

#define DEVICES_MAX 16

/* Prints index, platform, name, type, compute units and memory of every
 * device. Returns the exit status. */
int devices_list(void);

/* Opens the devices `selection` names (indices as devices_list numbers
 * them). A device that cannot be opened is left out with a warning.
 * Returns the number opened (>= 1); 0 after printing why none could be
 * (no device, or none opened: exit 1); or -1 after printing that the
 * selection names no device here (a bad --device: exit 2). */
int devices_open(const DeviceSelection *selection, ClDevice *devices, int capacity);

void devices_close(ClDevice *devices, int count);

#endif
