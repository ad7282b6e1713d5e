#define _POSIX_C_SOURCE 200809L
#include "cli/options.h"

#include "passes.h" /* kernels/: the estimators and their parameters */
#include "render/render_scene.h"
#include "scene/scene.h" /* SCENE_BDPT, SCENE_LIGHTPATH */

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    FOR_RENDER = 1 << COMMAND_RENDER,
    FOR_ESTIMATE = 1 << COMMAND_ESTIMATE,
    FOR_MERGE = 1 << COMMAND_MERGE,
    FOR_CHECK = 1 << COMMAND_CHECK,
    FOR_ALL = FOR_RENDER | FOR_ESTIMATE | FOR_MERGE, /* every command that renders or estimates */
};

/* Every flag: the subcommands that take it and its --help lines. A flag
 * with `value` takes one (--flag VALUE or --flag=VALUE). A flag may appear
 * once per subcommand with its own help; an entry without a name starts a
 * section of the help. */
typedef struct {
    const char *name;
    const char *value;
    int commands;
    const char *help;
} Flag;

static const Flag flags[] = {
    {NULL, NULL, FOR_RENDER, "Sampling"},
    {"--spp", "N", FOR_RENDER, "samples per pixel (default: the scene's Sampler\n\"pixelsamples\", else 64)"},
    {"--sampler", "NAME", FOR_RENDER,
     "sobol-sets: each of the M sets its own Owen-scrambled\nSobol sequence (sets independent, as MoN assumes);\n"
     "sobol-pixel: one sequence over all of a pixel's samples\n(the best mean, but the sets' means are correlated);\n"
     "independent: uniform random numbers. Default: the\nscene's Sampler \"independent\" or else sobol-sets\n"
     "(docs/sampling.md)"},
    {"--light-sampler", "NAME", FOR_RENDER,
     "how next-event estimation picks a light: bvh (the light\ntree: by power, distance and facing at each point),\n"
     "power or uniform. Default: the scene's Integrator\n\"lightsampler\", else bvh, as pbrt-v4"},
    {"--seed", "N", FOR_RENDER,
     "random seed (default 0); the image depends only on the\nseed and the sample range, never on passes or devices"},
    {"--first-sample", "N", FOR_RENDER, "first sample index of the range rendered (default 0)"},
    {"--time", "SECONDS", FOR_RENDER, "stop after the pass that reaches this render time"},
    {"--integrator", "MODE", FOR_RENDER,
     "nee: the path tracer, next-event estimation with MIS\n(default, unless the scene asks for bdpt or "
     "lightpath);\nbsdf: "
     "the path tracer, BSDF sampling only (the\nfirefly-prone case); bdpt: bidirectional path tracing;\nlightpath: the "
     "light tracer (docs/design.md)"},
    {"--maxdepth", "N", FOR_RENDER, "override the scene's Integrator \"maxdepth\""},
    {"--resolution", "WxH", FOR_RENDER, "override the scene's Film resolution (each 1..65536)"},
    {NULL, NULL, FOR_ALL, "Estimators"},
    {"--sets", "M", FOR_RENDER, "number of sets for MoN and G-MoN, 1..64 (default 21)"},
    {"--estimators", "LIST", FOR_ALL,
     "comma-separated estimators, or all (default mean,mon,gmon; `estimate`: the file's):"},
    {"--estimator-param", "NAME=VALUE", FOR_ALL, "set an estimator parameter (repeatable):"},
    {"--stderr", NULL, FOR_ALL,
     "add a <name>.stderr layer per estimator: its per-pixel\nstandard error (the mean's from the set means, the\n"
     "others by the jackknife over sets)"},
    {"--gini-mode", "MODE", FOR_ALL,
     "channel: G and trim per channel (default);\npixel: one G per pixel, the mean of the channels' G;\n"
     "luminance: sort and trim whole sets by luminance"},
    {"--diagnostics", NULL, FOR_ALL, "add layers: Gini G, trim count c, non-finite and\nrounded samples"},
    {"--write-sets", NULL, FOR_RENDER,
     "add the exact per-set sums, for `estimate` and merging\n(without it, --estimators mean accumulates one sum\n"
     "per pixel instead of M)"},
    {"--write-sets", NULL, FOR_ESTIMATE, "keep the per-set sums in the output (`merge` always does)"},
    {NULL, NULL, FOR_ALL, "Output"},
    {"--outfile", "PATH", FOR_RENDER,
     "EXR file (default: the scene's Film \"filename\" with an\n.exr extension, else render.exr); the PNG preview "
     "goes\n"
     "beside it with a .png extension. Files are written under\na temporary name and renamed when complete; the paths\n"
     "written are always printed, and the output directory\nis checked before the render starts"},
    {"--outfile", "PATH", FOR_ESTIMATE, "EXR file (default estimate.exr); the PNG preview goes\nbeside it"},
    {"--outfile", "PATH", FOR_MERGE, "EXR file (default merged.exr); the PNG preview goes\nbeside it"},
    {"--preview", "NAME", FOR_ALL,
     "estimator shown in the PNG, one of --estimators (default\ngmon if requested, else the first requested)"},
    {"--exposure", "X", FOR_ALL, "PNG exposure multiplier (default 1)"},
    {"--quiet", NULL, FOR_ALL, "no progress bar and no summary line"},
    {"--checkpoints", "DIR", FOR_RENDER,
     "at 1, 2, 4, ... samples per pixel and at the end, write\nDIR/spp-NNNNNN.exr (attribute `seconds`: render time "
     "so\n"
     "far) and a row per estimator to DIR/checkpoints.csv\n(spp,seconds,estimator,rmse,relmse), from one render. A\n"
     "failed checkpoint is an error; the render goes on\nand exits 1 after writing --outfile"},
    {"--reference", "EXR", FOR_RENDER,
     "with --checkpoints: fill rmse and relmse against this\nimage's mean layer (relmse: mean of (x-r)^2/(r^2+0.01))"},
    {NULL, NULL, FOR_RENDER, "Devices"},
    {"--list-devices", NULL, FOR_RENDER, "list OpenCL devices and exit"},
    {"--device", "SPEC", FOR_RENDER,
     "all, cpu, gpu, or comma-separated indices from\n--list-devices (default all): the devices render at\n"
     "once, each a share of the pixels proportional to its\nspeed; the image is the same whatever the devices"},
    {NULL, NULL, FOR_RENDER, "Scene input"},
    {"--allow-unsupported", NULL, FOR_RENDER,
     "turn errors on unsupported scene features into warnings,\neach with a documented substitute"},
    {NULL, NULL, FOR_RENDER, "Developer"},
    {"--kernel-dir", "DIR", FOR_RENDER,
     "load OpenCL sources from DIR instead of the embedded copies\n(also: environment variable GMON_KERNEL_DIR)"},
    {"--dump-kernel", "FILE", FOR_RENDER,
     "write the path tracer source as specialized for this\nscene and these outputs, with its defines, to FILE"},
    {"--all-features", NULL, FOR_RENDER,
     "build the kernels with every feature instead of only\nwhat the scene and outputs use (for comparisons)"},
    {"--help", NULL, FOR_RENDER,
     "this text (`gmonrt estimate --help`, `gmonrt merge --help`:\nthose subcommands' flags)"},
    {NULL, NULL, FOR_ESTIMATE | FOR_MERGE | FOR_CHECK, "Help"},
    {"--help", NULL, FOR_ESTIMATE | FOR_MERGE | FOR_CHECK, "this text"},
    {"-h", NULL, FOR_ALL | FOR_CHECK, NULL},
};

