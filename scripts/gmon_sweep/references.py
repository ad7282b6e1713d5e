"""Reference images: the mean of a high sample count with next-event
estimation, rendered as two independent halves (same seed, disjoint sample
ranges) whose average is the reference and whose difference estimates the
reference's own remaining error.

With halves A and B of n/2 samples each, the reference R = (A + B) / 2 has
error variance Var(A) / 2 per pixel, and E[(A - B)^2] = 2 Var(A), so
E[(R - truth)^2] = E[(A - B)^2] / 4:
    residual RMSE   = sqrt(mean((A - B)^2) / 4)
    residual relMSE = mean((A - B)^2 / (R^2 + 0.01)) / 4
An error measured against R includes this residual (the sweep renders with
another seed, so the two errors are independent and their squares add).

The halves are rendered with --write-sets: their set means pooled give the
reference's variance per pixel (uncertainty.variance_from_sets, 2M sets
rather than the halves' one degree of freedom), stored as the `variance`
layer so that the sweep can take it out of every error (debiased metrics).

Writes <out>/<scene>.exr (float `mean` and `variance` layers, ZIP) and
<out>/<scene>.json (settings, the commands, residuals on the whole image and
on each crop: from the halves, and from the sets as residual_from_sets).
"""

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

from . import crops, exr, metrics, renderer, uncertainty

ROOT = renderer.ROOT


def residuals(half_a, half_b, regions):
    """{region name: {"rmse", "relmse"}}: the reference's estimated error."""
    reference = (half_a + half_b) / 2
    return {
        name: {
            "rmse": metrics.rmse(half_a, half_b, region) / 2,
            "relmse": float(
                np.mean(metrics.crop((half_a - half_b) ** 2 / (reference**2 + metrics.RELMSE_EPSILON), region)) / 4
            ),
        }
        for name, region in regions.items()
    }


def residuals_from_variance(reference, variance, regions):
    """{region name: {"rmse", "relmse"}} from a per-pixel variance of the
    reference: sqrt(mean(v)) and mean(v / (r^2 + 0.01))."""
    return {
        name: {
            "rmse": float(np.sqrt(np.mean(metrics.crop(variance, region)))),
            "relmse": float(np.mean(metrics.crop(variance / (reference**2 + metrics.RELMSE_EPSILON), region))),
        }
        for name, region in regions.items()
    }


def make_reference(gmonrt, scene, out_dir, spp, resolution, seed, crops_file, work_dir):
    if spp < 2 or spp % 2:
        raise ValueError(f"--spp {spp}: a reference needs an even sample count (two halves)")
    name = crops.scene_name(scene)
    half = spp // 2
    images, parts, commands, seconds = [], [], [], 0.0
    Path(work_dir).mkdir(parents=True, exist_ok=True)
    for first in (0, half):
        outfile = Path(work_dir) / f"{name}-half-{first}.exr"
        arguments = [scene, "--spp", half, "--first-sample", first, "--seed", seed, "--resolution", resolution,
                     "--integrator", "nee", "--estimators", "mean", "--write-sets", "--quiet", "--outfile", outfile]
        seconds += renderer.run(gmonrt, arguments)
        commands.append(renderer.command_line([*arguments[:-1], outfile.name]))  # the file name, not the temp dir
        images.append(renderer.read_estimate(outfile, "mean"))
        parts.append(uncertainty.read_set_sums(outfile))
    half_a, half_b = images
    reference = (half_a + half_b) / 2
    height, width, _ = reference.shape
    regions = crops.regions(crops_file, name, width, height)
    residual = residuals(half_a, half_b, regions)
    variance = uncertainty.variance_from_sets(parts)
    record = {
        "scene": renderer.shown(scene),
        "resolution": [width, height],
        "spp": spp,
        "seed": seed,
        "integrator": "nee",
        "estimator": "mean",
        "halves": [{"first_sample": 0, "spp": half}, {"first_sample": half, "spp": half}],
        "render_seconds": round(seconds, 1),
        "residual": residual,
        "residual_from_sets": residuals_from_variance(reference, variance, regions),
        "commands": commands,
    }
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    exr.write_layers(out_dir / f"{name}.exr", {"mean": reference, "variance": variance}, {
        "gmon.software": "gmon_sweep.references",
        "gmon.samples": spp,
        "gmon.seed": seed,
        "gmon.firstSample": 0,
        "gmon.sceneFile": renderer.shown(scene),
        "residualRmse": f"{residual['image']['rmse']:.6g}",
        "residualRelmse": f"{residual['image']['relmse']:.6g}",
        "gmon.varianceSource": "sets",
    })
    # Some OpenEXR versions store a ZIP chunk wrongly when zlib does not shrink
    # it (openexr issue 2306): read the file back before trusting it.
    if not np.array_equal(exr.read_layer(out_dir / f"{name}.exr", "mean"), reference.astype(np.float32)):
        raise RuntimeError(f"{out_dir / name}.exr does not read back as written")
    with open(out_dir / f"{name}.json", "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    return record


def load(reference_exr):
    """(reference image, its JSON record or None when there is none beside it)."""
    image = exr.read_layer(reference_exr, "mean")
    record_path = Path(reference_exr).with_suffix(".json")
    record = json.loads(record_path.read_text()) if record_path.exists() else None
    return image, record


def main(argv=None):
    p = argparse.ArgumentParser(prog="make-references.sh", description=__doc__.split("\n\n")[0])
    p.add_argument("scenes", nargs="*", type=Path, help="scene files (default: every scenes/*.pbrt)")
    p.add_argument("--spp", type=int, default=8192, help="samples per pixel in all (default 8192)")
    p.add_argument("--resolution", default="128x128", help="WIDTHxHEIGHT (default 128x128)")
    p.add_argument("--seed", type=int, default=1000, help="seed of both halves (default 1000; sweeps must use another)")
    p.add_argument("--out", type=Path, default=ROOT / "references", help="output directory (default references/)")
    p.add_argument("--crops", type=Path, default=ROOT / "scenes" / "crops.json", help="default scenes/crops.json")
    p.add_argument("--gmonrt", type=Path, default=renderer.GMONRT, help="default build/gmonrt")
    args = p.parse_args(argv)
    renderer.pocl_cache(ROOT / "build" / "pocl-cache")
    scenes = args.scenes or sorted((ROOT / "scenes").glob("*.pbrt"))
    with tempfile.TemporaryDirectory(prefix="gmon-references-") as work_dir:
        for scene in scenes:
            record = make_reference(args.gmonrt, scene, args.out, args.spp, args.resolution, args.seed, args.crops,
                                    work_dir)
            floor = record["residual"]["image"]
            print(f"{args.out / crops.scene_name(scene)}.exr: {args.spp} spp {args.resolution} in "
                  f"{record['render_seconds']} s, residual RMSE {floor['rmse']:.4g}, relMSE {floor['relmse']:.4g}",
                  file=sys.stderr)


if __name__ == "__main__":
    main()
