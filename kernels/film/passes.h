/* The film's passes: every per-pixel image an estimation can produce, in
 * one list shared by the host and the kernels. The pass ids, their bits in
 * an output mask, the EXR layer names, the command-line names and help, the
 * checkpoint columns and the masks below that steer the estimator code all
 * come from it: adding a set-based estimator is one row here (and its
 * parameters' rows below) and one file under kernels/film/estimators/
 * (docs/estimators.md, "Adding an estimator").
 *
 * PASS(id, name, type, kind, form, fn)
 *   id        PASS_<id> in the enum below, bit PASS_BIT(PASS_<id>)
 *   name      as users select it (--estimators), and the EXR layer
 *             <name>.R/G/B
 *   type      PASS_FLOAT or PASS_INT (values per pixel: EST_CHANNELS, RGB)
 *   kind      PASS_ESTIMATE: an estimator of the pixel value, from the set
 *             sums (it has a <name>.stderr image on request);
 *             PASS_DIAGNOSTIC: what G-MoN decided (--diagnostics);
 *             PASS_SAMPLE: an estimator that sees each sample as it is
 *             accumulated, from per-sample state the path tracer keeps only
 *             when it is requested (sample_passes.h; not re-estimable from
 *             the sets, not in "all")
 *   form      how it is computed, which gives its traits (FORM_TRAITS_*)
 *             and fn's signature; the estimates come unclamped, in the
 *             units of the set means v:
 *             CORE          with the sort of each channel
 *                           (estimate_channel); fn: none
 *             CORE_BY_RANK  the same, and its leave-one-out estimates
 *                           depend on the set left out only through its
 *                           rank (MoN)
 *             OF_SORTED     est_float fn(const est_float *v, int m,
 *                           const EstimatorParams *params): a function of
 *                           one channel's ascending v[0..m-1] alone (the
 *                           jackknife recomputes it)
 *             FIXED_WEIGHTS float fn(int side, int m, const
 *                           EstimatorParams *params, FixedWeights *out): a
 *                           weighted mean of the sorted set means whose
 *                           weights depend on m and the parameters only
 *                           (side 0); its leave-one-out estimates come from
 *                           prefix and suffix sums, by rank
 *             GATED         the same fn with two sides: side 0 where the
 *                           pixel's mean Gini Gbar is below the threshold
 *                           fn returns, side 1 at or above it
 *             WHOLE_PIXEL   void fn(const est_float (*v)[EST_CAPACITY],
 *                           const est_float (*t)[EST_CAPACITY], int m,
 *                           const EstimatorParams *params, FamilyShared
 *                           *shared, est_float *value): the three channels
 *                           together, from the sorted set means v[c], those
 *                           by set t[c] and what the family shares
 *                           (estimators.h); value[c] (recomputed by the
 *                           jackknife)
 *             SAMPLE        per sample (sample_passes.h); fn: none
 *             SAMPLE_NEIGHBOURHOOD  the same, and it needs the pixels
 *                           around it, so the whole image (not estimated
 *                           per pixel range)
 *   fn        the estimator's function (kernels/film/estimators/), none
 *             for the forms without one
 * Valid C11 and OpenCL C. */
#ifndef KERNELS_PASSES_H
#define KERNELS_PASSES_H

#include "../common/compat.h"

#define PASS_FLOAT 0
#define PASS_INT 1
#define PASS_ESTIMATE 0
#define PASS_DIAGNOSTIC 1
#define PASS_SAMPLE 2

/* The traits the estimator code steers by: computed with each channel's
 * sort (not by estimate_family); needs the pixel's three channels
 * together; fixed weights; leave-one-out estimates by rank; a function of
 * one channel's sorted values; needs the neighbouring pixels. */
#define TRAIT_CORE 1u
#define TRAIT_WHOLE_PIXEL 2u
#define TRAIT_FIXED_WEIGHTS 4u
#define TRAIT_BY_RANK 8u
#define TRAIT_OF_SORTED 16u
#define TRAIT_NEIGHBOURHOOD 32u

