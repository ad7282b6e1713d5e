#define _POSIX_C_SOURCE 200809L /* fseeko */
#define _FILE_OFFSET_BITS 64
/* NanoVDB files: a file is segments, each a 16-byte header (magic, version,
 * grid count, codec), then per grid 176 bytes of metadata and its name,
 * then the grids' bytes, each as stored with the segment's codec (none;
 * zlib: a 64-bit size and the stream; Blosc: chunks of at most 1 GiB, each
 * a 64-bit size and the chunk). The layout is NanoVDB's util/IO.h; the
 * grid's own structures are read through CNanoVDB.h (kernels/tracing/
 * nanovdb.h), and every node a lookup may reach is checked to lie inside the
 * grid's bytes before the grid is used. */
#include "scene/nanovdb_file.h"
#include "nanovdb.h"

#include <blosc.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define FILE_MAGIC 0x304244566f6e614eull /* "NanoVDB0", little-endian */
#define MAJOR_VERSION 32u                /* the file format of NanoVDB 32.x, pbrt-v4's and Debian's */
#define BLOSC_CHUNK (1ull << 30)

enum { HEADER_SIZE = 16, META_SIZE = 176 };
enum { CODEC_NONE, CODEC_ZIP, CODEC_BLOSC };
enum { CLASS_UNKNOWN = 0, CLASS_FOG_VOLUME = 2 };

static uint64_t u64_at(const unsigned char *b)
{
    uint64_t v;
    memcpy(&v, b, sizeof v);
    return v;
}

static uint32_t u32_at(const unsigned char *b)
{
    uint32_t v;
    memcpy(&v, b, sizeof v);
    return v;
}

static int fail(char *error, size_t size, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(error, size, format, args);
    va_end(args);
    return -1;
}

/* The walk over a grid's tree, checking that every node lies inside the
 * grid, is aligned, and that no level has more nodes than the tree says (a
 * corrupt file could send every child to one node). */
typedef struct {
    const unsigned char *base;
    uint64_t size;
    uint32_t visited[3], counts[3];
    NanoRegionVisit *visit;
    void *context;
} Walk;

static const void *node_at(Walk *w, const void *from, int64_t offset, uint64_t node_size, int level)
{
    uint64_t at = (uint64_t)((const unsigned char *)from - w->base) + (uint64_t)offset;
    if (offset < 0 || at % CNANOVDB_DATA_ALIGNMENT != 0 || at > w->size || node_size > w->size - at ||
        (level >= 0 && ++w->visited[level] > w->counts[level]))
        return NULL;
    return w->base + at;
}

static void region(Walk *w, const int32_t origin[3], int32_t extent, float value)
{
    int32_t hi[3] = {origin[0] + extent - 1, origin[1] + extent - 1, origin[2] + extent - 1};
    w->visit(w->context, origin, hi, value);
}

/* Child n of a node of 2^log2dim children a side, each `child` voxels. */
static void child_origin(const int32_t origin[3], uint32_t n, int log2dim, int32_t child, int32_t out[3])
{
    uint32_t mask = (1u << log2dim) - 1u;
    out[0] = origin[0] + (int32_t)(n >> (2 * log2dim)) * child;
    out[1] = origin[1] + (int32_t)((n >> log2dim) & mask) * child;
    out[2] = origin[2] + (int32_t)(n & mask) * child;
}

static void walk_leaf(Walk *w, const cnanovdb_node0F *leaf, const int32_t origin[3])
{
    float largest = leaf->mVoxels[0];
    for (int i = 1; i < 512; ++i)
        largest = leaf->mVoxels[i] > largest ? leaf->mVoxels[i] : largest;
    region(w, origin, 8, largest);
}

static int walk_lower(Walk *w, const cnanovdb_node1F *node, const int32_t origin[3])
{
    for (uint32_t n = 0; n < 4096u; ++n) {
        int32_t at[3];
        child_origin(origin, n, 4, 8, at);
        if (!cnanovdb_mask4_isOn(&node->mChildMask, n)) {
            region(w, at, 8, node->mTable[n].value);
            continue;
        }
        const cnanovdb_node0F *leaf = node_at(w, node, (int64_t)node->mTable[n].child, sizeof *leaf, 0);
        if (!leaf)
            return -1;
        walk_leaf(w, leaf, at);
    }
    return 0;
}

static int walk_upper(Walk *w, const cnanovdb_node2F *node, const int32_t origin[3])
{
    for (uint32_t n = 0; n < 32768u; ++n) {
        int32_t at[3];
        child_origin(origin, n, 5, 128, at);
        if (!cnanovdb_mask5_isOn(&node->mChildMask, n)) {
            region(w, at, 128, node->mTable[n].value);
            continue;
        }
        const cnanovdb_node1F *lower = node_at(w, node, (int64_t)node->mTable[n].child, sizeof *lower, 1);
        if (!lower || walk_lower(w, lower, at))
            return -1;
    }
    return 0;
}

