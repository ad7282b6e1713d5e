#!/usr/bin/env python3
"""gmonrt's samplers compared on one scene: the variance of the mean, the
honesty of the reported standard error, MoN's and G-MoN's error and the time
of a render (the table of docs/sampling.md, "Why sobol-sets is the default").

    scripts/compare-samplers.sh ../shared/scenes/cornell-box/cornell-box.pbrt --resolution 64x64 --spp 64
    scripts/compare-samplers.sh scenes/cornell-glass.pbrt --samplers independent,sobol-sets --seeds 8 --csv build/samplers.csv
    scripts/compare-samplers.sh SCENE --gmonrt-args "--integrator nee" --keep build/sampler-renders

Every sampler of --samplers (gmonrt's --sampler) renders the scene with
seeds 1..N (--seeds, default 4), all at the same --spp, --resolution and
--sets, each with `--stderr --estimators mean,mon,gmon`, in the scene's
folder (scenes include files by relative paths). The renders alternate
between the samplers (seed 1 of each sampler, then seed 2, ...) so that they
share the machine's conditions; an untimed warm-up render of each sampler
(8x8 pixels, 1 spp) first has PoCL build and cache its kernels, which differ
between samplers.

The figures (the statistics functions below; tests/python/test_compare_samplers.py):
- var(mean): the variance of the mean image (EXR channel `mean`): per pixel
  and channel across the N seeds (unbiased, ddof=1), averaged over the image
  (pixels and R, G, B). "x first": over the first sampler's (<1: less noise).
- var/stderr^2: var(mean) over the mean (seeds, pixels, channels) of the
  squared `mean.stderr`, gmonrt's standard error of the mean from the spread
  of the M set means. 1 when the reported uncertainty is honest; below 1 the
  standard errors are too large (sets negatively correlated, as sobol-pixel's
  are), above 1 too small. With few seeds it is itself noisy: var(mean) has
  N-1 degrees of freedom a pixel, and scenes with fireflies spread it more.
- MoN MSE, G-MoN MSE: the mean over the seeds of the squared difference of
  the `mon` (`gmon`) image from the reference, averaged over the image. The
  reference is the mean image of all renders (every sampler, every seed),
  the best estimate at hand of the converged image; "mean MSE" is the same
  for the `mean` image, the baseline MoN and G-MoN trade bias against (it is
  slightly low, as each render is part of the reference).
- time: wall seconds of one render (the mean over the seeds; scene load
  included, kernel builds not: see the warm-up above).

Exit status: 0; 1 when a render fails (or comes back with another sampler
than asked, e.g. through --gmonrt-args); 2 for a bad command line or a
missing scene, gmonrt binary or virtual environment.
"""

import argparse
import csv
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

try:
    import numpy as np
except ImportError:  # pragma: no cover
    sys.exit("compare_samplers.py: numpy is missing: run it with scripts/compare-samplers.sh "
             "(or build/venv/bin/python after scripts/python-env.sh)")

ROOT = Path(__file__).resolve().parents[1]
SAMPLERS = "independent,sobol-pixel,sobol-sets"
ESTIMATORS = ("mean", "mon", "gmon")  # the channels read back, besides mean.stderr
WARMUP = ("--resolution", "8x8", "--spp", "1")


# ---------------------------------------------------------------- statistics

def variance_of_mean(means):
    """Variance of the mean image across seeds: `means` is N x H x W (x C),
    one image per seed (N >= 2). The unbiased (ddof=1) variance of each
    pixel and channel across the seeds, averaged over the image."""
    means = np.asarray(means, dtype=np.float64)
    if means.shape[0] < 2:
        raise ValueError(f"the variance across seeds needs at least 2 seeds, got {means.shape[0]}")
    return float(means.var(axis=0, ddof=1).mean())


def mean_squared_stderr(stderrs):
    """Mean of the squared standard errors (N x H x W (x C)) over the seeds,
    pixels and channels: the variance of the mean the renders report."""
    stderrs = np.asarray(stderrs, dtype=np.float64)
    return float(np.mean(stderrs * stderrs))