#define FORM_TRAITS_CORE TRAIT_CORE
#define FORM_TRAITS_CORE_BY_RANK (TRAIT_CORE | TRAIT_BY_RANK)
#define FORM_TRAITS_OF_SORTED TRAIT_OF_SORTED
#define FORM_TRAITS_FIXED_WEIGHTS (TRAIT_FIXED_WEIGHTS | TRAIT_BY_RANK)
#define FORM_TRAITS_GATED (TRAIT_WHOLE_PIXEL | TRAIT_FIXED_WEIGHTS | TRAIT_BY_RANK)
#define FORM_TRAITS_WHOLE_PIXEL TRAIT_WHOLE_PIXEL
#define FORM_TRAITS_SAMPLE 0u
#define FORM_TRAITS_SAMPLE_NEIGHBOURHOOD TRAIT_NEIGHBOURHOOD

#define GMON_PASSES(PASS)                                                                                              \
    PASS(MEAN, "mean", PASS_FLOAT, PASS_ESTIMATE, CORE, none)                                                          \
    PASS(MON, "mon", PASS_FLOAT, PASS_ESTIMATE, CORE_BY_RANK, none)                                                    \
    PASS(GMON, "gmon", PASS_FLOAT, PASS_ESTIMATE, CORE, none)                                                          \
    PASS(AMON, "amon", PASS_FLOAT, PASS_ESTIMATE, FIXED_WEIGHTS, amon_fixed_weights)                                   \
    PASS(ADMON, "admon", PASS_FLOAT, PASS_ESTIMATE, FIXED_WEIGHTS, admon_fixed_weights)                                \
    PASS(GGMON, "ggmon", PASS_FLOAT, PASS_ESTIMATE, WHOLE_PIXEL, ggmon_estimate)                                       \
    PASS(GMON_BINARY, "gmon-binary", PASS_FLOAT, PASS_ESTIMATE, GATED, gmon_binary_weights)                            \
    PASS(GMON_PARTIAL, "gmon-partial", PASS_FLOAT, PASS_ESTIMATE, GATED, gmon_partial_weights)                         \
    PASS(DMON_PARTIAL, "dmon-partial", PASS_FLOAT, PASS_ESTIMATE, GATED, dmon_partial_weights)                         \
    PASS(GMON_AUTHORS, "gmon-authors", PASS_FLOAT, PASS_ESTIMATE, WHOLE_PIXEL, gmon_authors_estimate)                  \
    PASS(PAKMON, "pakmon", PASS_FLOAT, PASS_ESTIMATE, OF_SORTED, pakmon_of_sorted)                                     \
    PASS(TRIMMED, "trimmed", PASS_FLOAT, PASS_ESTIMATE, FIXED_WEIGHTS, trimmed_fixed_weights)                          \
    PASS(WINSORIZED, "winsorized", PASS_FLOAT, PASS_ESTIMATE, FIXED_WEIGHTS, winsorized_fixed_weights)                 \
    PASS(GMEDIAN, "gmedian", PASS_FLOAT, PASS_ESTIMATE, WHOLE_PIXEL, gmedian_estimate)                                 \
    PASS(HUBER, "huber", PASS_FLOAT, PASS_ESTIMATE, OF_SORTED, huber_of_sorted)                                        \
    PASS(GINI, "gini", PASS_FLOAT, PASS_DIAGNOSTIC, CORE, none)                                                        \
    PASS(TRIM, "trim", PASS_INT, PASS_DIAGNOSTIC, CORE, none)                                                          \
    PASS(CLAMP, "clamp", PASS_FLOAT, PASS_SAMPLE, SAMPLE, none)                                                        \
    PASS(CLAMP_SUM, "clamp-sum", PASS_FLOAT, PASS_SAMPLE, SAMPLE, none)                                                \
    PASS(ABMM, "abmm", PASS_FLOAT, PASS_SAMPLE, SAMPLE, none)                                                          \
    PASS(GABMM, "gabmm", PASS_FLOAT, PASS_SAMPLE, SAMPLE, none)                                                        \
    PASS(ZIRR, "zirr", PASS_FLOAT, PASS_SAMPLE, SAMPLE_NEIGHBOURHOOD, none)                                            \
    PASS(MEAN_OR_MON, "mean-or-mon", PASS_FLOAT, PASS_SAMPLE, SAMPLE, none)

