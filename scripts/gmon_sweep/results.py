"""The results page: sweeps of every scene with a reference, for several M,
and docs/results.md with tables, plots and the commands that made them.

Sweeps go to build/results/<scene>/ (sweep.sh's outputs; --sweeps); the page, each
scene's CSV and its plots go to --docs (default docs/: results.md and
results/<scene>-*.png, results/<scene>.csv).
"""

import argparse
import json
import math
import shlex
import shutil
import sys
from pathlib import Path

from . import crops, exr, renderer, sweep
from .plots import estimators_of, label

ROOT = renderer.ROOT
FIGURES = ("error-vs-spp.png", "error-vs-time.png", "crops.png")


def line(rows, sets, estimator, region="image"):
    return sorted((r for r in rows if r["sets"] == sets and r["estimator"] == estimator and r["region"] == region),
                  key=lambda r: r["spp"])


def time_to_reach(curve, target, key):
    """Seconds at which `curve` (rows by rising spp) first gets to `target` in
    `key`, interpolated linearly in log(time) against log(error) between the
    two checkpoints around the crossing; None if it never does."""
    for before, after in zip([None] + curve[:-1], curve):
        if after[key] <= target:
            if before is None or after[key] == before[key]:
                return after["seconds"]
            fraction = math.log(before[key] / target) / math.log(before[key] / after[key])
            return math.exp(math.log(before["seconds"]) + fraction * math.log(after["seconds"] / before["seconds"]))
    return None


def reach_ratio(rows, sets, key):
    """Time for G-MoN to reach the mean's final `key` error, over the time of
    that final checkpoint, as text; rows of one render share their times."""
    mean, gmon = line(rows, sets, "mean"), line(rows, sets, "gmon")
    target = mean[-1][key]
    seconds = time_to_reach(gmon, target, key)
    if seconds is None:
        return f"not reached (final: {gmon[-1][key] / target:.2f}x the mean's)"
    return f"{seconds / mean[-1]['seconds']:.2f}"


def listing(words):
    """"mean, MoN and G-MoN" for ["mean", "MoN", "G-MoN"]."""
    return " and ".join(words) if len(words) < 3 else f"{', '.join(words[:-1])} and {words[-1]}"


def error(row, key):
    """A row's "rmse" or "relmse" as text, marked † when at the reference's floor."""
    text = f"{row[key]:.4g}"
    floor = row[f"{key}_floor"]
    return f"{text} †" if floor is not None and sweep.at_floor(row[key], floor, key) else text


def below_zero(rows, sweep_dir):
    """Lines of a table: per estimator and M, the pixels of the last
    checkpoint with a channel below 0 and the lowest value there (gabmm goes
    negative on a firefly; a negative filter lobe can make any estimate so)."""
    all_sets = sorted({r["sets"] for r in rows})
    final_spp = max(r["spp"] for r in rows)
    out = [f"Pixels below zero at {final_spp} spp (any channel; the lowest value in brackets):", "",
           f"| estimator | {' | '.join(f'M = {m}' for m in all_sets)} |", "| --- " * (len(all_sets) + 1) + "|"]
    for estimator in estimators_of(rows):
        cells = []
        for sets in all_sets:
            image = exr.read_layer(sweep.checkpoint_path(Path(sweep_dir) / f"M{sets}", final_spp), estimator)
            negative = int((image.min(axis=-1) < 0).sum())
            cells.append(f"{negative} of {image.shape[0] * image.shape[1]} ({image.min():.3g})" if negative else "0")
        out.append(f"| {label(estimator)} | {' | '.join(cells)} |")
    return out + [""]


