#define _POSIX_C_SOURCE 200809L
#include "cli/options.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char help_text[] = "usage: gmonrt [options] [scene.pbrt]\n"
                                "       gmonrt estimate [options] render.exr\n"
                                "       gmonrt merge [options] part1.exr part2.exr ...\n"
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
                                "\n"
                                "Sampling\n"
                                "  --spp N              samples per pixel (default: the scene's Sampler\n"
                                "                       \"pixelsamples\", else 64). Sampling is always independent\n"
                                "                       uniform random, as median of means requires.\n"
                                "  --seed N             random seed (default 0); the image depends only on the\n"
                                "                       seed and the sample range, never on passes or devices\n"
                                "  --first-sample N     first sample index of the range rendered (default 0)\n"
                                "  --time SECONDS       stop after the pass that reaches this render time\n"
                                "  --integrator MODE    nee: next-event estimation with MIS (default);\n"
                                "                       bsdf: BSDF sampling only (the firefly-prone case)\n"
                                "  --maxdepth N         override the scene's Integrator \"maxdepth\"\n"
                                "  --resolution WxH     override the scene's Film resolution\n"
                                "\n"
                                "Estimators\n"
                                "  --sets M             number of sets for MoN and G-MoN, 1..64 (default 21)\n"
                                "  --estimators LIST    comma-separated subset of mean,mon,gmon (default all)\n"
                                "  --gini-mode MODE     channel: G and trim per channel (default);\n"
                                "                       pixel: one G per pixel, the mean of the channels' G;\n"
                                "                       luminance: sort and trim whole sets by luminance\n"
                                "  --diagnostics        add layers: Gini G, trim count c, non-finite samples\n"
                                "  --write-sets         add the exact per-set sums, for `estimate` and merging\n"
                                "                       (without it, --estimators mean accumulates one sum\n"
                                "                       per pixel instead of M)\n"
                                "\n";
/* Two parts: C compilers need not support longer string literals. */
static const char help_text_output[] =
    "Output\n"
    "  --outfile PATH       EXR file (default: the scene's Film \"filename\" with an\n"
    "                       .exr extension, else render.exr); the PNG preview goes\n"
    "                       beside it with a .png extension\n"
    "  --preview NAME       estimator shown in the PNG: mean, mon or gmon (default\n"
    "                       gmon, or the only one requested)\n"
    "  --exposure X         PNG exposure multiplier (default 1)\n"
    "  --quiet              no progress bar and no summary line\n"
    "  --checkpoints DIR    at 1, 2, 4, ... samples per pixel and at the end, write\n"
    "                       DIR/spp-NNNNNN.exr (attribute `seconds`: render time so\n"
    "                       far) and a row per estimator to DIR/checkpoints.csv\n"
    "                       (spp,seconds,estimator,rmse,relmse), from one render\n"
    "  --reference EXR      with --checkpoints: fill rmse and relmse against this\n"
    "                       image's mean layer (relmse: mean of (x-r)^2/(r^2+0.01))\n"
    "\n"
    "Devices\n"
    "  --list-devices       list OpenCL devices and exit\n"
    "  --device SPEC        all, cpu, gpu, or comma-separated indices from\n"
    "                       --list-devices (default all): the devices render at\n"
    "                       once, each a share of the pixels proportional to its\n"
    "                       speed; the image is the same whatever the devices\n"
    "\n"
    "Scene input\n"
    "  --allow-unsupported  turn errors on unsupported scene features into warnings,\n"
    "                       each with a documented substitute\n"
    "\n"
    "Developer\n"
    "  --kernel-dir DIR     load OpenCL sources from DIR instead of the embedded copies\n"
    "                       (also: environment variable GMON_KERNEL_DIR)\n"
    "  --dump-kernel FILE   write the path tracer source as specialized for this\n"
    "                       scene and these outputs, with its defines, to FILE\n"
    "  --all-features       build the kernels with every feature instead of only\n"
    "                       what the scene and outputs use (for comparisons)\n"
    "  --help               this text\n"
    "\n"
    "Exit status: 0 success, 1 render or I/O failure, 2 bad command line, 130 interrupted\n"
    "by Ctrl-C (after writing the image of the samples done).\n";

const char *options_help(void)
{
    static char text[sizeof help_text + sizeof help_text_output];
    if (!text[0])
        snprintf(text, sizeof text, "%s%s", help_text, help_text_output);
    return text;
}

static int fail(char *error, size_t size, const char *format, const char *a, const char *b)
{
    snprintf(error, size, format, a, b);
    return 2;
}

