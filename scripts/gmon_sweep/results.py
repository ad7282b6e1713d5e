"""The results page: sweeps of every scene with a reference, for several M,
and docs/results.md with tables, plots and the commands that made them.

Sweeps go to build/results/<scene>/ (sweep.sh's outputs; --sweeps); the page, each
scene's CSVs and its plots go to --docs (default docs/: results.md and
results/<scene>-*.png, results/<scene>.csv, results/<scene>-summary.csv,
results/<scene>-reach.csv). The tables of single values, the crops and the
plots come from the first seed's render; the intervals from all seeds.
"""

import argparse
import json
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


def listing(words):
    """"mean, MoN and G-MoN" for ["mean", "MoN", "G-MoN"]."""
    return " and ".join(words) if len(words) < 3 else f"{', '.join(words[:-1])} and {words[-1]}"


def error(row, key):
    """A row's "rmse" or "relmse" as text, marked † when at the reference's floor."""
    text = f"{row[key]:.4g}"
    floor = row[f"{key}_floor"]
    return f"{text} †" if floor is not None and sweep.at_floor(row[key], floor, key) else text


def interval(row, key, digits=4):
    """"value [low, high]" of a summary.csv field, or the value alone when
    the interval is unknown (one seed); "-" when there is no value."""
    value, low, high = row[key], row[f"{key}_lo"], row[f"{key}_hi"]
    if value is None:
        return "-"
    if low is None or low != low:  # NaN: fewer than two seeds
        return f"{value:.{digits}g}"
    return f"{value:.{digits}g} [{low:.{digits}g}, {high:.{digits}g}]"


def debiased_cell(row, key):
    """A debiased value with its interval, marked ‡ when the interval includes 0."""
    text = interval(row, key, 3)
    return f"{text} ‡" if row[f"{key}_includes_zero"] else text


def ratio_cell(row, key):
    """An error ratio to the mean with its interval and verdict."""
    if row[f"{key}_ratio"] is None or row[f"{key}_ratio"] != row[f"{key}_ratio"]:
        return "-"
    low, high = row[f"{key}_ratio_lo"], row[f"{key}_ratio_hi"]
    if low is None or low != low:
        return f"{row[f'{key}_ratio']:.3f}"
    return f"{row[f'{key}_ratio']:.3f} [{low:.3f}, {high:.3f}] {row[f'{key}_verdict']}"


def seeds_section(summary_rows, reach_rows):
    """Lines: every M and estimator at the last checkpoint, means over seeds
    with 95% intervals, the debiased errors and the paired ratios."""
    rows = [r for r in summary_rows if r["region"] == "image"]
    final_spp = max(r["spp"] for r in rows)
    finals = [r for r in rows if r["spp"] == final_spp]
    seeds = max(r["seeds"] for r in finals)
    out = [f"Over {seeds} seeds at {final_spp} spp (mean [95% Student t interval]; MSE debiased: the reference's "
           "own variance taken out, ‡ where its interval includes 0; ratio: the estimator's error over the mean's "
           "of the same samples, per seed, then over seeds, better or worse only when its interval excludes 1):", "",
           "| M | estimator | MSE | MSE debiased | relMSE debiased | SSIM | FLIP | MSE debiased ratio | "
           "relMSE debiased ratio | FLIP ratio |", "| --- " * 10 + "|"]
    for r in finals:
        out.append(f"| {r['sets']} | {label(r['estimator'])} | {interval(r, 'mse', 3)} | "
                   f"{debiased_cell(r, 'mse_debiased')} | {debiased_cell(r, 'relmse_debiased')} | "
                   f"{interval(r, 'ssim', 3)} | {interval(r, 'flip', 3)} | {ratio_cell(r, 'mse_debiased')} | "
                   f"{ratio_cell(r, 'relmse_debiased')} | {ratio_cell(r, 'flip')} |")
    out += ["", "Time to reach the mean's error at its last checkpoint, over the mean's time to it (per seed, then "
            "over seeds; below 1: sooner):", "", "| M | estimator | by RMSE | by relMSE |", "| --- " * 4 + "|"]
    cells = {(r["sets"], r["estimator"], r["metric"]): r for r in reach_rows}
    for sets, estimator in dict.fromkeys((r["sets"], r["estimator"]) for r in reach_rows):
        if estimator == "mean":
            continue
        texts = []
        for metric in ("rmse", "relmse"):
            r = cells[(sets, estimator, metric)]
            if r["time_ratio"] is None:
                texts.append(f"not reached by {r['seeds'] - r['reached']} of {r['seeds']} seeds")
            else:
                texts.append(interval({"x": r["time_ratio"], "x_lo": r["time_ratio_lo"],
                                       "x_hi": r["time_ratio_hi"]}, "x", 3))
        out.append(f"| {sets} | {label(estimator)} | {' | '.join(texts)} |")
    return out + [""]


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
            seed = rows[0]["seed"]
            image = exr.read_layer(sweep.checkpoint_path(sweep.run_directory(sweep_dir, sets, seed), final_spp),
                                   estimator)
            negative = int((image.min(axis=-1) < 0).sum())
            cells.append(f"{negative} of {image.shape[0] * image.shape[1]} ({image.min():.3g})" if negative else "0")
        out.append(f"| {label(estimator)} | {' | '.join(cells)} |")
    return out + [""]


