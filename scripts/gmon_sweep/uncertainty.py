"""Error you can trust: the reference's own noise taken out of the error
(debiased metrics), and intervals over independent seeds.

Debiasing. An estimate x and a reference r rendered with independent seeds
have E[(x - r)^2] = E[(x - truth)^2] + Var(r) per pixel and channel, so
    MSE_debiased    = mean((x - r)^2) - mean(v)
    relMSE_debiased = mean(((x - r)^2 - v) / (r^2 + 0.01))
with v an unbiased per-pixel estimate of Var(r). v comes from the
reference's set means: groups g (the sets of one or more renders of
disjoint sample ranges) with counts n_g, means t_g and n = sum n_g samples
in all make r = sum n_g t_g / n, whose variance is sigma^2 / n, and
sum n_g (t_g - r)^2 has expectation (G - 1) sigma^2 whatever the counts, so
    v = sum_g n_g (t_g - r)^2 / ((G - 1) n)
(sample variance of the set means / M for equal counts). Without sets, the
reference's two halves A and B give v = (A - B)^2 / 4 per pixel, and a
reference JSON record only their averages over each region (its residual
RMSE squared and relMSE). The debiased value's own 95% interval is Student's
t over the pixels of the region (the terms averaged over channels: the
channels of one pixel share paths, pixels do not); a value whose interval
includes 0 cannot be told from no error at all. SSIM and FLIP are not sums
of squared errors and have no such correction: they stay as measured.

Seeds. A configuration rendered with S seeds gives S values of every metric:
their mean and a 95% interval, mean +- t_{0.975, S-1} sd / sqrt(S). An
estimator's error ratio to the mean is taken per seed (the two estimates
share that render's samples, so the samples' luck cancels), then averaged
over seeds with the same interval; an estimator is called better (or worse)
only when that interval excludes 1.
"""

import math

import numpy as np
from scipy import stats

from . import exr, metrics

LEVEL = 0.95


def t_interval(values):
    """(mean, low, high): the mean of `values` and its 95% Student t
    interval; low and high NaN with fewer than two values or any NaN."""
    values = np.asarray(values, dtype=np.float64)
    if values.size == 0:
        return math.nan, math.nan, math.nan
    mean = float(np.mean(values))
    if values.size < 2 or not np.all(np.isfinite(values)):
        return mean, math.nan, math.nan
    half = float(stats.t.ppf(0.5 + LEVEL / 2, values.size - 1) * np.std(values, ddof=1) / math.sqrt(values.size))
    return mean, mean - half, mean + half


# --- The reference's variance from its sets ---


def set_counts(first_sample, samples, sets):
    """Samples of each set j in the range [first_sample, first_sample +
    samples): sample s goes to set s mod M (docs/estimators.md, "Sets")."""

    def below(end, j):  # samples s < end with s mod M == j
        return (end - j + sets - 1) // sets if end > j else 0

    return np.array([below(first_sample + samples, j) - below(first_sample, j) for j in range(sets)])


def set_sums(channels, header):
    """(sums, counts): set j's exact sums as float64 (M x height x width x 3)
    and its sample count, from the sets.* channels of a render written with
    --write-sets (layout: host/io/exr_image.h); None when it has none."""
    sets = int(header.get("gmon.sets", 0))
    if sets < 1 or "sets.0.R.w0" not in channels:
        return None
    if "sets.grid" in channels:
        grid = channels["sets.grid"].astype(np.int64)
        # Grid word 0: no nonzero sample, every sum 0 (any unit will do).
        unit = np.where(grid == 0, 0.0, np.ldexp(1.0, (grid - 1024).clip(-1074, 1023).astype(np.int32)))
    else:
        unit = np.full(channels["sets.0.R.w0"].shape, 2.0**-56)
    sums = np.empty((sets, *unit.shape, 3))
    for j in range(sets):
        for c, name in enumerate(exr.CHANNELS):
            words = [channels[f"sets.{j}.{name}.w{k}"] for k in range(4)]
            # A signed 128-bit integer, w3 holding the sign: float64 keeps
            # its top 53 bits, ample for a variance.
            value = words[3].view(np.int32).astype(np.float64)
            for word in (words[2], words[1], words[0]):
                value = value * 2.0**32 + word.astype(np.float64)
            sums[j, ..., c] = value * unit
    counts = set_counts(int(header.get("gmon.firstSample", 0)), int(header["gmon.samples"]), sets)
    return sums, counts


def variance_from_sets(parts):
    """v, the variance of the mean of every sample, per pixel and channel,
    from `parts`: (sums, counts) of renders of disjoint sample ranges (e.g.
    the two halves of a reference), their sets pooled as groups."""
    sums = np.concatenate([s for s, _ in parts])
    counts = np.concatenate([c for _, c in parts]).astype(np.float64)
    keep = counts > 0
    sums, counts = sums[keep], counts[keep]
    if len(counts) < 2:
        raise ValueError("the variance of a mean needs at least two sets with samples")
    total = counts.sum()
    shape = (-1,) + (1,) * (sums.ndim - 1)
    means = sums / counts.reshape(shape)
    mean = sums.sum(axis=0) / total
    spread = np.sum(counts.reshape(shape) * (means - mean) ** 2, axis=0)
    return spread / ((len(counts) - 1) * total)


