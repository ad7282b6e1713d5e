#!/usr/bin/env python3
"""gmonrt's samples against upstream pbrt-v4's on the same scenes: image mean,
per-pixel variance (whole image, per 4x4 region, lit surfaces only), wall time
and efficiency, at 64 spp with seeds 1 and 2 on both sides.

    scripts/compare-pbrt.sh                          # every scene of ../shared/pbrt-v4-renders gmonrt renders
    scripts/compare-pbrt.sh --scenes cornell-box,veach-mis --csv build/compare-pbrt.csv
    scripts/compare-pbrt.sh --pbrt /var/tmp/pbrt-v4/build/pbrt --pbrt-sampler independent

pbrt-v4's side is by default the stored renders of ../shared/pbrt-v4-renders
(README.md there: 64 spp seeds 1 and 2, 1024 spp seed 100, *.seconds wall
times); with --pbrt PATH (or --build-pbrt) it is rendered live from a copy of
the scene with the Film resolution (and optionally the Sampler) replaced,
alternating with gmonrt's renders so both share the machine's conditions.
pbrt-v4's "halton" and "sobol" samplers (veach-mis, the killeroos,
caustic-glass ask for them) place a pixel's film samples alike for every
seed, so the two seeds' difference leaves out the variance those positions
add, most of it at edges (a visible light's rim): the script notes it, and
--pbrt-sampler zsobol with a live pbrt-v4 measures it.

The figures (the statistics functions below; tests/python/test_compare_pbrt.py):
- Per-pixel variance of a renderer at N spp: half the squared difference of
  its two seeds' images, per channel, averaged over R, G and B (the mean of
  the three channels' variances; --variance-of luminance: the variance of
  0.2126 R + 0.7152 G + 0.0722 B instead, which counts pbrt-v4's spectral
  colour noise, strongest in B, less). "var g/p" is the ratio
  of the image averages, gmonrt over pbrt-v4 (>1: gmonrt noisier); its "+-"
  is a block standard error over 4x4 regions (regions taken as independent
  draws: it also counts the spread of the true ratio across the image, so it
  overstates the noise).
- Mean ratio: the image mean (all pixels, channels averaged) of gmonrt's two
  seeds averaged, over pbrt-v4's 1024 spp image when there is one (else its
  two 64 spp seeds averaged); "+-": standard error from a block estimate over
  4x4 regions (half the squared difference of the seeds' region means; the
  1024 spp image's from its 64 spp seeds scaled by 64/1024, an upper bound
  for a low-discrepancy sampler).
- Regions: 4x4 pixels; those whose pbrt-v4 mean is at least 5% of the image
  mean are compared; regions where both renderers' variance is exactly zero
  are left out. "worst" is the largest gmonrt/pbrt-v4 ratio among them, at
  its top-left pixel (x, y; y down), "<=1" the fraction with ratio <= 1. A
  region's variance is 16 pixels x 3 channels of squared differences (16 to
  48 degrees of freedom as the channels correlate), so a ratio of equal
  variances reads 0.36-2.8 (95%, F(16,16)) by chance; "chance" is the median
  worst ratio among that many regions if the variances were equal (F(16,16)).
- Lit: the variance ratio without pixels whose pbrt-v4 mean is below 1% of
  the image mean (unlit, background) or above 50x it (emitters seen directly).
- Time: wall seconds of one 64 spp render (mean of the two seeds), scene load
  and, for gmonrt, kernel builds included; stored pbrt-v4 times come from
  *.seconds (2 threads, a shared 2-core machine: approximate).
- Efficiency: (pbrt var x pbrt time) / (gmonrt var x gmonrt time): >1 means
  gmonrt reaches a given error sooner.
"""

import argparse
import csv
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

try:
    import numpy as np
except ImportError:  # pragma: no cover
    sys.exit("compare_pbrt.py: numpy is missing: run it with scripts/compare-pbrt.sh "
             "(or build/venv/bin/python after scripts/python-env.sh)")

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"
REGION = 4  # pixels a region side
REGION_MIN = 0.05  # regions compared: pbrt-v4 mean at least this fraction of the image mean
LIT_MIN = 0.01  # lit pixels: pbrt-v4 mean at least this fraction of the image mean ...
EMITTER = 50.0  # ... and at most this multiple of it
LUMINANCE = (0.2126, 0.7152, 0.0722)  # Rec. 709 / sRGB primaries' Y
INTEGRATOR_VARIANTS = {}  # folder -> integrator: a row "the same with `Integrator "volpath"`" (scene_table)