def scene_section(scene, rows, settings, sweep_dir, summary_rows, reach_rows):
    all_sets = sorted({r["sets"] for r in rows})
    final_spp = max(r["spp"] for r in rows)
    estimators = estimators_of(rows)
    count = {2: "two", 3: "three"}.get(len(estimators), str(len(estimators)))
    out = [f"## {scene}", ""]
    out += seeds_section(summary_rows, reach_rows)
    out += [f"Whole image at {final_spp} spp, seed {rows[0]['seed']} (the last checkpoint of each render; seconds "
            f"are render and estimator time to that checkpoint, the same for the {count} estimators of one render; "
            "† marks a value at the reference's floor):", ""]
    out += ["| M | estimator | RMSE | relMSE | SSIM | FLIP | bias vs reference | bias vs mean | seconds |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for sets in all_sets:
        mean_bias = line(rows, sets, "mean")[-1]["rel_bias"]
        for estimator in estimators:
            r = line(rows, sets, estimator)[-1]
            out.append(f"| {sets} | {label(estimator)} | {error(r, 'rmse')} | {error(r, 'relmse')} | "
                       f"{r['ssim']:.4f} | {r['flip']:.4f} | "
                       f"{r['rel_bias']:+.2%} | {r['rel_bias'] - mean_bias:+.3%} | {r['seconds']:.1f} |")
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


def page(all_rows, all_settings, sweep_dirs, arguments, docs, all_summaries, all_reaches):
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
           f"Each scene: one progressive render per M and seed, M in {{{', '.join(map(str, first['sets']))}}}, "
           f"with checkpoints at every power of two up to {first['max_spp']} spp, {first['resolution']}, "
           f"seeds {', '.join(map(str, sweep.seed_list(first)))}, "
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
           "`cornell-diffuse`.", "",
           "Debiased MSE and relMSE, intervals over seeds and paired ratios: [estimators.md](estimators.md), "
           "\"Error you can trust\" (`scripts/gmon_sweep/uncertainty.py`). SSIM and FLIP cannot be debiased: "
           "they stay as measured against the noisy reference.", ""]
    if (docs / "results-discussion.md").exists():
        out += ["What these numbers say against the paper's expectations, written by hand: "
                "[results-discussion.md](results-discussion.md).", ""]
    out += reference_table(all_settings)
    out += summary(all_rows)
    for scene, rows in all_rows.items():
        out += scene_section(scene, rows, all_settings[scene], sweep_dirs[scene], all_summaries[scene],
                             all_reaches[scene])
    return "\n".join(out)


def main(argv=None):
    p = argparse.ArgumentParser(prog="results.sh", description=__doc__.split("\n\n")[0])
    p.add_argument("scenes", nargs="*", type=Path, help="default: every scenes/*.pbrt with a reference")
    p.add_argument("--sets", type=sweep.positive_list, default=[5, 11, 21, 25], help="default 5,11,21,25")
    p.add_argument("--max-spp", type=int, default=1024, help="last checkpoint of every render (default 1024)")
    p.add_argument("--estimators", type=sweep.estimator_list,
                   help="gmonrt's --estimators, mean among them (default gmonrt's: mean,mon,gmon)")
    p.add_argument("--seeds", type=sweep.positive_int, default=sweep.DEFAULT_SEEDS,
                   help=f"independent renders per M (default {sweep.DEFAULT_SEEDS}; intervals over them)")
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
    all_rows, all_settings, all_summaries, all_reaches = {}, {}, {}, {}
    for scene_path in scenes:
        scene = crops.scene_name(scene_path)
        out = args.sweeps / scene
        if not args.no_render:
            sweep.main([str(scene_path), "--sets", ",".join(map(str, args.sets)), "--max-spp", str(args.max_spp),
                        "--integrator", args.integrator, "--out", str(out), "--gmonrt", str(args.gmonrt),
                        "--seeds", str(args.seeds),
                        "--figure-spp", f"{min(64, args.max_spp)},{args.max_spp}",
                        *(["--estimators", args.estimators] if args.estimators else [])])
        all_settings[scene] = json.loads((out / "sweep.json").read_text())
        first_seed = sweep.seed_list(all_settings[scene])[0]
        all_rows[scene] = [r for r in sweep.read_csv(out / "sweep.csv") if r["seed"] == first_seed]
        all_summaries[scene] = sweep.read_csv(out / "summary.csv")
        all_reaches[scene] = sweep.read_csv(out / "reach.csv")
        shutil.copy(out / "sweep.csv", figures_dir / f"{scene}.csv")
        shutil.copy(out / "summary.csv", figures_dir / f"{scene}-summary.csv")
        shutil.copy(out / "reach.csv", figures_dir / f"{scene}-reach.csv")
        for figure in FIGURES:
            shutil.copy(out / figure, figures_dir / f"{scene}-{figure}")
    arguments = [a for a in (argv if argv is not None else sys.argv[1:]) if a != "--no-render"]
    sweep_dirs = {scene: args.sweeps / scene for scene in all_rows}
    (args.docs / "results.md").write_text(page(all_rows, all_settings, sweep_dirs, arguments, args.docs,
                                               all_summaries, all_reaches) + "\n")
    print(f"wrote {args.docs / 'results.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()
