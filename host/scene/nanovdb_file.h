/* NanoVDB files (.nvdb), as NanoVDB 32.x writes them: the float grids that
 * pbrt-v4's "nanovdb" medium reads (nanovdb_file.c). */
#ifndef HOST_SCENE_NANOVDB_FILE_H
#define HOST_SCENE_NANOVDB_FILE_H

#include <stddef.h>
#include <stdint.h>

/* One grid, its bytes as NanoVDB lays the grid out in memory (32-byte
 * aligned), checked: every node it points to lies inside it. */
typedef struct {
    void *data;
    uint64_t size;
    double world_bounds[2][3]; /* of its active values (NanoVDB's world bbox) */
    float largest;             /* the largest value it holds, tiles and background included */
} NanoGrid;

/* Reads the grid called `name` from the file at `path`. Returns 0 with
 * *grid filled, 1 when the file holds no grid of that name, or -1 with a
 * message in `error` (an unreadable, corrupt or truncated file, another
 * NanoVDB major version, a grid that is not of floats or not a fog volume,
 * a compression the file needs that this build cannot undo). */
int nanovdb_read(const char *path, const char *name, NanoGrid *grid, char *error, size_t error_size);

void nanovdb_free(NanoGrid *grid);

/* Calls visit for every part of a checked grid that holds values, in index
 * space (inclusive voxel bounds): each leaf with the largest of its
 * voxels, each tile with its value; and the background, once, with
 * lo > hi. */
typedef void NanoRegionVisit(void *context, const int32_t lo[3], const int32_t hi[3], float value);
void nanovdb_visit(const NanoGrid *grid, NanoRegionVisit *visit, void *context);

/* The grid's map from index to world space (NanoVDB's, in double): world =
 * matrix (row-major) * index + translation; and its inverse's matrix. */
void nanovdb_map(const NanoGrid *grid, double matrix[9], double inverse[9], double translation[3]);

#endif