# ---------------------------------------------------------------- statistics

def channel_mean(image):
    """H x W x C -> H x W (mean over channels); H x W unchanged."""
    image = np.asarray(image, dtype=np.float64)
    return image.mean(axis=-1) if image.ndim == 3 else image


def pixel_variance(a, b, weights=None):
    """Per-pixel variance of one render from two seeds: half the squared
    difference, per channel, averaged over the channels (H x W); with
    `weights` (one a channel, e.g. LUMINANCE) the variance of that weighted sum."""
    d = np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)
    if weights is not None:
        d = d @ np.asarray(weights, dtype=np.float64)
        return 0.5 * d * d
    return channel_mean(0.5 * d * d)


def region_sums(x, size=REGION):
    """Sums of an H x W array over size x size regions (partial regions at the
    right and bottom edges) and each region's pixel count."""
    x = np.asarray(x, dtype=np.float64)
    rows, cols = np.arange(0, x.shape[0], size), np.arange(0, x.shape[1], size)
    sums = np.add.reduceat(np.add.reduceat(x, rows, axis=0), cols, axis=1)
    counts = np.add.reduceat(np.add.reduceat(np.ones(x.shape), rows, axis=0), cols, axis=1)
    return sums, counts


def ratio_se(numerators, denominators):
    """Ratio of sums sum(n)/sum(d) and its standard error with the (n, d) pairs
    as independent draws (the ratio estimator's linearization)."""
    n, d = np.ravel(numerators), np.ravel(denominators)
    total = d.sum()
    if total <= 0:
        return math.inf if n.sum() > 0 else math.nan, math.nan
    ratio = float(n.sum() / total)
    k = n.size
    residual = n - ratio * d
    se = math.sqrt(k / max(k - 1, 1) * float(np.sum(residual * residual))) / total
    return float(ratio), float(se)


def block_mean_variance(a, b, size=REGION):
    """Variance of the image mean (channels averaged) of ONE of two seed
    renders a, b, from the seeds' region means: sum over regions of
    (n_r / N)^2 * (A_r - B_r)^2 / 2."""
    sa, counts = region_sums(channel_mean(a), size)
    sb, _ = region_sums(channel_mean(b), size)
    n = counts.sum()
    d = (sa - sb) / n  # (n_r / N) * (A_r - B_r)
    return float(np.sum(0.5 * d * d))


def mean_ratio(g1, g2, p1, p2, reference=None, reference_spp=None, spp=64):
    """gmonrt's mean over pbrt-v4's and its standard error (block estimate).
    gmonrt: (g1 + g2) / 2. pbrt-v4: `reference` (reference_spp samples) when
    given, its variance the 64 spp seeds' scaled by spp / reference_spp; else
    (p1 + p2) / 2. Returns (ratio, se, gmonrt mean, pbrt mean)."""
    mg = 0.5 * (channel_mean(g1).mean() + channel_mean(g2).mean())
    var_g = 0.5 * block_mean_variance(g1, g2)
    if reference is not None:
        mp = channel_mean(reference).mean()
        var_p = block_mean_variance(p1, p2) * spp / reference_spp
    else:
        mp = 0.5 * (channel_mean(p1).mean() + channel_mean(p2).mean())
        var_p = 0.5 * block_mean_variance(p1, p2)
    if mp <= 0:
        return math.nan, math.nan, float(mg), float(mp)
    ratio = mg / mp
    rel = math.sqrt(var_g / mg**2 + var_p / mp**2) if mg > 0 else math.nan
    return float(ratio), float(ratio * rel), float(mg), float(mp)


def lit_mask(reference, dark=LIT_MIN, emitter=EMITTER):
    """Pixels whose mean (channels averaged) is at least `dark` and at most
    `emitter` times the image mean."""
    m = channel_mean(reference)
    level = m.mean()
    return (m >= dark * level) & (m <= emitter * level)


