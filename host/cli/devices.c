#include "cli/devices.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_LISTED 64

static int enumerate(ClDeviceInfo *devices)
{
    int count = cl_devices_enumerate(devices, MAX_LISTED);
    if (count == 0)
        fprintf(stderr, "gmonrt: no OpenCL device found (for PoCL, is POCL_CACHE_DIR writable?)\n");
    return count;
}

int devices_list(void)
{
    ClDeviceInfo devices[MAX_LISTED];
    int count = enumerate(devices);
    if (count <= 0)
        return 1;
    printf("%-5s %-32s %-44s %-11s %5s %9s\n", "index", "platform", "device", "type", "units", "memory");
    for (int i = 0; i < count; ++i)
        printf("%-5d %-32.32s %-44.44s %-11s %5u %6.1f GiB\n", i, devices[i].platform_name, devices[i].name,
               cl_device_type_name(devices[i].type), devices[i].compute_units,
               (double)devices[i].global_memory / (1024.0 * 1024.0 * 1024.0));
    return 0;
}

/* Marks the devices `selection` names in chosen[]. Returns 0, or -1 after
 * printing why it names none here. */
static int select_devices(const DeviceSelection *selection, const ClDeviceInfo *devices, int count, int *chosen)
{
    const char *spec = selection->spec;
    switch (selection->kind) {
    case DEVICES_ALL:
        for (int i = 0; i < count; ++i)
            chosen[i] = 1;
        return 0;
    case DEVICES_CPU:
    case DEVICES_GPU: {
        int cpu = selection->kind == DEVICES_CPU, any = 0;
        for (int i = 0; i < count; ++i)
            any |= chosen[i] = (devices[i].type & (cpu ? CL_DEVICE_TYPE_CPU : CL_DEVICE_TYPE_GPU)) != 0;
        if (!any)
            fprintf(stderr, "gmonrt: --device %s: no %s device (see gmonrt --list-devices)\n", spec,
                    cpu ? "CPU" : "GPU");
        return any ? 0 : -1;
    }
    case DEVICES_INDICES:
        for (int k = 0; k < selection->index_count; ++k) {
            int index = selection->indices[k];
            if (index >= count) {
                fprintf(stderr, "gmonrt: --device %s: no device %d, there are %d (see gmonrt --list-devices)\n", spec,
                        index, count);
                return -1;
            }
            chosen[index] = 1;
        }
        return 0;
    }
    return -1;
}

int devices_open(const DeviceSelection *selection, ClDevice *opened, int capacity)
{
    ClDeviceInfo devices[MAX_LISTED];
    int count = enumerate(devices);
    if (count <= 0)
        return 0;
    int chosen[MAX_LISTED] = {0};
    if (select_devices(selection, devices, count, chosen))
        return -1;
    int n = 0;
    for (int i = 0; i < count; ++i) {
        if (!chosen[i])
            continue;
        if (n == capacity) {
            fprintf(stderr, "gmonrt: warning: using the first %d of the selected devices\n", capacity);
            break;
        }
        if (cl_device_open(&opened[n], &devices[i])) {
            fprintf(stderr, "gmonrt: warning: cannot open device %d '%s'; going on without it\n", i, devices[i].name);
            continue;
        }
        ++n;
    }
    if (n == 0)
        fprintf(stderr, "gmonrt: none of the selected devices could be opened\n");
    return n;
}

void devices_close(ClDevice *devices, int count)
{
    for (int i = 0; i < count; ++i)
        cl_device_close(&devices[i]);
}
