"""Convergence sweep of one scene: error against samples per pixel and
wall-clock time, for the mean and the other estimators of the same samples
(--estimators; default gmonrt's: mean, MoN and G-MoN).

Design: one progressive render per M and seed (`gmonrt --checkpoints`;
--seeds S independent seeds, default 4, for intervals over seeds). The renderer
stops at every power of two up to --max-spp (and at --max-spp itself), writes
the estimates of the samples so far and records its wall-clock time to
that point (estimators included, file writing excluded) and, given the
reference, each estimator's RMSE and relMSE. Nothing is rendered twice for
one M; the mean is the same for every M up to float rounding (the samples do
not depend on M), only its time differs. This script then measures every
checkpoint image on the whole image and on the scene's named crops (RMSE,
relMSE, SSIM, FLIP, relative bias; MSE and relMSE also debiased, the
reference's own variance taken out: gmon_sweep.uncertainty), checks its
whole-image RMSE against the renderer's, flags errors the reference's own
residual error could account for, and draws the plots (from the first
seed). The estimators measured are those the renderer wrote: the rows of its
checkpoints.csv (one a layer: clamp one a level).

Outputs in --out: sweep.csv (one row per M, seed, checkpoint, estimator and
region), summary.csv (per M, checkpoint, estimator and region: every metric's
mean and 95% interval over seeds, and each estimator's paired error ratio to
the mean's), reach.csv (time to reach the mean's final error, over seeds),
sweep.json (settings, reference, commands), error-vs-spp.png,
error-vs-time.png, crops.png, and the renders (M<m>/seed-<s>/spp-<n>.exr).
"""

import argparse
import csv
import json
import sys
from pathlib import Path

from . import crops, exr, metrics, plots, references, renderer, uncertainty

ROOT = renderer.ROOT
# Raw metrics first, then the reference's floor, then the debiased MSE and
# relMSE (uncertainty.debiased) with the source of the reference's variance.
COLUMNS = ("scene", "sets", "seed", "estimator", "spp", "seconds", "region", "rmse", "relmse", "ssim", "flip",
           "rel_bias", "rmse_floor", "relmse_floor", "at_floor", "mse", "mse_debiased", "mse_debiased_lo",
           "mse_debiased_hi", "mse_debiased_includes_zero", "relmse_debiased", "relmse_debiased_lo",
           "relmse_debiased_hi", "relmse_debiased_includes_zero", "variance_source")
DEFAULT_SEEDS = 4
# The renderer's RMSE and ours come from the same float pixels; they differ
# only by summation order and precision.
RMSE_AGREEMENT = 1e-4


def checkpoint_path(run_dir, spp):
    return Path(run_dir) / f"spp-{spp:06d}.exr"


def run_directory(out, sets, seed):
    """Where the render of one M and seed goes."""
    return Path(out) / f"M{sets}" / f"seed-{seed}"


def seed_list(settings):
    """The seeds of a sweep.json (sweeps before --seeds had one, "seed")."""
    return settings.get("seeds") or [settings["seed"]]


def render(gmonrt, scene, run_dir, max_spp, sets, reference, resolution, seed, integrator, time_budget, estimators,
           sampler=None):
    """One progressive render with checkpoints; returns the command line run.
    A 1-spp render with the same settings first builds the OpenCL programs
    into PoCL's cache: gmonrt's `seconds` would otherwise include that build.
    `estimators`: a --estimators list, or None for gmonrt's default;
    `sampler`: a --sampler name, or None for the scene's."""
    settings = ["--sets", sets, "--resolution", resolution, "--seed", seed, "--integrator", integrator, "--quiet"]
    if estimators:
        settings += ["--estimators", estimators]
    if sampler:
        settings += ["--sampler", sampler]
    renderer.run(gmonrt, [scene, "--spp", 1, *settings, "--outfile", Path(run_dir) / "warm-up.exr"])
    arguments = [scene, "--spp", max_spp, "--checkpoints", run_dir, "--reference", reference, *settings,
                 "--outfile", Path(run_dir) / "final.exr"]
    if time_budget:
        arguments += ["--time", time_budget]
    renderer.run(gmonrt, arguments)
    return renderer.command_line(arguments)