def chance_worst(regions, dof=16):
    """Median of the largest of `regions` ratios of two equal variances, each
    estimated with `dof` degrees of freedom (an F(dof, dof) variate)."""
    if regions <= 0:
        return math.nan
    from scipy.stats import f
    return float(f.ppf(0.5 ** (1.0 / regions), dof, dof))


def region_ratios(var_g, var_p, reference, size=REGION, min_fraction=REGION_MIN):
    """Per-region variance ratios, gmonrt over pbrt-v4, for regions whose
    reference mean is at least min_fraction of the image mean and where at
    least one variance is nonzero. Returns a dict: regions (count), worst
    (largest ratio; inf where pbrt-v4's variance is 0 and gmonrt's not),
    worst_x, worst_y (its top-left pixel), at_most_one (fraction <= 1),
    ratios (H/size x W/size, NaN for regions left out)."""
    sg, counts = region_sums(var_g, size)
    sp, _ = region_sums(var_p, size)
    sm, _ = region_sums(channel_mean(reference), size)
    level = channel_mean(reference).mean()
    keep = (sm / counts >= min_fraction * level) & ((sg > 0) | (sp > 0))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.where(sp > 0, sg / np.where(sp > 0, sp, 1.0), np.inf)
    ratios = np.where(keep, ratios, np.nan)
    n = int(keep.sum())
    result = {"regions": n, "worst": math.nan, "worst_x": -1, "worst_y": -1,
              "at_most_one": math.nan, "ratios": ratios}
    if n:
        flat = np.where(keep, ratios, -1.0)
        row, col = np.unravel_index(int(np.argmax(flat)), flat.shape)
        result.update(worst=float(ratios[row, col]), worst_x=int(col * size), worst_y=int(row * size),
                      at_most_one=float(np.sum(ratios[keep] <= 1.0) / n))
    return result


def compare(g1, g2, p1, p2, reference=None, reference_spp=None, spp=64, time_g=math.nan, time_p=math.nan,
            weights=None):
    """Every figure for one scene (a dict; see the module's docstring);
    `weights`: pixel_variance's (None: the channels' variances averaged)."""
    for name, image in (("gmonrt seed 2", g2), ("pbrt-v4 seed 1", p1), ("pbrt-v4 seed 2", p2)):
        if np.shape(image) != np.shape(g1):
            raise ValueError(f"{name} is {np.shape(image)}, gmonrt seed 1 {np.shape(g1)}")
    if reference is not None and np.shape(reference)[:2] != np.shape(g1)[:2]:
        reference = None  # a reference at another resolution is no reference
    ref = reference if reference is not None else 0.5 * (np.asarray(p1, np.float64) + np.asarray(p2, np.float64))
    var_g, var_p = pixel_variance(g1, g2, weights), pixel_variance(p1, p2, weights)
    ratio, se, mg, mp = mean_ratio(g1, g2, p1, p2, reference, reference_spp, spp)
    sg, _ = region_sums(var_g)
    sp, _ = region_sums(var_p)
    var_ratio, var_ratio_se = ratio_se(sg, sp)
    lit = lit_mask(ref)
    lit_g, lit_p = var_g[lit].sum(), var_p[lit].sum()
    var_ratio_lit = lit_g / lit_p if lit_p > 0 else (math.inf if lit_g > 0 else math.nan)
    regions = region_ratios(var_g, var_p, ref)
    out = {
        "mean_gmonrt": mg, "mean_pbrt": mp, "mean_ratio": ratio, "mean_ratio_se": se,
        "mean_reference": f"spp{reference_spp}" if reference is not None else f"spp{spp} seeds averaged",
        "var_gmonrt": float(var_g.mean()), "var_pbrt": float(var_p.mean()),
        "var_ratio": var_ratio, "var_ratio_se": var_ratio_se,
        "var_ratio_lit": float(var_ratio_lit), "lit_pixels": float(lit.mean()),
        "regions": regions["regions"], "worst_region_ratio": regions["worst"],
        "worst_region_x": regions["worst_x"], "worst_region_y": regions["worst_y"],
        "regions_at_most_one": regions["at_most_one"], "chance_worst": chance_worst(regions["regions"]),
        "time_gmonrt": time_g, "time_pbrt": time_p,
    }
    def efficiency(vg, vp):
        denominator = vg * time_g
        return float(vp * time_p / denominator) if denominator > 0 else math.nan
    out["efficiency"] = efficiency(out["var_gmonrt"], out["var_pbrt"])
    for name, w in (("channels", None), ("luminance", LUMINANCE)):  # the whole-image ratio both ways
        out[f"var_ratio_{name}"] = ratio_se(*(region_sums(pixel_variance(a, b, w))[0] for a, b in ((g1, g2), (p1, p2))))[0]
    out["efficiency_lit"] = efficiency(float(var_g[lit].mean()) if lit.any() else math.nan,
                                       float(var_p[lit].mean()) if lit.any() else math.nan)
    return out