def scene_section(scene, rows, settings, sweep_dir):
    all_sets = sorted({r["sets"] for r in rows})
    final_spp = max(r["spp"] for r in rows)
    estimators = estimators_of(rows)
    count = {2: "two", 3: "three"}.get(len(estimators), str(len(estimators)))
    out = [f"## {scene}", ""]
    out += [f"Whole image at {final_spp} spp (the last checkpoint of each render; seconds are render and "
            f"estimator time to that checkpoint, the same for the {count} estimators of one render; † marks a "
            "value at the reference's floor):", ""]
    out += ["| M | estimator | RMSE | relMSE | SSIM | FLIP | bias vs reference | bias vs mean | seconds |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for sets in all_sets:
        mean_bias = line(rows, sets, "mean")[-1]["rel_bias"]
        for estimator in estimators:
            r = line(rows, sets, estimator)[-1]
            out.append(f"| {sets} | {label(estimator)} | {error(r, 'rmse')} | {error(r, 'relmse')} | "
                       f"{r['ssim']:.4f} | {r['flip']:.4f} | "
                       f"{r['rel_bias']:+.2%} | {r['rel_bias'] - mean_bias:+.3%} | {r['seconds']:.1f} |")
    if "gmon" in estimators:
        out += ["", "Time for G-MoN to reach the mean's error at the last checkpoint, as a fraction of the mean's "
                "time (below 1: G-MoN gets there sooner):", "",
                "| M | by RMSE | by relMSE |", "| --- | --- | --- |"]
        for sets in all_sets:
            out.append(f"| {sets} | {reach_ratio(rows, sets, 'rmse')} | {reach_ratio(rows, sets, 'relmse')} |")
    shown_sets = sweep.figure_sets(all_sets)
    regions = [name for name in dict.fromkeys(r["region"] for r in rows) if name != "image"]
    if regions:
        out += ["", f"Crops at {final_spp} spp, M = {shown_sets} (relMSE / FLIP; † at the reference's floor):", "",
                f"| crop | {' | '.join(map(label, estimators))} |", "| --- " * (len(estimators) + 1) + "|"]
        for region in regions:
            cells = []
            for estimator in estimators:
                r = line(rows, shown_sets, estimator, region)[-1]
                cells.append(f"{error(r, 'relmse')} / {r['flip']:.3f}")
            out.append(f"| {region} | {' | '.join(cells)} |")
    out += [""] + below_zero(rows, sweep_dir)
    for figure in FIGURES:
        out += [f"![{scene} {figure[:-4]}](results/{scene}-{figure})", ""]
    out += ["Commands run by the sweep:", "", "```sh", *settings["commands"], "```", ""]
    return out


def reference_table(all_settings):
    out = ["## References", "",
           "Mean of two independent halves with next-event estimation; residual: the reference's own error on the "
           "whole image, estimated from the halves.", "",
           "| scene | spp | resolution | seed | residual RMSE | residual relMSE | render seconds |",
           "| --- | --- | --- | --- | --- | --- | --- |"]
    for scene, settings in all_settings.items():
        record = settings["reference_record"]
        if not record:
            out.append(f"| {scene} | (no record beside {settings['reference']}) | | | | | |")
            continue
        residual = record["residual"]["image"]
        out.append(f"| {scene} | {record['spp']} | {record['resolution'][0]}x{record['resolution'][1]} | "
                   f"{record['seed']} | {residual['rmse']:.4g} | {residual['relmse']:.4g} | "
                   f"{record['render_seconds']:.0f} |")
    return out + [""]


def summary(all_rows):
    """Computed statements: which estimator has the lowest error where."""
    out = ["## Summary (computed from the tables below)", ""]
    for scene, rows in all_rows.items():
        for sets in sorted({r["sets"] for r in rows}):
            finals = {e: line(rows, sets, e)[-1] for e in estimators_of(rows)}
            best = {key: min(finals, key=lambda e: finals[e][key]) for key in ("rmse", "relmse", "flip")}
            flags = " (some at the reference's floor)" if any(f["at_floor"] for f in finals.values()) else ""
            gmon_bias = ""
            if "gmon" in finals:
                bias = finals["gmon"]["rel_bias"] - finals["mean"]["rel_bias"]
                gmon_bias = f"; G-MoN's bias against the mean of the same samples {bias:+.3%}"
            out.append(f"- {scene}, M = {sets}, {finals['mean']['spp']} spp: lowest RMSE {label(best['rmse'])}, "
                       f"relMSE {label(best['relmse'])}, FLIP {label(best['flip'])}{gmon_bias}{flags}.")
    return out + [""]


def page(all_rows, all_settings, sweep_dirs, arguments, docs):
    first = next(iter(all_settings.values()))
    estimators = list(dict.fromkeys(e for rows in all_rows.values() for e in estimators_of(rows)))
    others = [label(e) for e in estimators if e != "mean"]
    owners = listing([f"{name}'s" for name in others])
    out = [f"# Results: error of {listing(list(map(label, estimators)))} against time and samples", "",
           "Generated by `scripts/results.sh` (do not edit by hand). Every number comes from the CSVs in "
           "`docs/results/`; the definitions of the metrics are in `scripts/gmon_sweep/metrics.py`, the sweep's "
           "design in `scripts/gmon_sweep/sweep.py`.", "",
           "## How it was made", "",
           "```sh",
           "scripts/make-references.sh   # references/<scene>.exr and .json",
           f"scripts/results.sh {shlex.join(arguments)}".rstrip(),
           "```", "",
           f"Each scene: one progressive render per M in {{{', '.join(map(str, first['sets']))}}} with checkpoints at "
           f"every power of two up to {first['max_spp']} spp, {first['resolution']}, seed {first['seed']}, "
           f"integrator {first['integrator']} (the references use seed 1000 and next-event estimation). The mean "
           f"is the same for every M up to float rounding; the sets only change {listing(others)}. Times are "
           "wall-clock seconds on the machine that ran the command (PoCL on CPU; shared, so noisy), render and "
           "estimators included.", "",
           "Reference floor: the reference's own RMSE and relMSE, estimated from its two independent halves "
           "(`scripts/gmon_sweep/references.py`). A value is marked † (column `at_floor` in the CSVs) when the "
           "measured MSE or relMSE is under twice the reference's: half or more of it may be the reference's own "
           "error, so it is not a result about the estimator.", "",
           "Bias vs reference: (average of the estimate - average of the reference) / average of the reference "
           "over the whole image; for the mean it is noise (of the render and the reference). Bias vs mean: the "
           "same for the estimate minus the mean of the same samples, (average of the estimate - average of the "
           "mean) / average of the reference: the noise of the samples cancels, so this measures "
           f"{owners} own bias, e.g. the darkening others report for G-MoN on a firefly-free scene such as "
           "`cornell-diffuse`.", ""]
    if (docs / "results-discussion.md").exists():
        out += ["What these numbers say against the paper's expectations, written by hand: "
                "[results-discussion.md](results-discussion.md).", ""]
    out += reference_table(all_settings)
    out += summary(all_rows)
    for scene, rows in all_rows.items():
        out += scene_section(scene, rows, all_settings[scene], sweep_dirs[scene])
    return "\n".join(out)


def main(argv=None):
    p = argparse.ArgumentParser(prog="results.sh", description=__doc__.split("\n\n")[0])
    p.add_argument("scenes", nargs="*", type=Path, help="default: every scenes/*.pbrt with a reference")
    p.add_argument("--sets", type=sweep.positive_list, default=[5, 11, 21, 25], help="default 5,11,21,25")
    p.add_argument("--max-spp", type=int, default=1024, help="last checkpoint of every render (default 1024)")
    p.add_argument("--estimators", type=sweep.estimator_list,
                   help="gmonrt's --estimators, mean among them (default gmonrt's: mean,mon,gmon)")
    p.add_argument("--integrator", choices=("nee", "bsdf"), default="nee", help="default nee")
    p.add_argument("--docs", type=Path, default=ROOT / "docs", help="where results.md and results/ go (default docs/)")
    p.add_argument("--sweeps", type=Path, default=ROOT / "build" / "results",
                   help="where the sweeps go, one directory per scene (default build/results/)")
    p.add_argument("--no-render", action="store_true", help="rebuild the page from the sweeps already in --sweeps")
    p.add_argument("--gmonrt", type=Path, default=renderer.GMONRT, help="default build/gmonrt")
    args = p.parse_args(argv)
    renderer.pocl_cache(ROOT / "build" / "pocl-cache")
    scenes = args.scenes or [s for s in sorted((ROOT / "scenes").glob("*.pbrt"))
                             if (ROOT / "references" / f"{s.stem}.exr").exists()]
    figures_dir = args.docs / "results"
    figures_dir.mkdir(parents=True, exist_ok=True)
    all_rows, all_settings = {}, {}
    for scene_path in scenes:
        scene = crops.scene_name(scene_path)
        out = args.sweeps / scene
        if not args.no_render:
            sweep.main([str(scene_path), "--sets", ",".join(map(str, args.sets)), "--max-spp", str(args.max_spp),
                        "--integrator", args.integrator, "--out", str(out), "--gmonrt", str(args.gmonrt),
                        "--figure-spp", f"{min(64, args.max_spp)},{args.max_spp}",
                        *(["--estimators", args.estimators] if args.estimators else [])])
        all_rows[scene] = sweep.read_csv(out / "sweep.csv")
        all_settings[scene] = json.loads((out / "sweep.json").read_text())
        shutil.copy(out / "sweep.csv", figures_dir / f"{scene}.csv")
        for figure in FIGURES:
            shutil.copy(out / figure, figures_dir / f"{scene}-{figure}")
    arguments = [a for a in (argv if argv is not None else sys.argv[1:]) if a != "--no-render"]
    sweep_dirs = {scene: args.sweeps / scene for scene in all_rows}
    (args.docs / "results.md").write_text(page(all_rows, all_settings, sweep_dirs, arguments, args.docs) + "\n")
    print(f"wrote {args.docs / 'results.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()