def read_set_sums(path):
    """set_sums() of an EXR file, reading every channel."""
    channels, header = exr.read_channels(path)
    return set_sums(channels, header)


def variance_from_halves(half_a, half_b):
    """v per pixel and channel from two independent halves of equal counts:
    E[(A - B)^2] = 2 Var(A) and Var((A + B) / 2) = Var(A) / 2."""
    return (half_a - half_b) ** 2 / 4


class ReferenceNoise:
    """What is known of a reference's own variance: per pixel (`variance`,
    height x width x 3) or only as averages over each region (`floors`, a
    reference record's residual: {region: {"rmse", "relmse"}}); `source`
    says which ("sets", "halves", or "" when nothing is known)."""

    def __init__(self, variance=None, floors=None, source=""):
        self.variance, self.floors, self.source = variance, floors or {}, source

    @classmethod
    def of_reference(cls, path, record):
        """The noise of a reference file: its sets.* channels (a gmonrt render
        written with --write-sets), else its `variance` layer (references.py
        derives it from the sets of its halves), else its record's residual
        (from the halves' difference), else nothing."""
        channels, header = exr.read_channels(path)
        parsed = set_sums(channels, header)
        if parsed is not None:
            return cls(variance_from_sets([parsed]), source="sets")
        layers, _ = exr.read(path)
        if "variance" in layers:
            return cls(layers["variance"], source=str(header.get("gmon.varianceSource", "sets")))
        if record and record.get("residual"):
            return cls(floors=record["residual"], source="halves")
        return cls()


def _pixel_interval(terms, correction=0.0, correction_variance=0.0):
    """(value, low, high) of mean(terms) - correction: per-pixel terms
    (already averaged over channels), Student t over the pixels;
    `correction_variance` adds the variance of a correction known only as an
    average."""
    terms = terms.reshape(-1)
    value = float(np.mean(terms)) - correction
    if terms.size < 2:
        return value, math.nan, math.nan
    half = float(stats.t.ppf(0.5 + LEVEL / 2, terms.size - 1)) * math.sqrt(
        float(np.var(terms, ddof=1)) / terms.size + correction_variance)
    return value, value - half, value + half


def debiased(image, reference, noise, region=None, name="image"):
    """{"mse", "mse_debiased", "mse_debiased_lo", "mse_debiased_hi",
    "mse_debiased_includes_zero", and the same for relmse} of `image` on one
    region (`name` its key in noise.floors); the debiased fields are None when
    the reference's noise is unknown."""
    x, r = metrics.crop(image, region), metrics.crop(reference, region)
    squared = (x - r) ** 2
    weight = 1.0 / (r**2 + metrics.RELMSE_EPSILON)
    result = {"mse": float(np.mean(squared))}
    pixels = squared.shape[0] * squared.shape[1]
    if noise.variance is not None:
        v = metrics.crop(noise.variance, region)
        mse = _pixel_interval((squared - v).mean(axis=-1))
        rel = _pixel_interval(((squared - v) * weight).mean(axis=-1))
    elif name in noise.floors:
        # Only the halves' averages: a per-pixel (A - B)^2 / 4 has one degree
        # of freedom (variance 2 v^2 for normal noise), so its average over
        # the region adds about 2 floor^2 / pixels to the variance.
        floor_mse, floor_rel = noise.floors[name]["rmse"] ** 2, noise.floors[name]["relmse"]
        mse = _pixel_interval(squared.mean(axis=-1), floor_mse, 2 * floor_mse**2 / pixels)
        rel = _pixel_interval((squared * weight).mean(axis=-1), floor_rel, 2 * floor_rel**2 / pixels)
    else:
        mse = rel = (None, None, None)
    for key, (value, low, high) in (("mse", mse), ("relmse", rel)):
        result[f"{key}_debiased"], result[f"{key}_debiased_lo"], result[f"{key}_debiased_hi"] = value, low, high
        result[f"{key}_debiased_includes_zero"] = includes_zero(low, high) if value is not None else None
    return result


def includes_zero(low, high):
    """1 when the interval [low, high] includes 0 (or is unknown), else 0."""
    return int(not (low > 0 or high < 0))


# --- Over seeds ---


def ratio(error, mean_error):
    """An error over the mean's of the same samples; equal errors give
    exactly 1 (the mean against itself), a zero or missing mean's NaN."""
    if error is None or mean_error is None:
        return math.nan
    if error == mean_error:
        return 1.0
    return error / mean_error if mean_error != 0 else math.nan


def time_to_reach(curve, target, key):
    """Seconds at which `curve` (rows by rising spp) first gets to `target` in
    `key`, interpolated linearly in log(time) against log(error) between the
    two checkpoints around the crossing; None if it never does."""
    for before, after in zip([None] + curve[:-1], curve):
        if after[key] <= target:
            if before is None or after[key] == before[key] or after[key] == target:
                return after["seconds"]
            fraction = math.log(before[key] / target) / math.log(before[key] / after[key])
            return math.exp(math.log(before["seconds"]) + fraction * math.log(after["seconds"] / before["seconds"]))
    return None