def stderr_ratio(means, stderrs):
    """var(mean) / mean(stderr^2): 1 when the standard errors are honest,
    <1 when too large, >1 when too small (NaN when nothing is reported,
    inf when only the variance is nonzero)."""
    variance, reported = variance_of_mean(means), mean_squared_stderr(stderrs)
    if reported > 0:
        return variance / reported
    return math.inf if variance > 0 else math.nan


def reference_image(images):
    """The reference: the mean of every render's mean image (any number of
    H x W (x C) images, all samplers and seeds together)."""
    images = [np.asarray(i, dtype=np.float64) for i in images]
    if not images:
        raise ValueError("no image to average")
    return np.mean(images, axis=0)


def mean_squared_error(images, reference):
    """The mean over `images` (N x H x W (x C)) of each one's squared
    difference from `reference`, averaged over the image."""
    d = np.asarray(images, dtype=np.float64) - np.asarray(reference, dtype=np.float64)
    return float(np.mean(d * d))


def compare(renders, order=None):
    """Every figure, one dict a sampler (see the module's docstring).
    `renders`: sampler -> a list (one per seed) of dicts with the channels
    'mean', 'mean.stderr', 'mon', 'gmon' (H x W (x C) arrays) and 'seconds';
    `order`: the samplers in the order printed, the first the baseline of
    "x first" (default: the dict's order)."""
    order = list(order or renders)
    reference = reference_image([r["mean"] for s in order for r in renders[s]])
    rows, baseline = [], None
    for sampler in order:
        seeds = renders[sampler]
        stack = {name: np.array([r[name] for r in seeds], dtype=np.float64)
                 for name in ESTIMATORS + ("mean.stderr",)}
        variance = variance_of_mean(stack["mean"])
        if baseline is None:
            baseline = variance
        relative = variance / baseline if baseline > 0 else (math.inf if variance > 0 else math.nan)
        rows.append({
            "sampler": sampler,
            "seeds": len(seeds),
            "image_mean": float(stack["mean"].mean()),
            "var_mean": variance,
            "var_relative": float(relative),
            "stderr2": mean_squared_stderr(stack["mean.stderr"]),
            "var_over_stderr2": stderr_ratio(stack["mean"], stack["mean.stderr"]),
            "mse_mean": mean_squared_error(stack["mean"], reference),
            "mse_mon": mean_squared_error(stack["mon"], reference),
            "mse_gmon": mean_squared_error(stack["gmon"], reference),
            "seconds": float(np.mean([r["seconds"] for r in seeds])),
        })
    return rows, reference


# ---------------------------------------------------------------- renders

class RenderError(RuntimeError):
    pass


def read_render(path):
    """The channels of a gmonrt EXR that compare() reads (float64 arrays,
    H x W x 3) and its header's gmon.sampler."""
    import OpenEXR
    with OpenEXR.File(str(path)) as exr:
        part = exr.parts[0]
        channels = part.channels
        missing = [n for n in ESTIMATORS + ("mean.stderr",) if n not in channels]
        if missing:
            raise RenderError(f"{path} lacks {', '.join(missing)} (it has: {', '.join(sorted(channels))})")
        out = {n: np.array(channels[n].pixels, dtype=np.float64) for n in ESTIMATORS + ("mean.stderr",)}
        out["sampler"] = str(part.header.get("gmon.sampler", ""))
    return out


def gmonrt_command(args, scene, sampler, seed, outfile, settings):
    return [args.gmonrt, scene.name, "--quiet", "--sampler", sampler, "--seed", seed, "--sets", args.sets,
            *settings, "--stderr", "--estimators", ",".join(ESTIMATORS), "--outfile", outfile,
            *shlex.split(args.gmonrt_args)]