static const char render_intro[] = "usage: gmonrt [options] [scene.pbrt]\n"
                                   "       gmonrt estimate [options] render.exr\n"
                                   "       gmonrt merge [options] part1.exr part2.exr ...\n"
                                   "       gmonrt check scene.pbrt\n"
                                   "       gmonrt --list-devices\n"
                                   "\n"
                                   "Renders a pbrt-v4 scene with an OpenCL path tracer and writes the mean, MoN and\n"
                                   "G-MoN estimates of the same samples to one EXR, plus a PNG preview. With no\n"
                                   "scene, renders the default scene (a Cornell box with a glass sphere and a small,\n"
                                   "very bright light). `estimate` recomputes the estimators from an EXR written\n"
                                   "with --write-sets (for example with another Gini mode). `merge` combines\n"
                                   "EXRs written with --write-sets from disjoint sample ranges (--first-sample,\n"
                                   "--spp) of one scene, seed and M into the render of their union: exactly\n"
                                   "the set sums, and so the estimates, of one render over all the samples.\n"
                                   "`check` lists what a scene needs that gmonrt lacks or that is missing\n"
                                   "(exit 0: nothing; 3: only missing files; 1: an unsupported feature).\n";
static const char render_exit[] = "Exit status: 0 success; 1 render or I/O failure; 2 bad command line. Ctrl-C\n"
                                  "(SIGINT), SIGTERM and SIGHUP (sent by `timeout`, Slurm's time limit, a closed\n"
                                  "terminal) stop the render after its pass and write the image of the samples\n"
                                  "done, then exit 128 + the signal: 130, 143, 129. Before any sample is done, or\n"
                                  "at a second signal, gmonrt exits at once with that status and leaves existing\n"
                                  "files as they were.\n";