static int parse_u64(const char *text, uint64_t max, uint64_t *out)
{
    if (!text || !*text || *text == '-')
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

static int parse_estimators(const char *text, int *outputs)
{
    *outputs = 0;
    char copy[64];
    if (strlen(text) >= sizeof copy)
        return -1;
    strcpy(copy, text);
    for (char *save = NULL, *item = strtok_r(copy, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        if (strcmp(item, "mean") == 0)
            *outputs |= ESTIMATOR_OUTPUT_MEAN;
        else if (strcmp(item, "mon") == 0)
            *outputs |= ESTIMATOR_OUTPUT_MON;
        else if (strcmp(item, "gmon") == 0)
            *outputs |= ESTIMATOR_OUTPUT_GMON;
        else
            return -1;
    }
    return *outputs ? 0 : -1;
}

int options_parse(int argc, char **argv, Options *o, char *error, size_t size)
{
    memset(o, 0, sizeof *o);
    o->command = COMMAND_RENDER;
    o->estimator.set_count = ESTIMATOR_DEFAULT_SETS;
    o->estimator.gini_mode = GINI_PER_CHANNEL;
    o->outputs = ESTIMATOR_OUTPUT_MEAN | ESTIMATOR_OUTPUT_MON | ESTIMATOR_OUTPUT_GMON;
    o->exposure = 1.0f;
    o->max_depth = -1;

    int first = 1;
    if (argc > 1 && strcmp(argv[1], "estimate") == 0) {
        o->command = COMMAND_ESTIMATE;
        first = 2;
    } else if (argc > 1 && strcmp(argv[1], "merge") == 0) {
        o->command = COMMAND_MERGE;
        first = 2;
    }
    for (int i = first; i < argc; ++i) {
        const char *flag = argv[i];
        /* Accept --flag=value as well as --flag value. */
        char name[64];
        const char *value = NULL;
        const char *equals = strchr(flag, '=');
        if (flag[0] == '-' && equals && (size_t)(equals - flag) < sizeof name) {
            memcpy(name, flag, (size_t)(equals - flag));
            name[equals - flag] = '\0';
            value = equals + 1;
            flag = name;
        }
#define NEEDS_VALUE()                                                                                                  \
    do {                                                                                                               \
        if (!value) {                                                                                                  \
            if (i + 1 >= argc)                                                                                         \
                return fail(error, size, "%s needs a value (see --help)", flag, NULL);                                 \
            value = argv[++i];                                                                                         \
        }                                                                                                              \
    } while (0)
        uint64_t number = 0;
        double real = 0.0;
        static const char *const switches[] = {
            "--help",        "-h",           "--list-devices",      "--quiet",
            "--diagnostics", "--write-sets", "--allow-unsupported", "--all-features"};
        for (size_t k = 0; value && k < sizeof switches / sizeof switches[0]; ++k)
            if (strcmp(flag, switches[k]) == 0)
                return fail(error, size, "%s takes no value", flag, NULL);
        if (strcmp(flag, "--help") == 0 || strcmp(flag, "-h") == 0) {
            o->command = COMMAND_HELP;
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
            NEEDS_VALUE();
            o->checkpoints = value;
        } else if (strcmp(flag, "--reference") == 0) {
            NEEDS_VALUE();
            o->reference = value;
        } else if (strcmp(flag, "--dump-kernel") == 0) {
            NEEDS_VALUE();
            o->dump_kernel = value;
        } else if (strcmp(flag, "--spp") == 0) {
            NEEDS_VALUE();
            if (parse_u64(value, UINT64_C(1) << 40, &number) || number == 0)
                return fail(error, size, "--spp: '%s' is not a positive integer", value, NULL);
            o->spp = number;
        } else if (strcmp(flag, "--seed") == 0) {
            NEEDS_VALUE();
            if (parse_u64(value, UINT32_MAX, &number))
                return fail(error, size, "--seed: '%s' is not an integer in 0..4294967295", value, NULL);
            o->seed = (uint32_t)number;
        } else if (strcmp(flag, "--first-sample") == 0) {
            NEEDS_VALUE();
            if (parse_u64(value, UINT64_C(1) << 48, &number))
                return fail(error, size, "--first-sample: '%s' is not a non-negative integer", value, NULL);
            o->first_sample = number;
        } else if (strcmp(flag, "--sets") == 0) {
            NEEDS_VALUE();
            if (parse_u64(value, 64, &number) || number < 1)
                return fail(error, size, "--sets: '%s' is not in 1..64", value, NULL);
            o->estimator.set_count = (int)number;
        } else if (strcmp(flag, "--estimators") == 0) {
            NEEDS_VALUE();
            if (parse_estimators(value, &o->outputs))
                return fail(error, size, "--estimators: '%s' is not a list of mean, mon, gmon", value, NULL);
        } else if (strcmp(flag, "--gini-mode") == 0) {
            NEEDS_VALUE();
            if (strcmp(value, "channel") == 0)
                o->estimator.gini_mode = GINI_PER_CHANNEL;
            else if (strcmp(value, "pixel") == 0)
                o->estimator.gini_mode = GINI_PER_PIXEL;
            else if (strcmp(value, "luminance") == 0)
                o->estimator.gini_mode = SORT_BY_LUMINANCE;
            else
                return fail(error, size, "--gini-mode: '%s' is not channel, pixel or luminance", value, NULL);
        } else if (strcmp(flag, "--preview") == 0) {
            NEEDS_VALUE();
            if (strcmp(value, "mean") && strcmp(value, "mon") && strcmp(value, "gmon"))
                return fail(error, size, "--preview: '%s' is not mean, mon or gmon", value, NULL);
            o->preview = value;
        } else if (strcmp(flag, "--exposure") == 0) {
            NEEDS_VALUE();
            if (parse_double(value, &real))
                return fail(error, size, "--exposure: '%s' is not a non-negative number", value, NULL);
            o->exposure = (float)real;
        } else if (strcmp(flag, "--time") == 0) {
            NEEDS_VALUE();
            if (parse_double(value, &real) || real <= 0.0)
                return fail(error, size, "--time: '%s' is not a positive number of seconds", value, NULL);
            o->time_budget = real;
        } else if (strcmp(flag, "--resolution") == 0) {
            NEEDS_VALUE();
            unsigned w = 0, h = 0;
            char tail = 0;
            if (sscanf(value, "%ux%u%c", &w, &h, &tail) != 2 || w == 0 || h == 0 || w > 65536 || h > 65536)
                return fail(error, size, "--resolution: '%s' is not WIDTHxHEIGHT (e.g. 640x480)", value, NULL);
            o->width = w;
            o->height = h;
        } else if (strcmp(flag, "--maxdepth") == 0) {
            NEEDS_VALUE();
            if (parse_u64(value, 10000, &number))
                return fail(error, size, "--maxdepth: '%s' is not an integer in 0..10000", value, NULL);
            o->max_depth = (int)number;
        } else if (strcmp(flag, "--integrator") == 0) {
            NEEDS_VALUE();
            if (strcmp(value, "nee") == 0)
                o->bsdf_only = 0;
            else if (strcmp(value, "bsdf") == 0)
                o->bsdf_only = 1;
            else
                return fail(error, size, "--integrator: '%s' is not nee or bsdf", value, NULL);
        } else if (strcmp(flag, "--device") == 0) {
            NEEDS_VALUE();
            o->devices = value;
        } else if (strcmp(flag, "--outfile") == 0) {
            NEEDS_VALUE();
            o->outfile = value;
        } else if (strcmp(flag, "--kernel-dir") == 0) {
            NEEDS_VALUE();
            o->kernel_dir = value;
        } else if (flag[0] == '-' && flag[1] != '\0') {
            return fail(error, size, "unknown option '%s' (see --help)", flag, NULL);
        } else {
            if (value)
                return fail(error, size, "unexpected '%s'", argv[i], NULL);
            if (o->command == COMMAND_MERGE) {
                if (o->merge_count == OPTIONS_MAX_MERGE)
                    return fail(error, size, "merge takes at most 1024 files", NULL, NULL);
                o->merge_inputs[o->merge_count++] = flag;
                continue;
            }
            if (o->input)
                return fail(error, size, "more than one input file: '%s' and '%s'", o->input, flag);
            o->input = flag;
        }
#undef NEEDS_VALUE
    }
    if (o->command == COMMAND_ESTIMATE && !o->input)
        return fail(error, size, "estimate needs an EXR file written with --write-sets", NULL, NULL);
    if (o->command == COMMAND_MERGE && o->merge_count < 1)
        return fail(error, size, "merge needs the EXR files to combine (written with --write-sets)", NULL, NULL);
    if (o->reference && !o->checkpoints)
        return fail(error, size, "--reference is used with --checkpoints", NULL, NULL);
    if (!o->preview) {
        o->preview = (o->outputs & ESTIMATOR_OUTPUT_GMON)  ? "gmon"
                     : (o->outputs & ESTIMATOR_OUTPUT_MON) ? "mon"
                                                           : "mean";
    } else {
        int bit = strcmp(o->preview, "mean") == 0  ? ESTIMATOR_OUTPUT_MEAN
                  : strcmp(o->preview, "mon") == 0 ? ESTIMATOR_OUTPUT_MON
                                                   : ESTIMATOR_OUTPUT_GMON;
        if (!(o->outputs & bit))
            return fail(error, size, "--preview %s: that estimator is not among --estimators", o->preview, NULL);
    }
    return 0;
}
