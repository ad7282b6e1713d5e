"""The sweep's figures (matplotlib, PNG): error against spp or time, and
crops side by side."""

import itertools

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the backend)
import numpy as np  # noqa: E402

from .metrics import crop, to_display  # noqa: E402

LABELS = {"mean": "mean", "mon": "MoN", "gmon": "G-MoN"}
# Colour maps of the estimators other than the mean, whose line is black:
# MoN's and G-MoN's, then the others' in the order they come.
COLOUR_MAPS = {"mon": plt.cm.Blues, "gmon": plt.cm.Reds}
OTHER_COLOUR_MAPS = (plt.cm.Greens, plt.cm.Purples, plt.cm.Oranges, plt.cm.Greys, plt.cm.YlOrBr, plt.cm.BuGn,
                     plt.cm.PuRd, plt.cm.GnBu, plt.cm.YlGn, plt.cm.RdPu, plt.cm.OrRd, plt.cm.BuPu)
PANELS = (("rmse", "RMSE"), ("relmse", "relMSE"), ("1-ssim", "1 - SSIM"), ("flip", "HDR-FLIP"))
AXES = {"spp": "samples per pixel", "seconds": "wall-clock seconds (render and estimators)"}


def _value(row, key):
    # 1 - SSIM is 0 for identical images; keep it on the log axis.
    return max(1 - row["ssim"], 1e-6) if key == "1-ssim" else row[key]


def label(estimator):
    """An estimator's name in tables and plots: MoN, G-MoN, else its own."""
    return LABELS.get(estimator, estimator)


def estimators_of(rows):
    """The estimators of sweep rows, in the order they come (the renderer's)."""
    return list(dict.fromkeys(r["estimator"] for r in rows))


def _colour_maps(estimators):
    others = itertools.cycle(OTHER_COLOUR_MAPS)
    return {e: COLOUR_MAPS[e] if e in COLOUR_MAPS else next(others) for e in estimators if e != "mean"}


def _lines(rows):
    """(label, colour, rows) per line: the mean once (the same for every M up
    to float rounding; its times come from the first M's render), every
    other estimator per M."""
    all_sets = sorted({r["sets"] for r in rows})
    estimators = estimators_of(rows)
    lines = []
    if "mean" in estimators:
        lines.append(("mean", "black", [r for r in rows if r["estimator"] == "mean" and r["sets"] == all_sets[0]]))
    for estimator, colours in _colour_maps(estimators).items():
        for i, sets in enumerate(all_sets):
            shade = colours(0.45 + 0.55 * (i + 1) / len(all_sets))
            lines.append((f"{label(estimator)} M={sets}", shade,
                          [r for r in rows if r["estimator"] == estimator and r["sets"] == sets]))
    return lines


def error_plots(rows, floors, x_key, path, title, region="image"):
    """2 x 2 log-log panels (RMSE, relMSE, 1 - SSIM, FLIP) against `x_key`
    ("spp" or "seconds") on `region`; the reference's residual RMSE and
    relMSE (`floors`) as dashed lines."""
    rows = [r for r in rows if r["region"] == region]
    lines = _lines(rows)
    # Beyond a dozen lines the legend goes below the panels, in columns.
    columns = 1 if len(lines) <= 12 else 4
    legend_rows = -(-(len(lines) + 1) // columns)
    figure, axes = plt.subplots(2, 2, figsize=(10, 8 + (0.17 * legend_rows if columns > 1 else 0)),
                                constrained_layout=True)
    for axis, (key, name) in zip(axes.flat, PANELS):
        for line_label, colour, line in lines:
            line = sorted(line, key=lambda r: r[x_key])
            axis.plot([r[x_key] for r in line], [_value(r, key) for r in line], marker="o", markersize=3,
                      color=colour, label=line_label)
        floor = floors.get(region, {}).get(key)
        if floor:
            axis.axhline(floor, color="grey", linestyle="--", linewidth=1, label="reference residual")
        axis.set_xscale("log", base=2 if x_key == "spp" else 10)
        axis.set_yscale("log")
        axis.set_xlabel(AXES[x_key])
        axis.set_ylabel(name)
        axis.grid(True, which="both", alpha=0.3)
    if columns == 1:
        axes.flat[0].legend(fontsize=7)
    else:
        figure.legend(*axes.flat[0].get_legend_handles_labels(), loc="outside lower center", ncol=columns, fontsize=7)
    figure.suptitle(f"{title}: error on the {'whole image' if region == 'image' else region}")
    figure.savefig(path, dpi=90)
    plt.close(figure)


def crops_figure(images, reference, regions, path, title, estimators):
    """Rows: each checkpoint of `images` ({spp: {layer: image}}) times each
    named region; columns: `estimators` (e.g. the file's), then the
    reference. Display encoding as metrics.to_display (exposure 1, sRGB)."""
    regions = regions or {"image": None}
    cells = [(spp, name, region) for spp in sorted(images) for name, region in regions.items()]
    columns = (*estimators, "reference")
    figure, axes = plt.subplots(len(cells), len(columns), figsize=(2 * len(columns), 2.2 * len(cells)), squeeze=False,
                                constrained_layout=True)
    for row, (spp, name, region) in enumerate(cells):
        for column, layer in enumerate(columns):
            image = reference if layer == "reference" else images[spp][layer]
            axis = axes[row][column]
            axis.imshow(np.clip(to_display(crop(image, region)), 0, 1), interpolation="nearest")
            axis.set_xticks([])
            axis.set_yticks([])
            if row == 0:
                axis.set_title(label(layer))
            if column == 0:
                axis.set_ylabel(f"{name}, {spp} spp")
    figure.suptitle(title)
    figure.savefig(path, dpi=90)
    plt.close(figure)