static const char estimate_intro[] = "usage: gmonrt estimate [options] render.exr\n"
                                     "\n"
                                     "Recomputes the estimators from the per-set sums of an EXR written with\n"
                                     "--write-sets (M, the sample range and the sample count come from the file).\n";
static const char merge_intro[] = "usage: gmonrt merge [options] part1.exr part2.exr ...\n"
                                  "\n"
                                  "Combines EXRs written with --write-sets from disjoint sample ranges of one\n"
                                  "scene, seed and M into the render of their union (the sums stay in the file,\n"
                                  "so it can be merged again).\n";
static const char check_intro[] = "usage: gmonrt check scene.pbrt\n"
                                  "\n"
                                  "Reads and converts a pbrt-v4 scene without rendering it (no OpenCL device is\n"
                                  "needed) and lists, one per line as file:line, every unsupported feature with\n"
                                  "the substitute --allow-unsupported would use, then every file the scene names\n"
                                  "that is missing (Include/Import, PLY meshes, textures: a scene's text can be\n"
                                  "checked before its geometry is downloaded), then a summary line:\n"
                                  "\"N unsupported features, M missing files\". The scene's warnings and notes\n"
                                  "are printed too.\n";
static const char check_exit[] = "Exit status: 0 everything is supported and present; 1 an unsupported feature\n"
                                 "(whether or not files are missing too), or a scene that cannot be read;\n"
                                 "2 bad command line; 3 only files are missing.\n";
static const char subcommand_exit[] = "Exit status: 0 success, 1 unusable input or I/O failure, 2 bad command line,\n"
                                      "128 + the signal when interrupted (existing files are left as they were).\n";

/* Appends `text` to the help being reflowed in `out` (a line at most
 * `width` long, broken at spaces). */
static void append_words(char *out, size_t size, const char *text, int width)
{
    size_t used = strlen(out);
    const char *line_start = strrchr(out, '\n');
    int column = (int)(used - (line_start ? (size_t)(line_start + 1 - out) : 0));
    while (*text && used + 1 < size) {
        size_t word = strcspn(text, " ");
        if (word == 0) {
            ++text;
            continue;
        }
        int space = column > 0;
        if (column + space + (int)word > width && column > 0) {
            used += (size_t)snprintf(out + used, size - used, "\n");
            column = 0;
            space = 0;
        }
        used += (size_t)snprintf(out + used, size - used, "%s%.*s", space ? " " : "", (int)word, text);
        column += space + (int)word;
        text += word;
    }
}

#define PARAMETER_NAME_(type, field, name, value, lowest, highest) name ", "

/* The help of --estimators and --estimator-param: their text, then the
 * names from kernels/film/passes.h's tables, so that no list is kept here. */