/* Returns 0, or -1 for a grid whose structure points outside it. */
static int walk_grid(Walk *w)
{
    const cnanovdb_griddata *grid = (const cnanovdb_griddata *)w->base;
    const cnanovdb_treedata *tree = cnanovdb_griddata_tree(grid);
    for (int k = 0; k < 3; ++k)
        w->counts[k] = tree->mNodeCount[k];
    const cnanovdb_rootdataF *root =
        node_at(w, tree, (int64_t)tree->mNodeOffset[ROOT_LEVEL], sizeof(cnanovdb_rootdataF), -1);
    if (!root || !node_at(w, root + 1, 0, (uint64_t)root->mTableSize * sizeof(cnanovdb_rootdata_tileF), -1))
        return -1;
    int32_t none[3] = {1, 1, 1}, nothing[3] = {0, 0, 0};
    w->visit(w->context, none, nothing, root->mBackground);
    for (uint32_t i = 0; i < root->mTableSize; ++i) {
        const cnanovdb_rootdata_tileF *tile = cnanovdb_rootdataF_getTile(root, i);
        /* The key packs the tile's origin: 21 bits an axis, of i, j, k >> 12. */
        int32_t origin[3] = {(int32_t)((uint32_t)((tile->key >> 42) & 0x1fffff) << 12),
                             (int32_t)((uint32_t)((tile->key >> 21) & 0x1fffff) << 12),
                             (int32_t)((uint32_t)(tile->key & 0x1fffff) << 12)};
        if (tile->child == 0) {
            region(w, origin, 4096, tile->value);
            continue;
        }
        const cnanovdb_node2F *upper = node_at(w, root, tile->child, sizeof *upper, 2);
        if (!upper || walk_upper(w, upper, origin))
            return -1;
    }
    return 0;
}

static void note_largest(void *context, const int32_t lo[3], const int32_t hi[3], float value)
{
    (void)lo;
    (void)hi;
    float *largest = context;
    *largest = value > *largest ? value : *largest;
}

void nanovdb_visit(const NanoGrid *grid, NanoRegionVisit *visit, void *context)
{
    Walk w = {.base = grid->data, .size = grid->size, .visit = visit, .context = context};
    (void)walk_grid(&w);
}

void nanovdb_map(const NanoGrid *grid, double matrix[9], double inverse[9], double translation[3])
{
    const cnanovdb_griddata *g = grid->data;
    memcpy(matrix, g->mMap.mMatD, 9 * sizeof *matrix);
    memcpy(inverse, g->mMap.mInvMatD, 9 * sizeof *inverse);
    memcpy(translation, g->mMap.mVecD, 3 * sizeof *translation);
}

/* Reads `stored` bytes at the file's position into the grid's `size` bytes
 * at `out`, undoing the codec. */
static int read_grid_bytes(FILE *f, int codec, uint64_t stored, unsigned char *out, uint64_t size, char *error,
                           size_t error_size)
{
    if (codec == CODEC_NONE)
        return stored == size && fread(out, 1, size, f) == size ? 0 : fail(error, error_size, "truncated grid data");
    uint64_t done = 0, used = 0;
    while (done < size) {
        unsigned char word[8];
        if (fread(word, 1, 8, f) != 8)
            return fail(error, error_size, "truncated grid data");
        uint64_t length = u64_at(word), chunk = codec == CODEC_ZIP ? size : size - done;
        chunk = codec == CODEC_BLOSC && chunk > BLOSC_CHUNK ? BLOSC_CHUNK : chunk;
        used += 8;
        if (length > stored - used || length > ((uint64_t)1 << 40))
            return fail(error, error_size, "a compressed block runs past the grid's data");
        unsigned char *packed = malloc(length ? length : 1);
        if (!packed)
            return fail(error, error_size, "out of memory");
        int ok = fread(packed, 1, length, f) == length;
        if (ok && codec == CODEC_ZIP) {
            uLongf unpacked = (uLongf)chunk;
            ok = uncompress(out, &unpacked, packed, (uLong)length) == Z_OK && unpacked == chunk;
        } else if (ok) {
            ok = blosc_decompress_ctx(packed, out + done, (size_t)chunk, 1) == (int)chunk;
        }
        free(packed);
        if (!ok)
            return fail(error, error_size, "the grid's %s data does not decompress",
                        codec == CODEC_ZIP ? "zlib" : "Blosc");
        done += chunk;
        used += length;
    }
    return 0;
}

/* The grid read: its own header agrees with the file's metadata, it is a
 * float fog volume, and its tree lies inside it. */
