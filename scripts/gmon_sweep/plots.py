"""The sweep's figures (matplotlib, PNG): error against spp or time, and
crops side by side."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the backend)
import numpy as np  # noqa: E402

from .metrics import crop, to_display  # noqa: E402

LABELS = {"mean": "mean", "mon": "MoN", "gmon": "G-MoN"}
COLOURS = {"mean": "black", "mon": plt.cm.Blues, "gmon": plt.cm.Reds}
PANELS = (("rmse", "RMSE"), ("relmse", "relMSE"), ("1-ssim", "1 - SSIM"), ("flip", "HDR-FLIP"))
AXES = {"spp": "samples per pixel", "seconds": "wall-clock seconds (render and estimators)"}


def _value(row, key):
    # 1 - SSIM is 0 for identical images; keep it on the log axis.
    return max(1 - row["ssim"], 1e-6) if key == "1-ssim" else row[key]


def _lines(rows):
    """(label, colour, rows) per line: the mean once (the same for every M up
    to float rounding; its times come from the first M's render), MoN and
    G-MoN per M."""
    all_sets = sorted({r["sets"] for r in rows})
    lines = [("mean", COLOURS["mean"], [r for r in rows if r["estimator"] == "mean" and r["sets"] == all_sets[0]])]
    for estimator in ("mon", "gmon"):
        for i, sets in enumerate(all_sets):
            shade = COLOURS[estimator](0.45 + 0.55 * (i + 1) / len(all_sets))
            lines.append((f"{LABELS[estimator]} M={sets}", shade,
                          [r for r in rows if r["estimator"] == estimator and r["sets"] == sets]))
    return lines


def error_plots(rows, floors, x_key, path, title, region="image"):
    """2 x 2 log-log panels (RMSE, relMSE, 1 - SSIM, FLIP) against `x_key`
    ("spp" or "seconds") on `region`; the reference's residual RMSE and
    relMSE (`floors`) as dashed lines."""
    rows = [r for r in rows if r["region"] == region]
    figure, axes = plt.subplots(2, 2, figsize=(10, 8), constrained_layout=True)
    for axis, (key, name) in zip(axes.flat, PANELS):
        for label, colour, line in _lines(rows):
            line = sorted(line, key=lambda r: r[x_key])
            axis.plot([r[x_key] for r in line], [_value(r, key) for r in line], marker="o", markersize=3,
                      color=colour, label=label)
        floor = floors.get(region, {}).get(key)
        if floor:
            axis.axhline(floor, color="grey", linestyle="--", linewidth=1, label="reference residual")
        axis.set_xscale("log", base=2 if x_key == "spp" else 10)
        axis.set_yscale("log")
        axis.set_xlabel(AXES[x_key])
        axis.set_ylabel(name)
        axis.grid(True, which="both", alpha=0.3)
    axes.flat[0].legend(fontsize=7)
    figure.suptitle(f"{title}: error on the {'whole image' if region == 'image' else region}")
    figure.savefig(path, dpi=90)
    plt.close(figure)


def crops_figure(images, reference, regions, path, title):
    """Rows: each checkpoint of `images` ({spp: {"mean", "mon", "gmon"}})
    times each named region; columns: mean, MoN, G-MoN, reference. Display
    encoding as metrics.to_display (exposure 1, sRGB)."""
    regions = regions or {"image": None}
    cells = [(spp, name, region) for spp in sorted(images) for name, region in regions.items()]
    columns = ("mean", "mon", "gmon", "reference")
    figure, axes = plt.subplots(len(cells), 4, figsize=(8, 2.2 * len(cells)), squeeze=False, constrained_layout=True)
    for row, (spp, name, region) in enumerate(cells):
        for column, layer in enumerate(columns):
            image = reference if layer == "reference" else images[spp][layer]
            axis = axes[row][column]
            axis.imshow(np.clip(to_display(crop(image, region)), 0, 1), interpolation="nearest")
            axis.set_xticks([])
            axis.set_yticks([])
            if row == 0:
                axis.set_title(LABELS.get(layer, layer))
            if column == 0:
                axis.set_ylabel(f"{name}, {spp} spp")
    figure.suptitle(title)
    figure.savefig(path, dpi=90)
    plt.close(figure)
