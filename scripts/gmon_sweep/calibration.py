"""Calibration of gmonrt's per-pixel standard errors (--stderr): how often
the reference lies within 1.96 standard errors of each estimate.

Per scene (default cornell-glass and cornell-diffuse), one progressive render
with every estimator and its standard error (--estimators all --stderr) at
the reference's resolution and integrator, another seed, checkpoints at every
power of two up to the largest --spp: the checkpoint EXRs carry the .stderr
layers, so 64, 256 and 1024 spp come from the same samples. Then per scene,
spp and estimator, over every pixel and channel (estimate v, its standard
error s, reference r):
  coverage      the fraction with |v - r| <= 1.96 s (a NaN s covers nothing)
  median ratio  the median of |v - r| / s where s is not NaN (0 / 0 is 0)
  NaN stderr    the fraction with s NaN
  low           of the values not covered, the fraction with v < r (heavy
                tails and a darkening bias both show as a high share)
  RMSE          of v against r

What a perfect standard error would give. With m set means of equal counts
and normal noise, (v - truth) / s of the mean is Student's t with m - 1
degrees of freedom, so it covers P(|t_{m-1}| <= 1.96), 0.936 for m = 21, not
0.95. The reference is itself a mean of n_ref samples of the same integrator,
independent of the render's: v - r has the variance of v times
(1 + spp / n_ref), so the error over s is t_{m-1} * sqrt(1 + spp / n_ref):
  perfect coverage = P(|t_{m-1}| <= 1.96 / sqrt(1 + spp / n_ref))
  perfect median   = sqrt(1 + spp / n_ref) * (the 0.75 quantile of t_{m-1})
The robust estimators are biased: their error includes the bias, which a
spread over sets does not see, so they cover less. Skewed per-pixel noise
(fireflies, few samples per set) makes even the mean's s a poor fit to t.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy import stats

from . import crops, exr, references, renderer, sweep

ROOT = renderer.ROOT
Z = 1.96
SCENES = ("cornell-glass", "cornell-diffuse")
SPPS = (64, 256, 1024)
QUICK_SPPS = (32, 64)  # --quick: at least one sample in each of the default 21 sets


def calibration(estimate, stderr, reference):
    """{"coverage", "median_ratio", "nan_stderr", "low", "rmse"} of one
    estimate over every pixel and channel (module docstring)."""
    error = np.abs(estimate - reference)
    known = ~np.isnan(stderr)
    covered = known & (error <= Z * stderr)
    ratio = np.divide(error, stderr, out=np.where(error == 0, 0.0, np.inf), where=known & (stderr > 0))
    return {
        "coverage": float(np.mean(covered)),
        "median_ratio": float(np.median(ratio[known])) if known.any() else float("nan"),
        "nan_stderr": float(np.mean(~known)),
        "low": float(np.mean((estimate < reference)[~covered])) if not covered.all() else float("nan"),
        "rmse": float(np.sqrt(np.mean(error**2))),
    }


def perfect(sets, spp, reference_spp):
    """(coverage, median ratio) of a perfect standard error of the mean."""
    widening = np.sqrt(1 + spp / reference_spp)
    t = stats.t(sets - 1)
    return float(1 - 2 * t.sf(Z / widening)), float(widening * t.ppf(0.75))


def measure_file(path, reference):
    """(the file's M, {estimator: calibration()}) of every estimator in a
    render written with --stderr, in the file's order."""
    layers, header = exr.read(path)
    measured = {}
    for estimator in exr.estimators(header):
        if f"{estimator}.stderr" not in layers:
            raise ValueError(f"{path}: no {estimator}.stderr layer (render with --stderr)")
        measured[estimator] = calibration(layers[estimator], layers[f"{estimator}.stderr"], reference)
    return int(header["gmon.sets"]), measured


def render(gmonrt, scene, run_dir, spps, resolution, seed, integrator, sets):
    """One render with checkpoints up to max(spps); returns (command line,
    wall-clock seconds)."""
    run_dir.mkdir(parents=True, exist_ok=True)
    for old in [*run_dir.glob("spp-*.exr"), run_dir / "checkpoints.csv"]:  # gmonrt appends to the CSV
        old.unlink(missing_ok=True)
    arguments = [scene, "--spp", max(spps), "--checkpoints", run_dir, "--estimators", "all", "--stderr",
                 "--sets", sets, "--resolution", resolution, "--seed", seed, "--integrator", integrator, "--quiet",
                 "--outfile", run_dir / "final.exr"]
    seconds = renderer.run(gmonrt, arguments)
    return renderer.command_line(arguments), seconds


def calibrate_scene(args, scene_path):
    """Rows (scene, spp, sets, reference_spp, residual_rmse, estimator and
    calibration()) of one scene, the command run and its seconds."""
    scene = crops.scene_name(scene_path)
    reference_path = args.references / f"{scene}.exr"
    reference, record = references.load(reference_path)
    if not record:
        raise SystemExit(f"{reference_path}: no .json record beside it (its sample count is needed)")
    if record["seed"] == args.seed:
        raise SystemExit(f"--seed {args.seed} is the reference's seed: its samples would not be independent")
    height, width, _ = reference.shape
    run_dir = args.out / scene
    command, seconds = render(args.gmonrt, scene_path, run_dir, args.spp, f"{width}x{height}", args.seed,
                              record["integrator"], args.sets)
    rows = []
    for spp in args.spp:
        path = sweep.checkpoint_path(run_dir, spp)
        if not path.exists():
            raise SystemExit(f"{path}: no checkpoint at {spp} spp (checkpoints are at powers of two)")
        sets, measured = measure_file(path, reference)
        for estimator, values in measured.items():
            rows.append({"scene": scene, "spp": spp, "sets": sets, "reference_spp": record["spp"],
                         "residual_rmse": record["residual"]["image"]["rmse"], "estimator": estimator, **values})
    return rows, command, seconds


def expectations_table(rows):
    """Per scene and spp: the reference, what a perfect standard error of the
    mean gives, and the reference's share of the mean's squared error."""
    out = ["| scene | spp | M | reference spp | perfect coverage | perfect median ratio | reference residual "
           "RMSE | its share of the mean's MSE |", "| --- " * 8 + "|"]
    for r in rows:
        if r["estimator"] == "mean":
            coverage, median = perfect(r["sets"], r["spp"], r["reference_spp"])
            share = r["residual_rmse"] ** 2 / r["rmse"] ** 2
            out.append(f"| {r['scene']} | {r['spp']} | {r['sets']} | {r['reference_spp']} | {coverage:.3f} | "
                       f"{median:.3f} | {r['residual_rmse']:.4g} | {share:.1%} |")
    return out


def long_table(rows):
    out = ["| scene | spp | estimator | coverage | median abs(error) / stderr | NaN stderr | uncovered below the "
           "reference | RMSE |", "| --- " * 8 + "|"]
    for r in rows:
        out.append(f"| {r['scene']} | {r['spp']} | {r['estimator']} | {r['coverage']:.3f} | "
                   f"{r['median_ratio']:.3f} | {r['nan_stderr']:.2%} | {r['low']:.0%} | {r['rmse']:.4g} |")
    return out


def pivot_table(rows, key, digits=3):
    """Estimators down, scene and spp across: one value (`key`) per cell."""
    columns = list(dict.fromkeys((r["scene"], r["spp"]) for r in rows))
    cells = {(r["estimator"], r["scene"], r["spp"]): r[key] for r in rows}
    out = ["| estimator | " + " | ".join(f"{scene} {spp}" for scene, spp in columns) + " |",
           "| --- " * (len(columns) + 1) + "|"]
    for estimator in dict.fromkeys(r["estimator"] for r in rows):
        out.append(f"| {estimator} | " + " | ".join(f"{cells[(estimator, *c)]:.{digits}f}" for c in columns) + " |")
    return out


def report(rows, commands, seconds, total_seconds):
    out = ["Standard errors: measured calibration (`gmon_sweep.calibration`).", "",
           "What a perfect standard error of the mean would give, P(|t_(M-1)| <= 1.96 / sqrt(1 + spp / reference "
           "spp)), and the reference's own noise:", "", *expectations_table(rows), "",
           "Coverage (fraction of pixel-channel values with |estimate - reference| <= 1.96 stderr):", "",
           *pivot_table(rows, "coverage"), "",
           "Median of |estimate - reference| / stderr:", "", *pivot_table(rows, "median_ratio"), "",
           "Every value:", "", *long_table(rows), "",
           "Commands (" + ", ".join(f"{s:.0f} s" for s in seconds) + f" of rendering; {total_seconds:.0f} s in all):",
           "", "```sh", *commands, "```"]
    return "\n".join(out)


def spp_list(text):
    values = sweep.positive_list(text)
    if any(v & (v - 1) for v in values):
        raise argparse.ArgumentTypeError(f"'{text}': checkpoints are at powers of two only")
    return values


def main(argv=None):
    p = argparse.ArgumentParser(prog="stderr-calibration.sh", description=__doc__.split("\n\n")[0])
    p.add_argument("scenes", nargs="*", type=Path,
                   help="scene files with a reference (default scenes/cornell-glass.pbrt scenes/cornell-diffuse.pbrt)")
    p.add_argument("--spp", type=spp_list, default=list(SPPS), help="powers of two (default 64,256,1024)")
    p.add_argument("--quick", action="store_true", help=f"--spp {','.join(map(str, QUICK_SPPS))} (for tests)")
    p.add_argument("--sets", type=int, default=21, help="M (default 21)")
    p.add_argument("--seed", type=int, default=0, help="seed (default 0; not the references')")
    p.add_argument("--references", type=Path, default=ROOT / "references",
                   help="directory of <scene>.exr and .json (default references/)")
    p.add_argument("--out", type=Path, default=ROOT / "build" / "calibration",
                   help="where the renders go (default build/calibration/)")
    p.add_argument("--gmonrt", type=Path, default=renderer.GMONRT, help="default build/gmonrt")
    args = p.parse_args(argv)
    if args.quick:
        args.spp = list(QUICK_SPPS)
    renderer.pocl_cache(ROOT / "build" / "pocl-cache")
    scenes = args.scenes or [ROOT / "scenes" / f"{name}.pbrt" for name in SCENES]
    start = time.monotonic()
    rows, commands, seconds = [], [], []
    for scene_path in scenes:
        scene_rows, command, scene_seconds = calibrate_scene(args, scene_path)
        rows += scene_rows
        commands.append(command)
        seconds.append(scene_seconds)
        print(f"{crops.scene_name(scene_path)}: rendered in {scene_seconds:.0f} s", file=sys.stderr)
    print(report(rows, commands, seconds, time.monotonic() - start))
    return rows


if __name__ == "__main__":
    main()