def read_renderer_csv(path):
    """The renderer's checkpoints.csv: [(spp, seconds, estimator, rmse)]."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or set(rows[0]) != {"spp", "seconds", "estimator", "rmse", "relmse"}:
        raise ValueError(f"{path}: not a checkpoints.csv with columns spp,seconds,estimator,rmse,relmse")
    return [(int(r["spp"]), float(r["seconds"]), r["estimator"], float(r["rmse"]) if r["rmse"] else None) for r in rows]


def at_floor(value, floor, key):
    """Whether a measured `key` error ("rmse" or "relmse") is one the
    reference's own error (`floor`, the same kind) could account for: a
    squared error under twice the reference's, i.e. half or more of it may be
    the reference's, so the value tells about the reference rather than the
    estimator."""
    return value**2 < 2 * floor**2 if key == "rmse" else value < 2 * floor


def floor_columns(values, floor):
    """rmse_floor, relmse_floor, and at_floor: 1 when the RMSE or the relMSE
    is at the reference's floor (at_floor above); empty where there is no
    floor."""
    if not floor:
        return {"rmse_floor": "", "relmse_floor": "", "at_floor": ""}
    limited = any(at_floor(values[key], floor[key], key) for key in ("rmse", "relmse"))
    return {"rmse_floor": floor["rmse"], "relmse_floor": floor["relmse"], "at_floor": int(limited)}


def measure_run(run_dir, scene, sets, seed, reference, regions, floors, noise):
    """Rows for every checkpoint and estimator of one render; `noise`: the
    reference's (uncertainty.ReferenceNoise)."""
    rows = []
    for spp, seconds, estimator, renderer_rmse in read_renderer_csv(Path(run_dir) / "checkpoints.csv"):
        image = renderer.read_estimate(checkpoint_path(run_dir, spp), estimator)
        measured = metrics.evaluate(image, reference, regions)
        ours = measured["image"]["rmse"]
        if renderer_rmse is None:
            raise RuntimeError(f"{run_dir}/checkpoints.csv has no RMSE for {estimator} at {spp} spp")
        if not abs(ours - renderer_rmse) <= RMSE_AGREEMENT * max(ours, renderer_rmse):
            raise RuntimeError(f"{run_dir}: {estimator} at {spp} spp: the renderer's RMSE {renderer_rmse} and "
                               f"this script's {ours} disagree")
        for name, values in measured.items():
            rows.append({"scene": scene, "sets": sets, "seed": seed, "estimator": estimator, "spp": spp,
                         "seconds": seconds, "region": name, **values, **floor_columns(values, floors.get(name)),
                         **uncertainty.debiased(image, reference, noise, regions[name], name),
                         "variance_source": noise.source})
    return rows


def write_csv(rows, path, columns=COLUMNS):
    """Rows as CSV with `columns` in order; None as an empty field."""
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: f"{v:.6g}" if isinstance(v, float) else "" if v is None else v
                             for k, v in row.items()})


def read_csv(path):
    """sweep.csv, summary.csv or reach.csv back as rows with numbers parsed
    (empty fields: None)."""
    text_columns = ("scene", "estimator", "region", "variance_source", "metric",
                    *(f"{m}_verdict" for m in uncertainty.RATIO_METRICS))
    integer_columns = ("sets", "seed", "spp", "at_floor", "seeds", "reached", "mse_debiased_includes_zero",
                       "relmse_debiased_includes_zero")

    def parse(column, text):
        if column in text_columns:
            return text
        if text == "":
            return None
        return int(text) if column in integer_columns else float(text)

    with open(path, newline="") as f:
        return [{k: parse(k, v) for k, v in row.items()} for row in csv.DictReader(f)]


def figure_sets(sets_list):
    """The M whose images the crops figure shows: 21 if swept, else the first."""
    return 21 if 21 in sets_list else sets_list[0]


