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

/* Marks the devices `spec` selects in chosen[]. Returns 0, or -1 after
 * printing why the spec is wrong. */
static int select_devices(const char *spec, const ClDeviceInfo *devices, int count, int *chosen)
{
    if (!spec || strcmp(spec, "all") == 0) {
        for (int i = 0; i < count; ++i)
            chosen[i] = 1;
        return 0;
    }
    if (strcmp(spec, "cpu") == 0 || strcmp(spec, "gpu") == 0) {
        cl_device_type wanted = spec[0] == 'c' ? CL_DEVICE_TYPE_CPU : CL_DEVICE_TYPE_GPU;
        int any = 0;
        for (int i = 0; i < count; ++i)
            any |= chosen[i] = (devices[i].type & wanted) != 0;
        if (!any)
            fprintf(stderr, "gmonrt: --device %s: no %s device (see gmonrt --list-devices)\n", spec,
                    spec[0] == 'c' ? "CPU" : "GPU");
        return any ? 0 : -1;
    }
    for (const char *p = spec;;) {
        char *end = NULL;
        long index = strtol(p, &end, 10);
        if (end == p || (*end != ',' && *end != '\0') || index < 0) {
            fprintf(stderr, "gmonrt: --device %s: expected all, cpu, gpu or indices like 0,2\n", spec);
            return -1;
        }
        if (index >= count) {
            fprintf(stderr, "gmonrt: --device %s: no device %ld, there are %d (see gmonrt --list-devices)\n", spec,
                    index, count);
            return -1;
        }
        if (chosen[index]) {
            fprintf(stderr, "gmonrt: --device %s: device %ld is named twice\n", spec, index);
            return -1;
        }
        chosen[index] = 1;
        if (*end == '\0')
            return 0;
        p = end + 1;
    }
}

int devices_open(const char *spec, ClDevice *opened, int capacity)
{
    ClDeviceInfo devices[MAX_LISTED];
    int count = enumerate(devices);
    if (count <= 0)
        return 0;
    int chosen[MAX_LISTED] = {0};
    if (select_devices(spec, devices, count, chosen))
        return 0;
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