def verdict(low, high):
    """"better" when the ratio's interval lies below 1, "worse" above it,
    else "undecided" (the interval includes 1 or is unknown)."""
    if high < 1:
        return "better"
    if low > 1:
        return "worse"
    return "undecided"


# Columns of summary.csv: one row per M, estimator, checkpoint and region,
# every metric as its mean over seeds and 95% interval, then the paired ratios
# to the mean of the same samples.
SUMMARY_METRICS = ("seconds", "rmse", "relmse", "ssim", "flip", "rel_bias", "mse", "mse_debiased", "relmse_debiased")
RATIO_METRICS = ("mse", "mse_debiased", "relmse", "relmse_debiased", "flip")
SUMMARY_COLUMNS = (
    ("scene", "sets", "estimator", "spp", "region", "seeds")
    + tuple(f"{m}{suffix}" for m in SUMMARY_METRICS for suffix in ("", "_lo", "_hi"))
    + ("mse_debiased_includes_zero", "relmse_debiased_includes_zero")
    + tuple(f"{m}{suffix}" for m in RATIO_METRICS for suffix in ("_ratio", "_ratio_lo", "_ratio_hi", "_verdict"))
)
# Columns of reach.csv: per M and estimator, the time to reach the mean's
# error at its last checkpoint over the mean's time to get there.
REACH_METRICS = ("rmse", "relmse")
REACH_COLUMNS = ("scene", "sets", "estimator", "metric", "seeds", "reached", "time_ratio", "time_ratio_lo",
                 "time_ratio_hi")


def _by(rows, *keys):
    grouped = {}
    for row in rows:
        grouped.setdefault(tuple(row[k] for k in keys), []).append(row)
    return grouped


def summarise(rows):
    """summary.csv's rows from sweep rows of one or more seeds: only the
    seeds that reached a checkpoint count for it (a --time budget may stop
    one seed earlier than another)."""
    means = {(r["sets"], r["seed"], r["spp"], r["region"]): r for r in rows if r["estimator"] == "mean"}
    out = []
    for (scene, sets, estimator, spp, region), group in _by(rows, "scene", "sets", "estimator", "spp",
                                                             "region").items():
        summary = {"scene": scene, "sets": sets, "estimator": estimator, "spp": spp, "region": region,
                   "seeds": len(group)}
        for metric in SUMMARY_METRICS:
            values = [r[metric] for r in group]
            if any(v is None for v in values):
                summary.update({metric: None, f"{metric}_lo": None, f"{metric}_hi": None})
                continue
            summary[metric], summary[f"{metric}_lo"], summary[f"{metric}_hi"] = t_interval(values)
        for metric in ("mse_debiased", "relmse_debiased"):
            if len(group) == 1:  # no spread over seeds: the render's own interval over pixels
                for suffix in ("_lo", "_hi", "_includes_zero"):
                    summary[f"{metric}{suffix}"] = group[0].get(f"{metric}{suffix}")
            elif summary[metric] is not None:
                summary[f"{metric}_includes_zero"] = includes_zero(summary[f"{metric}_lo"], summary[f"{metric}_hi"])
            else:
                summary[f"{metric}_includes_zero"] = None
        for metric in RATIO_METRICS:
            paired = [ratio(r[metric], means[(sets, r["seed"], spp, region)][metric])
                      if (sets, r["seed"], spp, region) in means else math.nan for r in group]
            value, low, high = t_interval(paired)
            summary.update({f"{metric}_ratio": value, f"{metric}_ratio_lo": low, f"{metric}_ratio_hi": high,
                            f"{metric}_verdict": verdict(low, high)})
        out.append(summary)
    return out


def reach(rows):
    """reach.csv's rows: per M, estimator and metric (REACH_METRICS), and
    per seed, the time the estimator takes to reach the mean's error at the
    mean's last checkpoint over the mean's time to that checkpoint; the mean
    and interval over seeds when every seed reached it (`reached` counts
    those that did)."""
    curves = {key: sorted(line, key=lambda r: r["spp"])
              for key, line in _by([r for r in rows if r["region"] == "image"], "sets", "seed", "estimator").items()}
    out = []
    scene = rows[0]["scene"] if rows else ""
    for sets, estimator in dict.fromkeys((s, e) for s, _, e in curves):
        seeds = [seed for s, seed, e in curves if s == sets and e == estimator]
        for metric in REACH_METRICS:
            fractions = []
            for seed in seeds:
                final = curves[(sets, seed, "mean")][-1]
                seconds = time_to_reach(curves[(sets, seed, estimator)], final[metric], metric)
                if seconds is not None:
                    fractions.append(seconds / final["seconds"])
            value, low, high = t_interval(fractions) if len(fractions) == len(seeds) else (None, None, None)
            out.append({"scene": scene, "sets": sets, "estimator": estimator, "metric": metric, "seeds": len(seeds),
                        "reached": len(fractions), "time_ratio": value, "time_ratio_lo": low,
                        "time_ratio_hi": high})
    return out