static int check_grid(NanoGrid *grid, const char *name, char *error, size_t error_size)
{
    const cnanovdb_griddata *g = grid->data;
    if (grid->size < sizeof(cnanovdb_griddata) + sizeof(cnanovdb_treedata) || g->mMagic != FILE_MAGIC ||
        g->mGridSize != grid->size)
        return fail(error, error_size, "grid \"%s\" is corrupt (its header)", name);
    if (g->mGridType != cnanovdb_GridType_Float)
        return fail(error, error_size, "grid \"%s\" is not of 32-bit floats (NanoVDB type %u)", name,
                    (unsigned)g->mGridType);
    if (g->mGridClass != CLASS_FOG_VOLUME && g->mGridClass != CLASS_UNKNOWN)
        return fail(error, error_size, "grid \"%s\" is not a fog volume (NanoVDB class %u)", name,
                    (unsigned)g->mGridClass);
    grid->largest = -INFINITY;
    Walk w = {.base = grid->data, .size = grid->size, .visit = note_largest, .context = &grid->largest};
    if (walk_grid(&w))
        return fail(error, error_size, "grid \"%s\" is corrupt (a node outside the grid)", name);
    for (int k = 0; k < 3; ++k) {
        grid->world_bounds[0][k] = g->mBBox[k];
        grid->world_bounds[1][k] = g->mBBox[3 + k];
        if (!(grid->world_bounds[1][k] >= grid->world_bounds[0][k]) || !isfinite(grid->world_bounds[0][k]) ||
            !isfinite(grid->world_bounds[1][k]))
            return fail(error, error_size, "grid \"%s\" has no active voxels (an empty bounding box)", name);
    }
    if (!isfinite(grid->largest))
        return fail(error, error_size, "grid \"%s\" holds a value that is not finite", name);
    return 0;
}

static int read_file(FILE *f, const char *name, NanoGrid *grid, char *error, size_t error_size)
{
    for (;;) {
        unsigned char header[HEADER_SIZE];
        size_t got = fread(header, 1, sizeof header, f);
        if (got == 0 && feof(f))
            return 1;
        if (got != sizeof header)
            return fail(error, error_size, "truncated segment header");
        if (u64_at(header) != FILE_MAGIC)
            return fail(error, error_size, "not a NanoVDB file (no magic number)");
        uint32_t version = u32_at(header + 8), major = version >> 21;
        unsigned count = header[12] | (unsigned)header[13] << 8, codec = header[14] | (unsigned)header[15] << 8;
        if (major != MAJOR_VERSION)
            return fail(error, error_size, "NanoVDB file format %u.%u, not %u.x (pbrt-v4's and this build's)", major,
                        (version >> 10) & 0x7ffu, MAJOR_VERSION);
        if (codec > CODEC_BLOSC)
            return fail(error, error_size, "unknown compression (codec %u)", codec);
        uint64_t skip = 0, wanted_offset = 0, wanted_stored = 0, wanted_size = 0;
        int found = 0;
        for (unsigned i = 0; i < count; ++i) {
            unsigned char meta[META_SIZE];
            if (fread(meta, 1, sizeof meta, f) != sizeof meta)
                return fail(error, error_size, "truncated grid metadata");
            uint32_t name_size = u32_at(meta + 136);
            char grid_name[256];
            if (name_size == 0 || name_size > sizeof grid_name || fread(grid_name, 1, name_size, f) != name_size ||
                grid_name[name_size - 1] != '\0')
                return fail(error, error_size, "corrupt grid name in the metadata");
            uint64_t size = u64_at(meta), stored = u64_at(meta + 8);
            if (!found && strcmp(grid_name, name) == 0) {
                found = 1;
                wanted_offset = skip;
                wanted_stored = stored;
                wanted_size = size;
            }
            if (stored > ((uint64_t)1 << 60) - skip)
                return fail(error, error_size, "corrupt grid size in the metadata");
            skip += stored;
        }
        if (!found) {
            if (fseeko(f, (off_t)skip, SEEK_CUR) != 0)
                return fail(error, error_size, "truncated file");
            continue;
        }
        if (wanted_size < sizeof(cnanovdb_griddata) || wanted_size > ((uint64_t)1 << 40))
            return fail(error, error_size, "grid \"%s\": corrupt size %llu", name, (unsigned long long)wanted_size);
        if (fseeko(f, (off_t)wanted_offset, SEEK_CUR) != 0)
            return fail(error, error_size, "truncated file");
        uint64_t padded =
            (wanted_size + CNANOVDB_DATA_ALIGNMENT - 1) / CNANOVDB_DATA_ALIGNMENT * CNANOVDB_DATA_ALIGNMENT;
        grid->data = aligned_alloc(CNANOVDB_DATA_ALIGNMENT, (size_t)padded);
        grid->size = wanted_size;
        if (!grid->data)
            return fail(error, error_size, "out of memory for grid \"%s\" (%llu bytes)", name,
                        (unsigned long long)wanted_size);
        if (read_grid_bytes(f, (int)codec, wanted_stored, grid->data, wanted_size, error, error_size) ||
            check_grid(grid, name, error, error_size)) {
            nanovdb_free(grid);
            return -1;
        }
        return 0;
    }
}

int nanovdb_read(const char *path, const char *name, NanoGrid *grid, char *error, size_t error_size)
{
    memset(grid, 0, sizeof *grid);
    FILE *f = fopen(path, "rb");
    if (!f)
        return fail(error, error_size, "cannot open: %s", strerror(errno));
    int result = read_file(f, name, grid, error, error_size);
    fclose(f);
    return result;
}

void nanovdb_free(NanoGrid *grid)
{
    free(grid->data);
    grid->data = NULL;
    grid->size = 0;
}