static const char *flag_help(const Flag *f, char *out, size_t size)
{
    const int estimators = strcmp(f->name, "--estimators") == 0;
    if (!estimators && strcmp(f->name, "--estimator-param") != 0)
        return f->help;
    const int width = 56; /* the help column of an 80-column terminal */
    out[0] = '\0';
    append_words(out, size, f->help, width);
    if (estimators) {
        for (int p = 0; p < PASS_COUNT; ++p)
            if (PASSES_ESTIMATES & PASS_BIT(p)) {
                char name[40];
                snprintf(name, sizeof name, "%s%s", pass_name(p), (PASSES_ESTIMATES >> (p + 1)) ? "," : ";");
                append_words(out, size, name, width);
            }
        append_words(out, size, "per sample, renders only (not in all):", width);
        for (int p = 0; p < PASS_COUNT; ++p)
            if (PASSES_SAMPLE & PASS_BIT(p)) {
                char name[40];
                snprintf(name, sizeof name, "%s%s", pass_name(p), (PASSES_SAMPLE >> (p + 1)) ? "," : "");
                append_words(out, size, name, width);
            }
        append_words(out, size, "(clamp: a layer clamp-<V> per level; docs/estimators.md)", width);
    } else {
        append_words(out, size, GMON_ESTIMATOR_PARAMS(PARAMETER_NAME_) "clamp.levels (V:V:...);", width);
        append_words(out, size, "defaults in docs/estimators.md; written to the EXR metadata", width);
    }
    return out;
}

const char *options_help(Command command)
{
    static char text[8192];
    const int bit = 1 << (command == COMMAND_LIST_DEVICES ? COMMAND_RENDER : command);
    size_t used = (size_t)snprintf(text, sizeof text, "%s",
                                   bit == FOR_ESTIMATE ? estimate_intro
                                   : bit == FOR_MERGE  ? merge_intro
                                   : bit == FOR_CHECK  ? check_intro
                                                       : render_intro);
    for (size_t i = 0; i < sizeof flags / sizeof flags[0] && used < sizeof text; ++i) {
        const Flag *f = &flags[i];
        if (!(f->commands & bit) || !f->help)
            continue;
        if (!f->name) {
            used += (size_t)snprintf(text + used, sizeof text - used, "\n%s\n", f->help);
            continue;
        }
        char head[64], listed[1024];
        snprintf(head, sizeof head, "%s%s%s", f->name, f->value ? " " : "", f->value ? f->value : "");
        used += (size_t)snprintf(text + used, sizeof text - used, "  %-20s ", head);
        const char *help = flag_help(f, listed, sizeof listed);
        /* Continuation lines line up under the first. */
        for (const char *line = help; *line && used < sizeof text;) {
            size_t length = strcspn(line, "\n");
            used += (size_t)snprintf(text + used, sizeof text - used, "%*s%.*s\n", line == help ? 0 : 23, "",
                                     (int)length, line);
            line += length + (line[length] == '\n');
        }
    }
    if (used < sizeof text)
        snprintf(text + used, sizeof text - used, "\n%s",
                 bit == FOR_RENDER ? render_exit : (bit == FOR_CHECK ? check_exit : subcommand_exit));
    return text;
}

__attribute__((format(printf, 3, 4))) static int fail(char *error, size_t size, const char *format, ...)
{
    va_list arguments;
    va_start(arguments, format);
    vsnprintf(error, size, format, arguments);
    va_end(arguments);
    return 2;
}

static int parse_u64(const char *text, uint64_t max, uint64_t *out)
{
    if (!text || !isdigit((unsigned char)*text))
        return -1;
    char *end = NULL;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || *end || v > max)
        return -1;
    *out = v;
    return 0;
}

static int parse_double(const char *text, double *out)
{
    if (!text || !*text)
        return -1;
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || *end || !(v >= 0.0) || v > 1e12)
        return -1;
    *out = v;
    return 0;
}

/* WIDTHxHEIGHT, each 1..65536 (checked as 64-bit numbers: no wrap-around). */
static int parse_resolution(const char *text, unsigned *width, unsigned *height)
{
    const char *x = strchr(text, 'x');
    char first[24];
    if (!x || (size_t)(x - text) >= sizeof first)
        return -1;
    memcpy(first, text, (size_t)(x - text));
    first[x - text] = '\0';
    uint64_t w = 0, h = 0;
    if (parse_u64(first, 65536, &w) || parse_u64(x + 1, 65536, &h) || w == 0 || h == 0)
        return -1;
    *width = (unsigned)w;
    *height = (unsigned)h;
    return 0;
}

