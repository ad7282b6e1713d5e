#include "scene/ply.h"

#include "scene/read_file.h"
#include "scene/scene_internal.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPERTIES 32
#define PLY_MAX_NAME 64

typedef enum { PLY_INT8, PLY_UINT8, PLY_INT16, PLY_UINT16, PLY_INT32, PLY_UINT32, PLY_FLOAT32, PLY_FLOAT64 } PlyType;

static const struct {
    const char *name;
    PlyType type;
} ply_types[] = {
    {"char", PLY_INT8},     {"int8", PLY_INT8},       {"uchar", PLY_UINT8},    {"uint8", PLY_UINT8},
    {"short", PLY_INT16},   {"int16", PLY_INT16},     {"ushort", PLY_UINT16},  {"uint16", PLY_UINT16},
    {"int", PLY_INT32},     {"int32", PLY_INT32},     {"uint", PLY_UINT32},    {"uint32", PLY_UINT32},
    {"float", PLY_FLOAT32}, {"float32", PLY_FLOAT32}, {"double", PLY_FLOAT64}, {"float64", PLY_FLOAT64},
};

static size_t type_size(PlyType type)
{
    static const size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[type];
}

static int type_is_integer(PlyType type)
{
    return type != PLY_FLOAT32 && type != PLY_FLOAT64;
}

typedef struct {
    char name[PLY_MAX_NAME];
    PlyType type;
    int is_list;
    PlyType count_type; /* lists only */
} PlyProperty;

typedef struct {
    char name[PLY_MAX_NAME];
    size_t count;
    PlyProperty properties[PLY_MAX_PROPERTIES];
    int property_count;
} PlyElement;

typedef enum { PLY_ASCII, PLY_LITTLE_ENDIAN, PLY_BIG_ENDIAN } PlyFormat;

typedef struct {
    const char *data;
    size_t size, pos;
    PlyFormat format;
    int swap; /* binary byte order differs from the host's */
    char *error;
    size_t error_size;
} PlyReader;

static int fail(PlyReader *r, const char *format, ...) SCENE_PRINTF(2, 3);

static int fail(PlyReader *r, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    if (r->error && r->error_size > 0)
        vsnprintf(r->error, r->error_size, format, args);
    va_end(args);
    return -1;
}

static int host_is_little_endian(void)
{
    uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 1;
}

/* ---- header ---- */

/* Splits a header line into at most `max` words (in place). */
static int split_words(char *line, char **words, int max)
{
    int n = 0;
    char *s = line;
    while (*s) {
        while (*s == ' ' || *s == '\t')
            *s++ = '\0';
        if (!*s)
            break;
        if (n == max)
            return max + 1;
        words[n++] = s;
        while (*s && *s != ' ' && *s != '\t')
            s++;
    }
    return n;
}

static int parse_type(const char *name, PlyType *type)
{
    for (size_t i = 0; i < sizeof ply_types / sizeof ply_types[0]; ++i)
        if (strcmp(name, ply_types[i].name) == 0) {
            *type = ply_types[i].type;
            return 0;
        }
    return -1;
}

static int copy_name(char *out, const char *name)
{
    size_t n = strlen(name);
    if (n >= PLY_MAX_NAME)
        return -1;
    memcpy(out, name, n + 1);
    return 0;
}

static int starts_with_word(const char *line, size_t length, const char *word)
{
    size_t n = strlen(word);
    return length >= n && memcmp(line, word, n) == 0 && (length == n || line[n] == ' ' || line[n] == '\t');
}