#define PASS_ENUM_(id, name, type, kind, form, fn) PASS_##id,
enum { GMON_PASSES(PASS_ENUM_) PASS_COUNT };
#undef PASS_ENUM_

#define PASS_BIT(pass) (1u << (pass))
/* A row's bit if `test` (of its kind or traits) holds, for the masks. */
#define FORM_HAS_(form, trait) ((FORM_TRAITS_##form & (trait)) != 0u)
#define PASS_BIT_IF_(test, id) ((test) ? PASS_BIT(PASS_##id) : 0u) |
#define PASS_ESTIMATE_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_((kind) == PASS_ESTIMATE, id)
#define PASS_DIAGNOSTIC_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_((kind) == PASS_DIAGNOSTIC, id)
#define PASS_SAMPLE_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_((kind) == PASS_SAMPLE, id)
#define PASS_CORE_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_(FORM_HAS_(form, TRAIT_CORE), id)
#define PASS_WHOLE_PIXEL_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_(FORM_HAS_(form, TRAIT_WHOLE_PIXEL), id)
#define PASS_FIXED_WEIGHTS_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_(FORM_HAS_(form, TRAIT_FIXED_WEIGHTS), id)
#define PASS_BY_RANK_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_(FORM_HAS_(form, TRAIT_BY_RANK), id)
#define PASS_OF_SORTED_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_(FORM_HAS_(form, TRAIT_OF_SORTED), id)
#define PASS_NEIGHBOURHOOD_BIT_(id, name, type, kind, form, fn) PASS_BIT_IF_(FORM_HAS_(form, TRAIT_NEIGHBOURHOOD), id)

/* Every set-based estimator, and the diagnostics: what the estimator
 * kernel computes. */
#define PASSES_ESTIMATES (GMON_PASSES(PASS_ESTIMATE_BIT_) 0u)
#define PASSES_DIAGNOSTICS (GMON_PASSES(PASS_DIAGNOSTIC_BIT_) 0u)
#define PASSES_ALL (PASSES_ESTIMATES | PASSES_DIAGNOSTICS)
/* The per-sample estimators (sample_passes.h, sample_estimator.cl). */
#define PASSES_SAMPLE (GMON_PASSES(PASS_SAMPLE_BIT_) 0u)
/* What a render computes unless asked otherwise. */
#define PASSES_DEFAULT (PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_MON) | PASS_BIT(PASS_GMON))

/* The passes of each trait (the table's comment). */
#define PASSES_CORE (GMON_PASSES(PASS_CORE_BIT_) 0u)
#define PASSES_PER_PIXEL (GMON_PASSES(PASS_WHOLE_PIXEL_BIT_) 0u)
#define PASSES_FIXED_WEIGHTS (GMON_PASSES(PASS_FIXED_WEIGHTS_BIT_) 0u)
#define PASSES_BY_RANK (GMON_PASSES(PASS_BY_RANK_BIT_) 0u)
#define PASSES_OF_SORTED (GMON_PASSES(PASS_OF_SORTED_BIT_) 0u)
#define PASSES_NEIGHBOURHOOD (GMON_PASSES(PASS_NEIGHBOURHOOD_BIT_) 0u)
/* The fixed-weight estimators that choose between weights by Gbar. */
#define PASSES_GATED_BY_GBAR (PASSES_PER_PIXEL & PASSES_FIXED_WEIGHTS)
/* The estimators of the family: estimate_family's. */
#define PASSES_FAMILY (PASSES_ESTIMATES & ~PASSES_CORE)

/* zirr's cascades K (the parameter zirr.k) at most. */
#define EST_ZIRR_CASCADES_MAX 16