# ---------------------------------------------------------------- EXR files

def read_rgb(path, layer=None):
    """An RGB image (H x W x 3, float64) from an EXR: `layer`.R/G/B when the
    file has that layer (gmonrt names its mean `mean`), else plain R, G, B
    (pbrt-v4's half-float channels)."""
    import OpenEXR
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = {name: channel.pixels for name, channel in exr.channels().items()}
    for prefix in ([f"{layer}."] if layer else []) + [""]:
        names = [prefix + c for c in "RGB"]
        if all(n in channels for n in names):
            return np.stack([channels[n] for n in names], axis=-1).astype(np.float64)
    raise ValueError(f"{path}: no {layer + ' ' if layer else ''}RGB channels (it has: {', '.join(sorted(channels))})")


# ---------------------------------------------------------------- pbrt-v4 scene copies

TOKEN = re.compile(r'#[^\n]*|"[^"]*"|\[|\]|[^\s"\[\]#]+')


def _directives(text):
    """(name, start, end, tokens) for each directive of a pbrt scene's text:
    tokens are (text, start, end) after the name, up to the next directive."""
    tokens = [(m.group(), m.start(), m.end()) for m in TOKEN.finditer(text) if not m.group().startswith("#")]
    out, i = [], 0
    while i < len(tokens):
        name, start, end = tokens[i]
        j = i + 1
        while j < len(tokens) and not re.fullmatch(r"[A-Z][A-Za-z]*", tokens[j][0]):
            j += 1
        body = tokens[i + 1:j]
        out.append((name, start, body[-1][2] if body else end, body))
        i = j
    return out


def _params(body):
    """A directive's parameters: (name, start, end) of each '"type name" value'."""
    params, k = [], 0
    while k < len(body):
        text, start, _ = body[k]
        if text.startswith('"') and len(text[1:-1].split()) == 2:
            if k + 1 < len(body) and body[k + 1][0] == "[":
                m = k + 1
                while m < len(body) and body[m][0] != "]":
                    m += 1
            else:
                m = k + 1
            m = min(m, len(body) - 1)
            params.append((text[1:-1].split()[1], start, body[m][2]))
            k = m + 1
        else:
            k += 1
    return params


def rewrite_scene(text, width, height, sampler=None):
    """A pbrt-v4 scene's text with the Film's xresolution/yresolution set to
    width x height (added when absent) and, with `sampler`, the Sampler
    directive replaced by `Sampler "<sampler>"` (its parameters dropped:
    --spp sets the count) or added before WorldBegin."""
    edits = []  # (start, end, replacement)
    directives = _directives(text)
    films = [d for d in directives if d[0] == "Film"]
    if not films:
        raise ValueError("the scene file has no Film directive (it may be in an Include: not supported)")
    _, start, end, body = films[0]
    for name, pstart, pend in _params(body):
        if name in ("xresolution", "yresolution"):
            edits.append((pstart, pend, ""))
    edits.append((end, end, f'\n    "integer xresolution" [ {width} ] "integer yresolution" [ {height} ]'))
    if sampler:
        samplers = [d for d in directives if d[0] == "Sampler"]
        if samplers:
            _, start, end, _ = samplers[0]
            edits.append((start, end, f'Sampler "{sampler}"'))
        else:
            world = [d for d in directives if d[0] == "WorldBegin"]
            if not world:
                raise ValueError("the scene file has no WorldBegin before which to add a Sampler")
            edits.append((world[0][1], world[0][1], f'Sampler "{sampler}"\n'))
    for start, end, replacement in sorted(edits, key=lambda e: (e[0], e[1]), reverse=True):
        text = text[:start] + replacement + text[end:]
    return text