/* Reads the header up to end_header; r->pos is left at the first data byte. */
static int parse_header(PlyReader *r, PlyElement *elements, int *element_count)
{
    int have_format = 0;
    *element_count = 0;
    for (int line_number = 1;; ++line_number) {
        if (r->pos >= r->size)
            return fail(r, "header ends without end_header (truncated?)");
        const char *start = r->data + r->pos;
        const char *newline = memchr(start, '\n', r->size - r->pos);
        size_t length = newline ? (size_t)(newline - start) : r->size - r->pos;
        r->pos += length + (newline ? 1 : 0);
        if (length > 0 && start[length - 1] == '\r')
            length--;
        char line[256];
        if (starts_with_word(start, length, "comment") || starts_with_word(start, length, "obj_info"))
            continue; /* may be long, and hold anything */
        if (length >= sizeof line)
            return fail(r, "header line %d is too long", line_number);
        memcpy(line, start, length);
        line[length] = '\0';
        if (memchr(line, '\0', length))
            return fail(r, "header line %d holds a NUL byte", line_number);
        char *w[6];
        int n = split_words(line, w, 5);
        if (line_number == 1) {
            if (n != 1 || strcmp(w[0], "ply") != 0)
                return fail(r, "not a PLY file (the first line is not \"ply\")");
            continue;
        }
        if (n == 0)
            continue;
        if (strcmp(w[0], "format") == 0) {
            if (n != 3 || strcmp(w[2], "1.0") != 0)
                return fail(r, "header line %d: expected \"format <kind> 1.0\"", line_number);
            if (strcmp(w[1], "ascii") == 0)
                r->format = PLY_ASCII;
            else if (strcmp(w[1], "binary_little_endian") == 0)
                r->format = PLY_LITTLE_ENDIAN;
            else if (strcmp(w[1], "binary_big_endian") == 0)
                r->format = PLY_BIG_ENDIAN;
            else
                return fail(r, "header line %d: unknown format \"%s\"", line_number, w[1]);
            have_format = 1;
        } else if (strcmp(w[0], "element") == 0) {
            if (n != 3)
                return fail(r, "header line %d: expected \"element <name> <count>\"", line_number);
            if (*element_count == PLY_MAX_ELEMENTS)
                return fail(r, "header line %d: more than %d elements", line_number, PLY_MAX_ELEMENTS);
            PlyElement *e = &elements[(*element_count)++];
            memset(e, 0, sizeof *e);
            char *end = NULL;
            errno = 0;
            unsigned long long count = strtoull(w[2], &end, 10);
            if (copy_name(e->name, w[1]) || *end || w[2][0] == '-' || errno || count > SIZE_MAX)
                return fail(r, "header line %d: bad element \"%s %s\"", line_number, w[1], w[2]);
            e->count = (size_t)count;
        } else if (strcmp(w[0], "property") == 0) {
            if (*element_count == 0)
                return fail(r, "header line %d: property before any element", line_number);
            PlyElement *e = &elements[*element_count - 1];
            if (e->property_count == PLY_MAX_PROPERTIES)
                return fail(r, "header line %d: more than %d properties", line_number, PLY_MAX_PROPERTIES);
            PlyProperty *p = &e->properties[e->property_count++];
            memset(p, 0, sizeof *p);
            int bad;
            if (n >= 2 && strcmp(w[1], "list") == 0) {
                p->is_list = 1;
                bad = n != 5 || parse_type(w[2], &p->count_type) || !type_is_integer(p->count_type) ||
                      parse_type(w[3], &p->type) || copy_name(p->name, w[4]);
            } else {
                bad = n != 3 || parse_type(w[1], &p->type) || copy_name(p->name, w[2]);
            }
            if (bad)
                return fail(r,
                            "header line %d: malformed property (expected \"property <type> <name>\" or "
                            "\"property list <integer type> <type> <name>\")",
                            line_number);
        } else if (strcmp(w[0], "end_header") == 0 && n == 1) {
            if (!have_format)
                return fail(r, "header has no format line");
            return 0;
        } else {
            return fail(r, "header line %d: unknown keyword \"%s\"", line_number, w[0]);
        }
    }
}

/* ---- data ---- */

/* Reads one value. Returns 0, -1 at the end of the data, -2 for a malformed
 * ASCII number (or a non-integer where an integer type is declared). */