/* The estimators' parameters (docs/estimators.md, "Estimators"):
 * PARAM(type, field, name, default, lowest, highest), set per render as
 * --estimator-param <name>=<value> and written to the EXR metadata. An
 * integer c of -1 means floor(m / 4) sets. */
#define GMON_ESTIMATOR_PARAMS(PARAM)                                                                                   \
    PARAM(float, amon_alpha, "amon.alpha", 0.5f, 0, 1)                                                                 \
    PARAM(float, admon_alpha, "admon.alpha", 0.5f, 0, 1)                                                               \
    PARAM(float, gmon_binary_threshold, "gmon-binary.threshold", 0.25f, 0, 1)                                          \
    PARAM(float, gmon_partial_threshold, "gmon-partial.threshold", 0.25f, 0, 1)                                        \
    PARAM(float, gmon_partial_alpha, "gmon-partial.alpha", 0.5f, 0, 1)                                                 \
    PARAM(float, dmon_partial_threshold, "dmon-partial.threshold", 0.25f, 0, 1)                                        \
    PARAM(float, dmon_partial_alpha, "dmon-partial.alpha", 0.5f, 0, 1)                                                 \
    PARAM(int32_t, trimmed_c, "trimmed.c", -1, -1, 31)                                                                 \
    PARAM(int32_t, winsorized_c, "winsorized.c", -1, -1, 31)                                                           \
    PARAM(int32_t, gmedian_iterations, "gmedian.iterations", 16, 1, 1000)                                              \
    PARAM(float, huber_k, "huber.k", 1.0f, 0.5, 100)                                                                   \
    PARAM(float, clamp_sum_direct, "clamp-sum.direct", 0.0f, 0, INFINITY)                                              \
    PARAM(float, clamp_sum_indirect, "clamp-sum.indirect", 10.0f, 0, INFINITY)                                         \
    PARAM(int32_t, zirr_k, "zirr.k", 6, 2, EST_ZIRR_CASCADES_MAX)                                                      \
    PARAM(float, zirr_base, "zirr.base", 8.0f, 1.125, 1024)                                                            \
    PARAM(float, zirr_kappa, "zirr.kappa", 1.0f, 0.001, 1e6)                                                           \
    PARAM(float, zirr_emin, "zirr.emin", 0.05f, 0, INFINITY)

/* clamp's levels V (at most EST_CLAMP_LEVELS_MAX, each > 0, INFINITY
 * allowed), one image clamp-<V> each: the parameter clamp.levels, values
 * separated by ':' (default 1:10:100). */
#define EST_CLAMP_LEVELS_MAX 8

#define PARAM_FIELD_(type, field, name, value, lowest, highest) type field;
/* Plain 4-byte fields: the same layout as a kernel argument on every
 * device. */
typedef struct {
    GMON_ESTIMATOR_PARAMS(PARAM_FIELD_)
    int32_t clamp_level_count;
    float clamp_levels[EST_CLAMP_LEVELS_MAX];
} EstimatorParams;
#undef PARAM_FIELD_

/* The images of an estimation, one buffer of RGB planes: the passes in
 * `passes` by id, then (with_stderr) the standard error of each estimate
 * among them, by id. */
KERNEL_FN int pass_image_count(uint32_t passes, int with_stderr)
{
    return count_bits32(passes) + (with_stderr ? count_bits32(passes & PASSES_ESTIMATES) : 0);
}

/* The plane of pass `pass` (in `passes`). */
KERNEL_FN int pass_slot(uint32_t passes, int pass)
{
    return count_bits32(passes & (PASS_BIT(pass) - 1u));
}

/* The plane of the standard error of estimate `pass` (in `passes`). */
KERNEL_FN int stderr_slot(uint32_t passes, int pass)
{
    return count_bits32(passes) + count_bits32(passes & PASSES_ESTIMATES & (PASS_BIT(pass) - 1u));
}

#endif /* KERNELS_PASSES_H */