/* all, cpu, gpu or distinct comma-separated indices. */
static int parse_devices(const char *text, DeviceSelection *d, char *error, size_t size)
{
    memset(d, 0, sizeof *d);
    d->spec = text;
    if (strcmp(text, "all") == 0 || strcmp(text, "cpu") == 0 || strcmp(text, "gpu") == 0) {
        d->kind = text[0] == 'a' ? DEVICES_ALL : (text[0] == 'c' ? DEVICES_CPU : DEVICES_GPU);
        return 0;
    }
    d->kind = DEVICES_INDICES;
    for (const char *p = text;;) {
        char *end = NULL;
        errno = 0;
        unsigned long index = isdigit((unsigned char)*p) ? strtoul(p, &end, 10) : 0;
        if (!end || errno || index > 1000000 || (*end != ',' && *end != '\0'))
            return fail(error, size, "--device %s: expected all, cpu, gpu or indices like 0,2", text);
        for (int k = 0; k < d->index_count; ++k)
            if (d->indices[k] == (int)index)
                return fail(error, size, "--device %s: device %lu is named twice", text, index);
        if (d->index_count == OPTIONS_MAX_DEVICES)
            return fail(error, size, "--device %s: more than %d devices", text, OPTIONS_MAX_DEVICES);
        d->indices[d->index_count++] = (int)index;
        if (*end == '\0')
            return 0;
        p = end + 1;
    }
}

/* Whether PATH, once its extension is replaced, names a file: "", "dir/"
 * and ".exr" would write a hidden "./.exr". */
static int names_a_file(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    const char *dot = strrchr(name, '.');
    return (dot ? (size_t)(dot - name) : strlen(name)) > 0;
}

/* The flag's entry for `command`; NULL if it has none (*exists: whether
 * another subcommand takes it). */
static const Flag *find_flag(const char *name, Command command, int *exists)
{
    *exists = 0;
    for (size_t i = 0; i < sizeof flags / sizeof flags[0]; ++i) {
        if (!flags[i].name || strcmp(flags[i].name, name) != 0)
            continue;
        if (flags[i].commands & (1 << command))
            return &flags[i];
        *exists = 1;
    }
    return NULL;
}