static int read_value(PlyReader *r, PlyType type, double *value)
{
    if (r->format == PLY_ASCII) {
        while (r->pos < r->size && strchr(" \t\r\n", r->data[r->pos]) && r->data[r->pos])
            r->pos++;
        if (r->pos >= r->size)
            return -1;
        const char *start = r->data + r->pos;
        char *end = NULL;
        double v = strtod(start, &end);
        if (end == start || (*end && !strchr(" \t\r\n", *end)))
            return -2;
        r->pos += (size_t)(end - start);
        if (type_is_integer(type) && v != floor(v))
            return -2;
        *value = v;
        return 0;
    }
    size_t n = type_size(type);
    if (r->size - r->pos < n)
        return -1;
    unsigned char b[8];
    memcpy(b, r->data + r->pos, n);
    r->pos += n;
    if (r->swap)
        for (size_t i = 0; i < n / 2; ++i) {
            unsigned char t = b[i];
            b[i] = b[n - 1 - i];
            b[n - 1 - i] = t;
        }
    switch (type) {
    case PLY_INT8: {
        int8_t v;
        memcpy(&v, b, 1);
        *value = v;
        break;
    }
    case PLY_UINT8:
        *value = b[0];
        break;
    case PLY_INT16: {
        int16_t v;
        memcpy(&v, b, 2);
        *value = v;
        break;
    }
    case PLY_UINT16: {
        uint16_t v;
        memcpy(&v, b, 2);
        *value = v;
        break;
    }
    case PLY_INT32: {
        int32_t v;
        memcpy(&v, b, 4);
        *value = v;
        break;
    }
    case PLY_UINT32: {
        uint32_t v;
        memcpy(&v, b, 4);
        *value = v;
        break;
    }
    case PLY_FLOAT32: {
        float v;
        memcpy(&v, b, 4);
        *value = v;
        break;
    }
    case PLY_FLOAT64:
        memcpy(value, b, 8);
        break;
    }
    return 0;
}

static int data_error(PlyReader *r, int code, const PlyElement *e, size_t item)
{
    if (code == -1)
        return fail(r, "unexpected end of file in element \"%s\" (item %zu of %zu)", e->name, item, e->count);
    return fail(r, "malformed number in element \"%s\" (item %zu)", e->name, item);
}

/* Reads a list's length: a non-negative integer. */
static int read_list_count(PlyReader *r, const PlyElement *e, const PlyProperty *p, size_t item, size_t *count)
{
    double v;
    int code = read_value(r, p->count_type, &v);
    if (code)
        return data_error(r, code, e, item);
    if (v < 0 || v > 1e6)
        return fail(r, "element \"%s\" item %zu: bad list length %g", e->name, item, v);
    *count = (size_t)v;
    return 0;
}

static int skip_property(PlyReader *r, const PlyElement *e, const PlyProperty *p, size_t item)
{
    size_t count = 1;
    if (p->is_list && read_list_count(r, e, p, item, &count))
        return -1;
    for (size_t k = 0; k < count; ++k) {
        double v;
        int code = read_value(r, p->type, &v);
        if (code)
            return data_error(r, code, e, item);
    }
    return 0;
}

static float to_float(double v)
{
    if (v > FLT_MAX)
        return INFINITY;
    if (v < -FLT_MAX)
        return -INFINITY;
    return (float)v; /* NaN stays NaN */
}

static int find_property(const PlyElement *e, const char *name)
{
    for (int i = 0; i < e->property_count; ++i)
        if (strcmp(e->properties[i].name, name) == 0)
            return i;
    return -1;
}

