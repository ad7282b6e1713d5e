/* gmonrt's command line: every flag, its default and its validation. */
#ifndef HOST_CLI_OPTIONS_H
#define HOST_CLI_OPTIONS_H

#include "film/film.h"

#include <stddef.h>
#include <stdint.h>

#define OPTIONS_MAX_MERGE 1024
#define OPTIONS_MAX_DEVICES 16 /* indices in one --device list */

typedef enum {
    COMMAND_RENDER,
    COMMAND_ESTIMATE, /* re-estimate a saved EXR's set sums */
    COMMAND_MERGE,    /* combine EXRs of disjoint sample ranges */
    COMMAND_CHECK,    /* list what a scene needs that gmonrt lacks or that is missing */
    COMMAND_LIST_DEVICES,
} Command;

/* --device, parsed: which devices exist is known only once they are
 * enumerated (devices_open). */
typedef struct {
    const char *spec; /* as given, for messages; NULL: all */
    enum { DEVICES_ALL, DEVICES_CPU, DEVICES_GPU, DEVICES_INDICES } kind;
    int indices[OPTIONS_MAX_DEVICES]; /* DEVICES_INDICES: distinct, in the order given */
    int index_count;
} DeviceSelection;

typedef struct {
    Command command;
    int help;                                    /* --help: print options_help(command) */
    const char *input;                           /* scene file (render, check) or EXR (estimate); NULL: default scene */
    const char *merge_inputs[OPTIONS_MAX_MERGE]; /* merge: the EXRs */
    int merge_count;
    const char *outfile; /* EXR path; NULL: from the scene's Film, else render.exr */
    uint64_t spp;        /* 0: the scene's Sampler pixelsamples */
    uint32_t seed;
    int quiet;
    EstimatorSettings estimator; /* --sets, --gini-mode, --estimators (passes, with the diagnostics'),
                                    --stderr, --estimator-param */
    int estimators_given;        /* --estimators was given (estimate: else the file's list) */
    int diagnostics;             /* --diagnostics: Gini, trim count, non-finite and rounded count layers */
    int write_sets;              /* --write-sets: exact per-set sums in the EXR */
    int preview;                 /* the pass shown in the PNG (a PASS_* id) */
    float exposure;              /* PNG exposure multiplier */
    double time_budget;          /* --time seconds, 0: none */
    unsigned width, height;      /* --resolution, 0: the scene's */
    int max_depth;               /* --maxdepth, -1: the scene's */
    int sampler;                 /* --sampler: SAMPLER_*, -1: the scene's */
    int light_sampler;           /* --light-sampler: LIGHT_SAMPLER_*, -1: the scene's */
    int bsdf_only;               /* --integrator bsdf */
    int light_subpaths;          /* --integrator: SCENE_BDPT, SCENE_LIGHTPATH, 0 (nee, bsdf), -1: the scene's */
    DeviceSelection devices;     /* --device */
    uint64_t first_sample;       /* --first-sample: start of the sample range */
    int allow_unsupported;
    const char *checkpoints; /* --checkpoints DIR */
    const char *reference;   /* --reference EXR, for the checkpoints' errors */
    const char *dump_kernel; /* --dump-kernel FILE */
    int all_features;        /* --all-features: no kernel specialization */
    const char *kernel_dir;
} Options;

/* Parses argv. Returns 0 on success; on a bad flag or value, or a flag the
 * subcommand does not use, writes a one-line message to `error` and returns
 * 2 (the exit code to use). */
int options_parse(int argc, char **argv, Options *options, char *error, size_t error_size);

/* Picks the preview (gmon if requested, else the first estimator) or
 * checks that the one asked for is requested: 0, or 2 with a message. For
 * `estimate` and `merge`, once the file's estimators are known. */
int options_check_preview(Options *options, char *error, size_t error_size);

/* The --help text of a command: its usage and only the flags it takes. */
const char *options_help(Command command);

#endif