def sweep(args):
    scene = crops.scene_name(args.scene)
    reference_path = args.reference or ROOT / "references" / f"{scene}.exr"
    reference, record = references.load(reference_path)
    height, width, _ = reference.shape
    resolution = args.resolution or f"{width}x{height}"
    if resolution != f"{width}x{height}":
        raise SystemExit(f"--resolution {resolution}: the reference {reference_path} is {width}x{height}")
    seeds = [args.seed + i for i in range(args.seeds)]
    if record and record["seed"] in seeds:
        raise SystemExit(f"--seed {args.seed} --seeds {args.seeds} includes the reference's seed {record['seed']}: "
                         "its samples would not be independent")
    regions = crops.regions(args.crops, scene, width, height)
    floors = record["residual"] if record else {}
    noise = uncertainty.ReferenceNoise.of_reference(reference_path, record)
    out = Path(args.out or ROOT / "build" / "sweep" / scene)
    out.mkdir(parents=True, exist_ok=True)
    rows, commands = [], []
    for sets in args.sets:
        for seed in seeds:
            run_dir = run_directory(out, sets, seed)
            run_dir.mkdir(parents=True, exist_ok=True)
            # gmonrt appends to checkpoints.csv: start from an empty directory.
            for old in [*run_dir.glob("spp-*.exr"), run_dir / "checkpoints.csv"]:
                old.unlink(missing_ok=True)
            commands.append(render(args.gmonrt, args.scene, run_dir, args.max_spp, sets, reference_path, resolution,
                                   seed, args.integrator, args.time, args.estimators, args.sampler))
            rows += measure_run(run_dir, scene, sets, seed, reference, regions, floors, noise)
        print(f"{scene}: M = {sets} done ({len(seeds)} seeds)", file=sys.stderr)
    write_csv(rows, out / "sweep.csv")
    write_csv(uncertainty.summarise(rows), out / "summary.csv", uncertainty.SUMMARY_COLUMNS)
    write_csv(uncertainty.reach(rows), out / "reach.csv", uncertainty.REACH_COLUMNS)
    settings = {"scene": renderer.shown(args.scene), "reference": renderer.shown(reference_path),
                "reference_record": record, "resolution": resolution, "max_spp": args.max_spp, "time_budget": args.time,
                "sets": args.sets, "seed": args.seed, "seeds": seeds,
                "variance_source": noise.source, "integrator": args.integrator,
                "sampler": args.sampler,
                "crops": {name: region for name, region in regions.items() if region}, "commands": commands}
    (out / "sweep.json").write_text(json.dumps(settings, indent=2) + "\n")
    # The plots and figure show one seed's render: lines over seeds would
    # zigzag between renders; the intervals are in summary.csv.
    title = f"{scene}, {resolution}, {args.integrator}, seed {seeds[0]}"
    first = [r for r in rows if r["seed"] == seeds[0]]
    plots.error_plots(first, floors, "spp", out / "error-vs-spp.png", title)
    plots.error_plots(first, floors, "seconds", out / "error-vs-time.png", title)
    shown_sets = figure_sets(args.sets)
    run_spps = sorted({r["spp"] for r in first if r["sets"] == shown_sets})
    figure_spps = [s for s in (args.figure_spp or []) if s in run_spps] or [run_spps[-1]]
    files = {spp: exr.read(checkpoint_path(run_directory(out, shown_sets, seeds[0]), spp)) for spp in figure_spps}
    images = {spp: layers for spp, (layers, _) in files.items()}
    estimators = plots.estimators_of(rows)  # the layers (clamp's by level), as the renderer's rows name them
    plots.crops_figure(images, reference, {n: r for n, r in regions.items() if r}, out / "crops.png",
                       f"{scene}, M = {shown_sets}", estimators)
    return out, rows


def positive_list(text):
    values = [int(v) for v in text.split(",")]
    if not values or min(values) < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a comma-separated list of positive integers")
    return values


def positive_int(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a positive integer")
    return value


def estimator_list(text):
    """--estimators: gmonrt's list (it checks the names); the mean among them,
    as the sweep compares every estimator with the mean of the same samples."""
    if "mean" not in text.split(",") and text != "all":
        raise argparse.ArgumentTypeError(f"'{text}' lacks mean: the sweep compares every estimator with the mean")
    return text


def parser():
    p = argparse.ArgumentParser(prog="sweep.sh", description=__doc__.split("\n\n")[0])
    p.add_argument("scene", type=Path, help="scene file, e.g. scenes/cornell-glass.pbrt")
    p.add_argument("--max-spp", type=int, default=1024, help="last checkpoint (default 1024)")
    p.add_argument("--time", type=float,
                   help="time budget per render in seconds: gmonrt stops after the pass that reaches it, keeping "
                        "the checkpoints written by then")
    p.add_argument("--sets", type=positive_list, default=[21], help="list of M, e.g. 5,11,21,25 (default 21)")
    p.add_argument("--estimators", type=estimator_list,
                   help="gmonrt's --estimators, mean among them (default gmonrt's: mean,mon,gmon)")
    p.add_argument("--reference", type=Path, help="reference EXR (default references/<scene>.exr)")
    p.add_argument("--resolution", help="WIDTHxHEIGHT; must be the reference's (default: the reference's)")
    p.add_argument("--seed", type=int, default=0, help="first seed (default 0; not the reference's)")
    p.add_argument("--seeds", type=positive_int, default=DEFAULT_SEEDS,
                   help=f"independent renders per M, seeds SEED, SEED + 1, ... (default {DEFAULT_SEEDS}): every "
                        "metric's interval in summary.csv is over them")
    p.add_argument("--integrator", choices=("nee", "bsdf"), default="nee", help="default nee")
    p.add_argument("--sampler", choices=("independent", "sobol-pixel", "sobol-sets"),
                   help="gmonrt --sampler (default: the scene's Sampler, docs/sampling.md)")
    p.add_argument("--crops", type=Path, default=ROOT / "scenes" / "crops.json", help="default scenes/crops.json")
    p.add_argument("--figure-spp", type=positive_list,
                   help="checkpoints shown in crops.png (default, and in place of any not reached: the last)")
    p.add_argument("--out", type=Path, help="output directory (default build/sweep/<scene>)")
    p.add_argument("--gmonrt", type=Path, default=renderer.GMONRT, help="default build/gmonrt")
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    renderer.pocl_cache(ROOT / "build" / "pocl-cache")
    out, rows = sweep(args)
    print(f"wrote {out}/sweep.csv ({len(rows)} rows) and plots", file=sys.stderr)


if __name__ == "__main__":
    main()