/* Texture coordinate names in use, tried in pbrt-v4's order. */
static const char *const uv_names[][2] = {
    {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};

static int read_vertices(PlyReader *r, const PlyElement *e, PlyMesh *mesh)
{
    static const char *names[8] = {"x", "y", "z", "nx", "ny", "nz", "u", "v"};
    int slot[PLY_MAX_PROPERTIES]; /* which of names[] each property fills, or -1 */
    int found[8];
    for (int k = 0; k < 6; ++k)
        found[k] = find_property(e, names[k]);
    found[6] = found[7] = -1;
    for (size_t i = 0; found[6] < 0 && i < sizeof uv_names / sizeof uv_names[0]; ++i) {
        int u = find_property(e, uv_names[i][0]), v = find_property(e, uv_names[i][1]);
        if (u >= 0 && v >= 0) {
            found[6] = u;
            found[7] = v;
            names[6] = uv_names[i][0];
            names[7] = uv_names[i][1];
        }
    }
    for (int k = 0; k < 8; ++k)
        if (found[k] >= 0 && e->properties[found[k]].is_list)
            return fail(r, "vertex property \"%s\" is a list", names[k]);
    if (found[0] < 0 || found[1] < 0 || found[2] < 0)
        return fail(r, "the vertex element lacks x, y or z");
    int has_normals = found[3] >= 0 && found[4] >= 0 && found[5] >= 0, has_uvs = found[6] >= 0;
    for (int i = 0; i < e->property_count; ++i)
        slot[i] = -1;
    for (int k = 0; k < 8; ++k)
        if ((k < 3 || (k < 6 && has_normals) || (k >= 6 && has_uvs)))
            slot[found[k]] = k;
    mesh->vertex_count = e->count;
    size_t allocated = e->count ? e->count : 1;
    mesh->positions = malloc(allocated * 3 * sizeof *mesh->positions);
    mesh->normals = has_normals ? malloc(allocated * 3 * sizeof *mesh->normals) : NULL;
    mesh->uvs = has_uvs ? malloc(allocated * 2 * sizeof *mesh->uvs) : NULL;
    if (!mesh->positions || (has_normals && !mesh->normals) || (has_uvs && !mesh->uvs))
        return fail(r, "out of memory for %zu vertices", e->count);
    for (size_t item = 0; item < e->count; ++item) {
        for (int i = 0; i < e->property_count; ++i) {
            const PlyProperty *p = &e->properties[i];
            if (slot[i] < 0) {
                if (skip_property(r, e, p, item))
                    return -1;
                continue;
            }
            double v;
            int code = read_value(r, p->type, &v);
            if (code)
                return data_error(r, code, e, item);
            if (slot[i] < 3)
                mesh->positions[3 * item + (size_t)slot[i]] = to_float(v);
            else if (slot[i] < 6)
                mesh->normals[3 * item + (size_t)slot[i] - 3] = to_float(v);
            else
                mesh->uvs[2 * item + (size_t)slot[i] - 6] = to_float(v);
        }
        const float *position = mesh->positions + 3 * item;
        if (!isfinite(position[0]) || !isfinite(position[1]) || !isfinite(position[2]))
            return fail(r, "vertex %zu has a non-finite position (%g, %g, %g)", item, (double)position[0],
                        (double)position[1], (double)position[2]);
    }
    return 0;
}

/* vertex_count: the vertex element's, as its header line declares. */
static int read_faces(PlyReader *r, const PlyElement *e, size_t vertex_count, PlyMesh *mesh)
{
    int list = find_property(e, "vertex_indices");
    if (list < 0)
        list = find_property(e, "vertex_index");
    if (list < 0 || !e->properties[list].is_list || !type_is_integer(e->properties[list].type))
        return fail(r, "the face element lacks an integer list \"vertex_indices\"");
    mesh->indices = malloc((e->count ? e->count : 1) * 6 * sizeof *mesh->indices);
    mesh->parts = malloc((e->count ? e->count : 1) * 2 * sizeof *mesh->parts); /* a face is one shape */
    if (!mesh->indices || !mesh->parts)
        return fail(r, "out of memory for %zu faces", e->count);
    for (size_t item = 0; item < e->count; ++item) {
        for (int i = 0; i < e->property_count; ++i) {
            const PlyProperty *p = &e->properties[i];
            if (i != list) {
                if (skip_property(r, e, p, item))
                    return -1;
                continue;
            }
            size_t count = 0; /* set by read_list_count; gcc -O2 cannot tell */
            if (read_list_count(r, e, p, item, &count))
                return -1;
            if (count != 3 && count != 4)
                return fail(r, "face %zu has %zu vertices; only triangles and quads are supported", item, count);
            uint32_t v[4];
            for (size_t k = 0; k < count; ++k) {
                double x;
                int code = read_value(r, p->type, &x);
                if (code)
                    return data_error(r, code, e, item);
                if (x < 0 || x >= (double)vertex_count || x > 4294967295.0)
                    return fail(r, "face %zu: vertex index %.0f is out of range (%zu vertices)", item, x, vertex_count);
                v[k] = (uint32_t)x;
            }
            uint32_t *out = mesh->indices + mesh->index_count;
            out[0] = v[0], out[1] = v[1], out[2] = v[2];
            mesh->parts[mesh->index_count / 3] = (uint32_t)item;
            mesh->index_count += 3;
            if (count == 4) { /* split the quad along its 0-2 diagonal */
                out[3] = v[0], out[4] = v[2], out[5] = v[3];
                mesh->parts[mesh->index_count / 3] = (uint32_t)item;
                mesh->index_count += 3;
            }
        }
    }
    return 0;
}

int ply_read(const char *path, PlyMesh *mesh, char *error, size_t error_size)
{
    memset(mesh, 0, sizeof *mesh);
    char *data = NULL, why[128];
    size_t size = 0;
    if (scene_read_file(path, SCENE_MAX_PLY_BYTES, &data, &size, why, sizeof why)) {
        snprintf(error, error_size, "cannot read: %s", why);
        return -1;
    }
    PlyReader r = {.data = data, .size = size, .error = error, .error_size = error_size};
    PlyElement elements[PLY_MAX_ELEMENTS];
    int element_count = 0;
    int result = parse_header(&r, elements, &element_count);
    if (result == 0)
        r.swap = r.format != PLY_ASCII && (r.format == PLY_LITTLE_ENDIAN) != host_is_little_endian();
    int vertex_element = -1, face_element = -1;
    for (int i = 0; result == 0 && i < element_count; ++i) {
        const PlyElement *e = &elements[i];
        int *which = strcmp(e->name, "vertex") == 0 ? &vertex_element
                     : strcmp(e->name, "face") == 0 ? &face_element
                                                    : NULL;
        if (which && *which >= 0)
            result = fail(&r, "more than one \"%s\" element", e->name);
        else if (which)
            *which = i;
    }
    if (result == 0 && vertex_element < 0)
        result = fail(&r, "no vertex element");
    if (result == 0 && face_element < 0)
        result = fail(&r, "no face element");
    for (int i = 0; result == 0 && i < element_count; ++i) {
        const PlyElement *e = &elements[i];
        /* Every value takes at least one byte: a cheap bound before allocating. */
        size_t per_item = e->property_count > 0 ? (size_t)e->property_count : 1;
        if (e->count > (r.size - r.pos) / per_item) {
            result = fail(&r, "element \"%s\" declares %zu items, more than the file holds", e->name, e->count);
            break;
        }
        if (i == vertex_element) {
            result = read_vertices(&r, e, mesh);
        } else if (i == face_element) {
            result = read_faces(&r, e, elements[vertex_element].count, mesh);
        } else {
            for (size_t item = 0; result == 0 && item < e->count; ++item)
                for (int k = 0; result == 0 && k < e->property_count; ++k)
                    result = skip_property(&r, e, &e->properties[k], item);
        }
    }
    free(data);
    if (result)
        shape_mesh_free(mesh);
    return result;
}