def run(command, cwd):
    """Runs a command, returns its wall seconds; RenderError with the end of
    its output when it fails."""
    command = [str(c) for c in command]
    start = time.monotonic()
    done = subprocess.run(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.monotonic() - start
    if done.returncode != 0:
        tail = "\n".join((done.stderr.strip() or done.stdout.strip()).splitlines()[-15:])
        raise RenderError(f"(in {cwd}) {shlex.join(command)} failed (exit {done.returncode}):\n{tail}")
    return seconds


def render_all(args, samplers, workdir, say):
    """Warm-up renders, then seeds 1..N of every sampler, alternating; returns
    sampler -> list of read_render() dicts with 'seconds'."""
    scene = args.scene.resolve()
    settings = ("--resolution", args.resolution, "--spp", args.spp)
    for sampler in samplers:
        say(f"  warm-up {sampler} ...")
        seconds = run(gmonrt_command(args, scene, sampler, 1, workdir / f"warmup-{sampler}.exr", WARMUP), scene.parent)
        say(f" {seconds:.1f} s\n")
    renders = {s: [] for s in samplers}
    for seed in range(1, args.seeds + 1):
        for sampler in samplers:
            outfile = workdir / f"{scene.stem}-{sampler}-seed{seed}.exr"
            say(f"  {sampler} seed {seed} ...")
            seconds = run(gmonrt_command(args, scene, sampler, seed, outfile, settings), scene.parent)
            say(f" {seconds:.2f} s\n")
            render = read_render(outfile)
            if render["sampler"] != sampler:
                raise RenderError(f"{outfile} was rendered with sampler '{render['sampler']}', not '{sampler}' "
                                  "(does --gmonrt-args set --sampler?)")
            render["seconds"] = seconds
            renders[sampler].append(render)
    return renders


# ---------------------------------------------------------------- output

COLUMNS = ["scene", "resolution", "spp", "sets", "seeds", "gmonrt_args", "sampler", "image_mean", "var_mean",
           "var_relative", "stderr2", "var_over_stderr2", "mse_mean", "mse_mon", "mse_gmon", "seconds"]


def fmt(x, digits=3):
    if isinstance(x, float):
        if math.isnan(x):
            return "-"
        if math.isinf(x):
            return "inf"
        return f"{x:.{digits}g}"
    return str(x)


def table(rows):
    first = rows[0]["sampler"] if rows else ""
    head = ["sampler", "var(mean)", f"x {first}", "var/stderr^2", "MoN MSE", "G-MoN MSE", "mean MSE", "time"]
    body = [[r["sampler"], f"{r['var_mean']:.3e}", fmt(r["var_relative"]), fmt(r["var_over_stderr2"]),
             f"{r['mse_mon']:.3e}", f"{r['mse_gmon']:.3e}", f"{r['mse_mean']:.3e}", f"{r['seconds']:.2f} s"]
            for r in rows]
    widths = [max(len(row[i]) for row in [head] + body) for i in range(len(head))]
    lines = ["  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths)))
             for row in [head] + body]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


LEGEND = """\
var(mean): variance of the mean image per pixel and channel across the seeds (ddof=1), averaged over the image;
  x FIRST: relative to the first sampler's (<1: less noise)
var/stderr^2: var(mean) over the mean squared mean.stderr: 1 when the reported standard errors are honest,
  <1 too large, >1 too small (noisy with few seeds)
MoN, G-MoN, mean MSE: squared error against the mean of all renders (every sampler and seed), averaged over
  the image and the seeds
time: wall seconds of one render (mean over the seeds; scene load included, kernel builds not)"""


# ---------------------------------------------------------------- main

def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=LEGEND)
    p.add_argument("scene", type=Path, help="the scene file (rendered in its folder)")
    p.add_argument("--samplers", default=SAMPLERS, help=f"comma-separated gmonrt samplers, the first the baseline (default {SAMPLERS})")
    p.add_argument("--seeds", type=int, default=4, help="renders of each sampler, seeds 1..N (default 4; at least 2)")
    p.add_argument("--spp", type=int, default=64, help="samples per pixel of each render (default 64)")
    p.add_argument("--resolution", default="128x128", help="WxH of each render (default 128x128)")
    p.add_argument("--sets", type=int, default=21, help="gmonrt's --sets M (default 21)")
    p.add_argument("--gmonrt", type=Path, default=ROOT / "build" / "gmonrt", help="gmonrt binary (default build/gmonrt)")
    p.add_argument("--gmonrt-args", default="", help='extra gmonrt arguments, e.g. "--integrator nee"')
    p.add_argument("--csv", type=Path, help="also write the figures to this CSV file")
    p.add_argument("--keep", type=Path, help="keep the renders (EXR and PNG previews) in this folder")
    # argparse takes a value beginning with "--" for a flag: join the pass-through to its flag first
    joined, i = [], 0
    while i < len(argv):
        if argv[i] == "--gmonrt-args" and i + 1 < len(argv):
            joined.append(f"--gmonrt-args={argv[i + 1]}")
            i += 2
        else:
            joined.append(argv[i])
            i += 1
    args = p.parse_args(joined)
    args.sampler_list = [s for s in args.samplers.split(",") if s]
    if not args.sampler_list:
        p.error("--samplers names no sampler")
    if len(set(args.sampler_list)) != len(args.sampler_list):
        p.error("--samplers names a sampler twice")
    if args.seeds < 2:
        p.error("--seeds must be at least 2 (the variance across seeds)")
    if args.spp < 1:
        p.error("--spp must be at least 1")
    if not re.fullmatch(r"[1-9]\d*x[1-9]\d*", args.resolution):
        p.error(f"--resolution must be WxH, e.g. 64x64, not '{args.resolution}'")
    if args.sets < 1:
        p.error("--sets must be at least 1")
    try:
        shlex.split(args.gmonrt_args)
    except ValueError as e:
        p.error(f"--gmonrt-args: {e}")
    return args


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    say = lambda text: (sys.stderr.write(text), sys.stderr.flush())  # noqa: E731
    try:
        import OpenEXR  # noqa: F401
    except ImportError as e:
        print(f"compare_samplers.py: {e}: run it with scripts/compare-samplers.sh, which sets up build/venv", file=sys.stderr)
        return 2
    if not os.access(args.gmonrt, os.X_OK):
        print(f"compare_samplers.py: no gmonrt at {args.gmonrt}: run scripts/build.sh (or pass --gmonrt)", file=sys.stderr)
        return 2
    args.gmonrt = args.gmonrt.resolve()  # the renders run in the scene's folder
    if not args.scene.is_file():
        print(f"compare_samplers.py: no scene file {args.scene}", file=sys.stderr)
        return 2
    if not os.environ.get("POCL_CACHE_DIR"):  # PoCL shows no device without one
        os.environ["POCL_CACHE_DIR"] = str(ROOT / "build" / "pocl-cache")
    os.makedirs(os.environ["POCL_CACHE_DIR"], exist_ok=True)

    with tempfile.TemporaryDirectory(prefix="compare-samplers-") as temporary:
        workdir = (args.keep or Path(temporary)).resolve()
        workdir.mkdir(parents=True, exist_ok=True)
        try:
            renders = render_all(args, args.sampler_list, workdir, say)
        except RenderError as e:
            say("\n")
            print(f"compare_samplers.py: {e}", file=sys.stderr)
            return 1
    rows, reference = compare(renders, args.sampler_list)

    total = args.seeds * len(args.sampler_list)
    print(f"{args.scene}, {args.resolution}, {args.spp} spp, M = {args.sets} sets, seeds 1-{args.seeds}, "
          f"gmonrt {args.gmonrt_args or '(default flags)'}; reference: the mean of all {total} renders "
          f"(image mean {reference.mean():.4g})")
    print(table(rows))
    print()
    print(LEGEND.replace("FIRST", args.sampler_list[0]))
    if args.csv:
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
            writer.writeheader()
            for r in rows:
                r.update(scene=str(args.scene), resolution=args.resolution, spp=args.spp, sets=args.sets,
                         gmonrt_args=args.gmonrt_args)
                writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})
        print(f"wrote {args.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