# pbrt-v4's samplers whose pixel positions (the film sample, GetPixel2D) do
# not depend on the seed: two seeds' renders then share them, and their
# difference leaves out the variance that comes from them (at edges).
UNSEEDED_PIXEL_SAMPLERS = ("halton", "sobol")


def scene_sampler(text):
    """The Sampler a pbrt scene's text names (pbrt-v4's default: zsobol)."""
    samplers = [body for name, _, _, body in _directives(text) if name == "Sampler"]
    return samplers[0][0][0].strip('"') if samplers and samplers[0] else "zsobol"


def scene_copy(scene, directory, width, height, sampler=None):
    """Writes the rewritten scene into `directory` beside symbolic links to
    everything else in the scene's folder (pbrt-v4 resolves Include, PLY and
    texture paths against the main file's folder); returns its path."""
    for entry in scene.parent.iterdir():
        if entry.name != scene.name and not (directory / entry.name).exists():
            (directory / entry.name).symlink_to(entry)
    copy = directory / scene.name
    copy.write_text(rewrite_scene(scene.read_text(), width, height, sampler))
    return copy


# ---------------------------------------------------------------- renders

class RenderError(RuntimeError):
    pass


def run_timed(command, cwd=None):
    start = time.monotonic()
    done = subprocess.run([str(c) for c in command], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.monotonic() - start
    if done.returncode != 0:
        tail = "\n".join((done.stderr.strip() or done.stdout.strip()).splitlines()[-15:])
        raise RenderError(f"{shlex.join(map(str, command))} failed (exit {done.returncode}):\n{tail}")
    return seconds, done.stdout


def render_gmonrt(args, scene, width, height, seed, outfile):
    command = [args.gmonrt, scene, "--resolution", f"{width}x{height}", "--spp", args.spp, "--seed", seed,
               "--outfile", outfile, "--quiet", "--estimators", "mean", *shlex.split(args.gmonrt_args)]
    seconds, _ = run_timed(command, cwd=scene.parent)
    return read_rgb(outfile, "mean"), seconds


def render_pbrt(args, scene_copy_path, seed, outfile):
    command = [args.pbrt, "--nthreads", args.pbrt_threads, "--spp", args.spp, "--seed", seed,
               "--outfile", outfile, "--quiet", scene_copy_path]
    seconds, _ = run_timed(command, cwd=scene_copy_path.parent)
    return read_rgb(outfile), seconds


def read_seconds(path):
    try:
        return float(path.read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return math.nan


def scene_table(renders):
    """folder -> (scene file relative to the scenes folder, width, height) from
    the table in renders/README.md; a row "the same with `Integrator "X"`"
    takes the row above's file, its integrator replaced (INTEGRATOR_VARIANTS);
    other rows without a .pbrt file are left out."""
    table, last = {}, None
    readme = renders / "README.md"
    if not readme.is_file():
        raise FileNotFoundError(f"{readme} is missing")
    for line in readme.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 3 or not re.fullmatch(r"\d+x\d+", cells[2]):
            continue
        w, h = map(int, cells[2].split("x"))
        variant = re.fullmatch(r'the same with `Integrator "(\w+)"`', cells[1])
        if cells[1].endswith(".pbrt"):
            table[cells[0]] = (cells[1], w, h)
            last = cells[1]
        elif variant and last:
            table[cells[0]] = (last, w, h)
            INTEGRATOR_VARIANTS[cells[0]] = variant.group(1)
    return table


def integrator_variant(scene, integrator, directory):
    """A copy of the scene in `directory` (beside links to its folder's
    files) with its Integrator's type replaced; returns its path."""
    directory.mkdir(parents=True, exist_ok=True)
    for entry in scene.parent.iterdir():
        if entry.name != scene.name and not (directory / entry.name).exists():
            (directory / entry.name).symlink_to(entry)
    copy = directory / scene.name
    copy.write_text(re.sub(r'Integrator\s+"\w+"', f'Integrator "{integrator}"', scene.read_text(), count=1))
    return copy


def compare_scene(args, folder, scene, width, height, workdir, say):
    stored = args.renders / folder
    spp = args.spp
    g, tg, p, tp = {}, {}, {}, {}
    seeds = (1, 2)
    if args.pbrt:
        live = workdir / f"{folder}-pbrt-scene"
        live.mkdir(exist_ok=True)
        copy = scene_copy(scene, live, width, height, args.pbrt_sampler)
    for seed in seeds:
        say(f"  {folder}: gmonrt seed {seed} ...")
        g[seed], tg[seed] = render_gmonrt(args, scene, width, height, seed, workdir / f"{folder}-gmonrt-seed{seed}.exr")
        say(f" {tg[seed]:.1f} s\n")
        if args.pbrt:
            say(f"  {folder}: pbrt-v4 seed {seed} ...")
            p[seed], tp[seed] = render_pbrt(args, copy, seed, workdir / f"{folder}-pbrt-seed{seed}.exr")
            say(f" {tp[seed]:.1f} s\n")
    if not args.pbrt:
        for seed in seeds:
            path = stored / f"spp{spp}-seed{seed}.exr"
            if not path.is_file():
                raise FileNotFoundError(f"{path} is missing (stored renders are 64 spp: use --pbrt for another --spp)")
            p[seed], tp[seed] = read_rgb(path), read_seconds(path.with_suffix(".seconds"))
    pbrt_sampler = args.pbrt_sampler if args.pbrt else None
    pbrt_sampler = pbrt_sampler or scene_sampler(scene.read_text(errors="replace"))
    if pbrt_sampler in UNSEEDED_PIXEL_SAMPLERS:
        say(f"  note: {folder}: pbrt-v4's Sampler \"{pbrt_sampler}\" places a pixel's film samples alike for every "
            "seed: its variance at edges is left out (compare live with --pbrt-sampler zsobol)\n")
    reference, reference_spp = None, None
    ref_path = stored / "spp1024-seed100.exr"
    if ref_path.is_file() and not args.no_reference:
        reference, reference_spp = read_rgb(ref_path), 1024
    figures = compare(g[1], g[2], p[1], p[2], reference, reference_spp, spp,
                      0.5 * (tg[1] + tg[2]), 0.5 * (tp[1] + tp[2]),
                      LUMINANCE if args.variance_of == "luminance" else None)
    figures.update(scene=folder, scene_file=str(scene), resolution=f"{width}x{height}", spp=spp,
                   pbrt_source="live" if args.pbrt else "stored",
                   pbrt_sampler=(args.pbrt_sampler or "as the scene asks"),
                   gmonrt_args=args.gmonrt_args, variance_of=args.variance_of,
                   time_gmonrt_seed1=tg[1], time_gmonrt_seed2=tg[2], time_pbrt_seed1=tp[1], time_pbrt_seed2=tp[2])
    return figures


# ---------------------------------------------------------------- output

COLUMNS = ["scene", "resolution", "spp", "pbrt_source", "pbrt_sampler", "gmonrt_args", "variance_of", "mean_reference",
           "mean_gmonrt", "mean_pbrt", "mean_ratio", "mean_ratio_se", "var_gmonrt", "var_pbrt", "var_ratio",
           "var_ratio_se", "var_ratio_channels", "var_ratio_luminance", "var_ratio_lit", "lit_pixels", "regions", "worst_region_ratio", "worst_region_x",
           "worst_region_y", "regions_at_most_one", "chance_worst", "time_gmonrt", "time_gmonrt_seed1",
           "time_gmonrt_seed2", "time_pbrt", "time_pbrt_seed1", "time_pbrt_seed2", "efficiency",
           "efficiency_lit", "scene_file"]


def fmt(x, digits=3):
    if isinstance(x, float):
        if math.isnan(x):
            return "-"
        if math.isinf(x):
            return "inf"
        return f"{x:.{digits}g}"
    return str(x)


def table(rows):
    head = ["scene", "mean g/p", "var g/p", "Y only", "lit", "worst 4x4 (x,y)", "chance", "<=1",
            "t gmonrt", "t pbrt", "efficiency"]
    body = []
    for r in rows:
        body.append([
            r["scene"],
            f"{r['mean_ratio']:.4f} +- {r['mean_ratio_se']:.4f}",
            f"{fmt(r['var_ratio'])} +- {fmt(r['var_ratio_se'], 2)}",
            fmt(r["var_ratio_luminance"]),
            fmt(r["var_ratio_lit"]),
            f"{fmt(r['worst_region_ratio'])} ({r['worst_region_x']},{r['worst_region_y']})",
            fmt(r["chance_worst"], 2),
            f"{100 * r['regions_at_most_one']:.0f}% of {r['regions']}" if r["regions"] else "-",
            f"{r['time_gmonrt']:.1f} s",
            f"{r['time_pbrt']:.1f} s" if not math.isnan(r["time_pbrt"]) else "-",
            fmt(r["efficiency"]),
        ])
    widths = [max(len(row[i]) for row in [head] + body) for i in range(len(head))]
    lines = ["  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths)))
             for row in [head] + body]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


LEGEND = """\
mean g/p: image mean, gmonrt (seeds 1+2) / pbrt-v4 (its 1024 spp image where stored), +- block SE (4x4 regions)
var g/p: per-pixel variance (half the squared seed difference; channels averaged, or --variance-of luminance),
  image average, gmonrt / pbrt-v4 (>1: gmonrt noisier), +- block SE over 4x4 regions (overstates: counts
  spatial spread)
Y only: the image's variance ratio for the luminance 0.2126 R + 0.7152 G + 0.0722 B alone (pbrt-v4's
  spectral colour noise, strongest in B, counts less)
lit: the var g/p ratio without pixels below 1% or above 50x the image mean (pbrt-v4's), i.e. unlit and emitters
worst 4x4: largest region ratio among regions at >= 5% of the image mean, at pixel (x,y), y down;
  chance: the median worst of as many regions of equal variances (F(16,16)); <=1: regions with ratio <= 1
t: wall seconds of one render (mean of 2 seeds, load and builds included); efficiency:
  (pbrt var x pbrt t) / (gmonrt var x gmonrt t), >1: gmonrt reaches an error sooner"""


# ---------------------------------------------------------------- main

def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=LEGEND)
    p.add_argument("--scenes", default="", help="comma-separated folders of --renders (default: every one gmonrt renders)")
    p.add_argument("--spp", type=int, default=64, help="samples per pixel of each render (default 64; stored pbrt-v4 renders: 64 only)")
    p.add_argument("--gmonrt", type=Path, default=ROOT / "build" / "gmonrt", help="gmonrt binary (default build/gmonrt)")
    p.add_argument("--gmonrt-args", default="", help='extra gmonrt arguments, e.g. "--integrator nee"')
    p.add_argument("--pbrt", type=Path, help="render pbrt-v4 live with this binary instead of the stored renders")
    p.add_argument("--build-pbrt", action="store_true", help="build pbrt-v4 with ../shared/peers/pbrt-v4/build.sh (6-11 min) and render live")
    p.add_argument("--pbrt-sampler", help='live only: replace (or add) the scene\'s Sampler, e.g. "independent"')
    p.add_argument("--pbrt-threads", type=int, default=2, help="live pbrt-v4's --nthreads (default 2)")
    p.add_argument("--renders", type=Path, default=SHARED / "pbrt-v4-renders", help="stored pbrt-v4 renders (default ../shared/pbrt-v4-renders)")
    p.add_argument("--scene-dir", type=Path, default=SHARED / "scenes", help="pbrt-v4 scenes (default ../shared/scenes)")
    p.add_argument("--variance-of", choices=("channels", "luminance"), default="channels",
                   help="per-pixel variance: of each channel, averaged (default), or of the luminance "
                        "(0.2126 R + 0.7152 G + 0.0722 B; pbrt-v4's spectral colour noise then counts less)")
    p.add_argument("--no-reference", action="store_true", help="take pbrt-v4's mean from its 64 spp seeds, not the 1024 spp image")
    p.add_argument("--csv", type=Path, help="also write the figures to this CSV file")
    p.add_argument("--keep", type=Path, help="keep the renders (and live scene copies) in this folder")
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
    if args.pbrt_sampler and not (args.pbrt or args.build_pbrt):
        p.error("--pbrt-sampler needs a live pbrt-v4 (--pbrt PATH or --build-pbrt)")
    if args.spp < 1:
        p.error("--spp must be at least 1")
    return args


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    say = lambda text: (sys.stderr.write(text), sys.stderr.flush())  # noqa: E731
    try:
        import OpenEXR  # noqa: F401
        import scipy  # noqa: F401
    except ImportError as e:
        print(f"compare_pbrt.py: {e}: run it with scripts/compare-pbrt.sh, which sets up build/venv", file=sys.stderr)
        return 2
    if not os.access(args.gmonrt, os.X_OK):
        print(f"compare_pbrt.py: no gmonrt at {args.gmonrt}: run scripts/build.sh (or pass --gmonrt)", file=sys.stderr)
        return 2
    if not os.environ.get("POCL_CACHE_DIR"):  # PoCL shows no device without one
        os.environ["POCL_CACHE_DIR"] = str(ROOT / "build" / "pocl-cache")
    os.makedirs(os.environ["POCL_CACHE_DIR"], exist_ok=True)
    try:
        known = scene_table(args.renders)
    except FileNotFoundError as e:
        print(f"compare_pbrt.py: {e} (pass --renders)", file=sys.stderr)
        return 2

    requested = [s for s in args.scenes.split(",") if s]
    for s in requested:
        if s not in known:
            print(f"compare_pbrt.py: unknown scene '{s}': {args.renders}/README.md lists {', '.join(known)}", file=sys.stderr)
            return 2
    chosen = []
    for folder in requested or list(known):
        scene = args.scene_dir / known[folder][0]
        if not scene.is_file():
            print(f"compare_pbrt.py: {folder}: scene file {scene} is missing", file=sys.stderr)
            return 2
        if not requested:
            check = subprocess.run([str(args.gmonrt), "check", str(scene)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            if check.returncode != 0:
                print(f"note: skipping {folder}: `gmonrt check {scene}` exits {check.returncode}", file=sys.stderr)
                continue
        chosen.append((folder, scene, *known[folder][1:]))
    if not chosen:
        print("compare_pbrt.py: no scene to compare", file=sys.stderr)
        return 2

    if args.build_pbrt and not args.pbrt:
        build = SHARED / "peers" / "pbrt-v4" / "build.sh"
        say(f"building pbrt-v4 with {build} (6-11 minutes) ...\n")
        done = subprocess.run([str(build)], stdout=subprocess.PIPE, text=True)
        lines = done.stdout.strip().splitlines()
        if done.returncode != 0 or not lines:
            print(f"compare_pbrt.py: {build} failed (exit {done.returncode})", file=sys.stderr)
            return 1
        args.pbrt = Path(lines[-1])
    if args.pbrt and not os.access(args.pbrt, os.X_OK):
        print(f"compare_pbrt.py: no pbrt-v4 binary at {args.pbrt}", file=sys.stderr)
        return 2
    if not args.pbrt and args.spp != 64:
        print("compare_pbrt.py: the stored pbrt-v4 renders are 64 spp: use --pbrt for another --spp", file=sys.stderr)
        return 2

    rows = []
    with tempfile.TemporaryDirectory(prefix="compare-pbrt-") as temporary:
        workdir = args.keep or Path(temporary)
        workdir.mkdir(parents=True, exist_ok=True)
        for folder, scene, width, height in chosen:
            if folder in INTEGRATOR_VARIANTS:
                scene = integrator_variant(scene, INTEGRATOR_VARIANTS[folder], workdir / f"{folder}-scene")
            try:
                rows.append(compare_scene(args, folder, scene, width, height, workdir, say))
            except (RenderError, FileNotFoundError, ValueError) as e:
                say("\n")
                print(f"compare_pbrt.py: {folder}: {e}", file=sys.stderr)
                return 1

    pbrt_side = f"live ({args.pbrt}, sampler: {args.pbrt_sampler or 'as the scene asks'})" if args.pbrt else f"stored ({args.renders})"
    print(f"gmonrt {args.gmonrt_args or '(default flags)'} against pbrt-v4 {pbrt_side}, {args.spp} spp, seeds 1 and 2; "
          f"variance of {'each channel, averaged' if args.variance_of == 'channels' else 'the luminance'}")
    print(table(rows))
    print()
    print(LEGEND)
    if args.csv:
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
            writer.writeheader()
            for r in rows:
                writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})
        print(f"wrote {args.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
