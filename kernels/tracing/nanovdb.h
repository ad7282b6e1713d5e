/* NanoVDB float grids (the "nanovdb" medium, FEATURE_NANOVDB): lookups in
 * a grid as NanoVDB lays it out in memory, through the C view of its
 * structures that Debian's libnanovdb-dev ships (CNanoVDB.h, copied into the
 * build's generated kernel headers). The host reads and checks the files
 * (host/scene/nanovdb_file.c) and walks the same structures for majorants. */
#ifndef KERNELS_NANOVDB_H
#define KERNELS_NANOVDB_H

#include "../common/compat.h"
#include "../common/vec3.h"

#ifdef __OPENCL_C_VERSION__
/* CNanoVDB.h typedefs the stdint names again, as compat.h does (the same
 * types): OpenCL C 1.2 (C99) warns. */
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wtypedef-redefinition"
#include "CNanoVDB.h"
#pragma clang diagnostic pop
#else
/* CNanoVDB.h defines its accessor functions `inline` without `static`
 * (C99 inline definitions: a call left out of line would need an external
 * definition that no file provides) and many static ones a file may not
 * use; on the host each is made static inline. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wpedantic" /* its zero-length padding arrays */
#include <stdbool.h>
#define inline static inline
#include "CNanoVDB.h"
#undef inline
#pragma GCC diagnostic pop
#endif

/* A nanovdb medium's parameters in medium_values (floats from its offset):
 * rows of the affine maps from the medium's unit cube to the index space
 * of its density and temperature grids, from the density grid's index
 * space back to the cube (the host's majorants), the temperature's
 * offset and scale (pbrt-v4's T = (t - offset) * scale), and a table of
 * the blackbody's linear sRGB (pbrt-v4's BlackbodySpectrum, peak 1) from
 * NANOVDB_TEMPERATURE_MIN kelvin in equal steps. */
#define NANOVDB_DENSITY_FROM_UNIT 0
#define NANOVDB_TEMPERATURE_FROM_UNIT 12
#define NANOVDB_UNIT_FROM_DENSITY 24
#define NANOVDB_TEMPERATURE_OFFSET 36
#define NANOVDB_TEMPERATURE_SCALE 37
#define NANOVDB_BLACKBODY_STEP 38  /* kelvin between entries */
#define NANOVDB_BLACKBODY_COUNT 39 /* entries; 0: no emission */
#define NANOVDB_BLACKBODY 40       /* 3 values an entry */
#define NANOVDB_PARAMETER_COUNT 40
#define NANOVDB_BLACKBODY_ENTRIES 256
#define NANOVDB_TEMPERATURE_MIN 100.0f /* pbrt-v4: no emission at or below */

/* Grids sit in medium_values at offsets that are multiples of this many
 * floats (NanoVDB's 32-byte alignment). */
#define NANOVDB_ALIGNMENT_FLOATS 8

/* The row-major affine map at `rows` (3 x 4) applied to p. */
KERNEL_FN Vec3 nanovdb_affine(GLOBAL const float *rows, Vec3 p)
{
    return vec3(rows[0] * p.x + rows[1] * p.y + rows[2] * p.z + rows[3],
                rows[4] * p.x + rows[5] * p.y + rows[6] * p.z + rows[7],
                rows[8] * p.x + rows[9] * p.y + rows[10] * p.z + rows[11]);
}

/* The grid's value at index-space point p as NanoVDB's trilinear sampler
 * (and pbrt-v4) takes it: voxel (i, j, k) at the point (i, j, k), the eight
 * around p weighed by their distances. */
KERNEL_FN float nanovdb_trilinear(GLOBAL const float *grid_data, Vec3 p)
{
    GLOBAL const cnanovdb_griddata *grid = (GLOBAL const cnanovdb_griddata *)grid_data;
    cnanovdb_readaccessor accessor;
    cnanovdb_readaccessor_init(&accessor, cnanovdb_treedata_rootF(cnanovdb_griddata_tree(grid)));
    float x = floor(p.x), y = floor(p.y), z = floor(p.z);
    float d[3] = {p.x - x, p.y - y, p.z - z};
    int32_t base[3] = {(int32_t)x, (int32_t)y, (int32_t)z};
    float sum = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        int bits[3] = {corner & 1, (corner >> 1) & 1, corner >> 2};
        cnanovdb_coord at;
        float w = 1.0f;
        for (int k = 0; k < 3; ++k) {
            at.mVec[k] = base[k] + bits[k];
            w *= bits[k] ? d[k] : 1.0f - d[k];
        }
        sum += w * cnanovdb_readaccessor_getValueF(&accessor, &at);
    }
    return sum;
}

/* The density and the blackbody radiance of the temperature (linear in the
 * table between entries; the caller applies Lescale) at unit-cube point u.
 * Reads the grid at `density`, the temperature grid at `temperature` (-1:
 * none) and the parameters at `parameters` of medium_values. */
KERNEL_FN float nanovdb_medium_at(GLOBAL const float *values, int32_t density, int32_t temperature, int32_t parameters,
                                  Vec3 u, Vec3 *le)
{
    GLOBAL const float *q = values + parameters;
    *le = vec3(0.0f, 0.0f, 0.0f);
    int count = (int)q[NANOVDB_BLACKBODY_COUNT];
    if (temperature >= 0 && count > 0) {
        float t = nanovdb_trilinear(values + temperature, nanovdb_affine(q + NANOVDB_TEMPERATURE_FROM_UNIT, u));
        t = (t - q[NANOVDB_TEMPERATURE_OFFSET]) * q[NANOVDB_TEMPERATURE_SCALE];
        if (t > NANOVDB_TEMPERATURE_MIN) {
            float at = fmin((t - NANOVDB_TEMPERATURE_MIN) / q[NANOVDB_BLACKBODY_STEP], (float)(count - 1));
            int i = (int)at;
            i = i > count - 2 ? count - 2 : i;
            float f = at - (float)i;
            GLOBAL const float *e = q + NANOVDB_BLACKBODY + 3 * i;
            *le = vec3((1.0f - f) * e[0] + f * e[3], (1.0f - f) * e[1] + f * e[4], (1.0f - f) * e[2] + f * e[5]);
        }
    }
    return nanovdb_trilinear(values + density, nanovdb_affine(q + NANOVDB_DENSITY_FROM_UNIT, u));
}

#endif