/* Applies one flag (its value already taken). Returns 0, or 2 with a message. */
static int set_flag(Options *o, const char *flag, const char *value, char *error, size_t size)
{
    uint64_t number = 0;
    double real = 0.0;
    if (strcmp(flag, "--help") == 0 || strcmp(flag, "-h") == 0) {
        o->help = 1;
    } else if (strcmp(flag, "--list-devices") == 0) {
        o->command = COMMAND_LIST_DEVICES;
    } else if (strcmp(flag, "--quiet") == 0) {
        o->quiet = 1;
    } else if (strcmp(flag, "--diagnostics") == 0) {
        o->diagnostics = 1;
    } else if (strcmp(flag, "--write-sets") == 0) {
        o->write_sets = 1;
    } else if (strcmp(flag, "--allow-unsupported") == 0) {
        o->allow_unsupported = 1;
    } else if (strcmp(flag, "--all-features") == 0) {
        o->all_features = 1;
    } else if (strcmp(flag, "--checkpoints") == 0) {
        o->checkpoints = value;
    } else if (strcmp(flag, "--reference") == 0) {
        o->reference = value;
    } else if (strcmp(flag, "--dump-kernel") == 0) {
        o->dump_kernel = value;
    } else if (strcmp(flag, "--spp") == 0) {
        if (parse_u64(value, UINT64_C(1) << 40, &number) || number == 0)
            return fail(error, size, "--spp: '%s' is not a positive integer", value);
        o->spp = number;
    } else if (strcmp(flag, "--seed") == 0) {
        if (parse_u64(value, UINT32_MAX, &number))
            return fail(error, size, "--seed: '%s' is not an integer in 0..4294967295", value);
        o->seed = (uint32_t)number;
    } else if (strcmp(flag, "--first-sample") == 0) {
        if (parse_u64(value, UINT64_C(1) << 48, &number))
            return fail(error, size, "--first-sample: '%s' is not a non-negative integer", value);
        o->first_sample = number;
    } else if (strcmp(flag, "--sets") == 0) {
        char message[128];
        if (parse_u64(value, 1000, &number) || film_check_set_count((int)number, message, sizeof message))
            return fail(error, size, "--sets: '%s': %s", value, message);
        o->estimator.set_count = (int)number;
    } else if (strcmp(flag, "--estimators") == 0) {
        char message[640];
        if (passes_from_list(value, &o->estimator.passes, message, sizeof message))
            return fail(error, size, "--estimators: %s", message);
        o->estimators_given = 1;
    } else if (strcmp(flag, "--estimator-param") == 0) {
        char message[640];
        if (estimator_param_set(&o->estimator.params, value, message, sizeof message))
            return fail(error, size, "--estimator-param: %s", message);
    } else if (strcmp(flag, "--stderr") == 0) {
        o->estimator.with_stderr = 1;
    } else if (strcmp(flag, "--gini-mode") == 0) {
        if (strcmp(value, "channel") == 0)
            o->estimator.gini_mode = GINI_PER_CHANNEL;
        else if (strcmp(value, "pixel") == 0)
            o->estimator.gini_mode = GINI_PER_PIXEL;
        else if (strcmp(value, "luminance") == 0)
            o->estimator.gini_mode = SORT_BY_LUMINANCE;
        else
            return fail(error, size, "--gini-mode: '%s' is not channel, pixel or luminance", value);
    } else if (strcmp(flag, "--preview") == 0) {
        o->preview = pass_from_name(value);
        if (o->preview < 0 || !(PASSES_ESTIMATES & PASS_BIT(o->preview)))
            return fail(error, size, "--preview: '%s' is not an estimator name (see --estimators)", value);
    } else if (strcmp(flag, "--exposure") == 0) {
        if (parse_double(value, &real))
            return fail(error, size, "--exposure: '%s' is not a non-negative number", value);
        o->exposure = (float)real;
    } else if (strcmp(flag, "--time") == 0) {
        if (parse_double(value, &real) || real <= 0.0)
            return fail(error, size, "--time: '%s' is not a positive number of seconds", value);
        o->time_budget = real;
    } else if (strcmp(flag, "--resolution") == 0) {
        if (parse_resolution(value, &o->width, &o->height))
            return fail(error, size, "--resolution: '%s' is not WIDTHxHEIGHT, each 1..65536 (e.g. 640x480)", value);
    } else if (strcmp(flag, "--sampler") == 0) {
        o->sampler = sampler_from_name(value);
        if (o->sampler < 0)
            return fail(error, size, "--sampler: '%s' is not sobol-sets, sobol-pixel or independent", value);
    } else if (strcmp(flag, "--light-sampler") == 0) {
        o->light_sampler = light_sampler_from_name(value);
        if (o->light_sampler < 0)
            return fail(error, size, "--light-sampler: '%s' is not bvh, exhaustive, power or uniform", value);
    } else if (strcmp(flag, "--maxdepth") == 0) {
        if (parse_u64(value, 10000, &number))
            return fail(error, size, "--maxdepth: '%s' is not an integer in 0..10000", value);
        o->max_depth = (int)number;
    } else if (strcmp(flag, "--integrator") == 0) {
        o->bsdf_only = strcmp(value, "bsdf") == 0;
        if (strcmp(value, "nee") == 0 || strcmp(value, "bsdf") == 0)
            o->light_subpaths = 0;
        else if (strcmp(value, "bdpt") == 0)
            o->light_subpaths = SCENE_BDPT;
        else if (strcmp(value, "lightpath") == 0)
            o->light_subpaths = SCENE_LIGHTPATH;
        else
            return fail(error, size, "--integrator: '%s' is not nee, bsdf, bdpt or lightpath", value);
    } else if (strcmp(flag, "--device") == 0) {
        return parse_devices(value, &o->devices, error, size);
    } else if (strcmp(flag, "--outfile") == 0) {
        if (!names_a_file(value))
            return fail(error, size, "--outfile '%s' names no file (give one such as out.exr)", value);
        o->outfile = value;
    } else if (strcmp(flag, "--kernel-dir") == 0) {
        o->kernel_dir = value;
    }
    return 0;
}

int options_check_preview(Options *o, char *error, size_t size)
{
    const uint32_t estimates = o->estimator.passes & PASSES_ESTIMATES;
    if (o->preview < 0) {
        o->preview = (estimates & PASS_BIT(PASS_GMON)) ? PASS_GMON : trailing_zeros64((uint64_t)estimates);
        return 0;
    }
    if (!(estimates & PASS_BIT(o->preview)))
        return fail(error, size, "--preview %s: that estimator is not among --estimators", pass_name(o->preview));
    return 0;
}

static const char *const command_names[] = {"render", "estimate", "merge", "check", "--list-devices"};

int options_parse(int argc, char **argv, Options *o, char *error, size_t size)
{
    memset(o, 0, sizeof *o);
    o->command = COMMAND_RENDER;
    estimator_settings_default(&o->estimator);
    o->preview = -1;
    o->exposure = 1.0f;
    o->max_depth = -1;
    o->light_subpaths = -1;
    o->sampler = -1;
    o->light_sampler = -1;

    int first = 1;
    if (argc > 1 && strcmp(argv[1], "estimate") == 0) {
        o->command = COMMAND_ESTIMATE;
        first = 2;
    } else if (argc > 1 && strcmp(argv[1], "merge") == 0) {
        o->command = COMMAND_MERGE;
        first = 2;
    } else if (argc > 1 && strcmp(argv[1], "check") == 0) {
        o->command = COMMAND_CHECK;
        first = 2;
    }
    const Command subcommand = o->command;
    for (int i = first; i < argc; ++i) {
        const char *arg = argv[i];
        if (arg[0] != '-' || arg[1] == '\0') {
            if (o->command == COMMAND_MERGE) {
                if (o->merge_count == OPTIONS_MAX_MERGE)
                    return fail(error, size, "merge takes at most 1024 files");
                o->merge_inputs[o->merge_count++] = arg;
                continue;
            }
            if (o->input)
                return fail(error, size, "more than one input file: '%s' and '%s'", o->input, arg);
            o->input = arg;
            continue;
        }
        /* --flag=value as well as --flag value. */
        char name[64];
        const char *value = NULL;
        const char *equals = strchr(arg, '=');
        if (equals && (size_t)(equals - arg) < sizeof name) {
            memcpy(name, arg, (size_t)(equals - arg));
            name[equals - arg] = '\0';
            value = equals + 1;
            arg = name;
        }
        int exists = 0;
        const Flag *flag = find_flag(arg, subcommand, &exists);
        if (!flag && exists)
            return fail(error, size, "`gmonrt %s` does not take %s (see gmonrt %s --help)", command_names[subcommand],
                        arg, command_names[subcommand]);
        if (!flag)
            return fail(error, size, "unknown option '%s' (see --help)", arg);
        if (!flag->value && value)
            return fail(error, size, "%s takes no value", arg);
        if (flag->value && !value) {
            if (i + 1 >= argc)
                return fail(error, size, "%s needs a value (see --help)", arg);
            value = argv[++i];
        }
        if (set_flag(o, arg, value, error, size))
            return 2;
    }
    if (o->help)
        return 0;
    if (o->command == COMMAND_ESTIMATE && !o->input)
        return fail(error, size, "estimate needs an EXR file written with --write-sets");
    if (o->command == COMMAND_CHECK && !o->input)
        return fail(error, size, "check needs a scene file");
    if (o->command == COMMAND_MERGE && o->merge_count < 1)
        return fail(error, size, "merge needs the EXR files to combine (written with --write-sets)");
    if (o->reference && !o->checkpoints)
        return fail(error, size, "--reference is used with --checkpoints");
    if (o->diagnostics)
        o->estimator.passes |= PASSES_DIAGNOSTICS;
    if ((o->command == COMMAND_ESTIMATE || o->command == COMMAND_MERGE) && (o->estimator.passes & PASSES_SAMPLE)) {
        for (int p = 0; p < PASS_COUNT; ++p)
            if (o->estimator.passes & PASSES_SAMPLE & PASS_BIT(p))
                return fail(error, size,
                            "--estimators %s: it sees each sample as it is accumulated, so only a render computes it "
                            "(`%s` has only the set sums)",
                            pass_name(p), command_names[o->command]);
    }
    if (o->estimator.with_stderr && o->estimator.gini_mode == SORT_BY_LUMINANCE)
        return fail(error, size, "--stderr is not available with --gini-mode luminance (it trims whole RGB sets)");
    /* estimate and merge take the file's estimators: their preview is
     * chosen once those are known (options_for_file). */
    if ((o->command != COMMAND_ESTIMATE && o->command != COMMAND_MERGE) || o->estimators_given)
        return options_check_preview(o, error, size);
    return 0;
}
