"""Error of an image against a reference, on the whole image and on crops.

Images are height x width x 3 arrays of linear radiance.
- RMSE: sqrt of the mean over pixels and channels of (x - r)^2.
- relMSE: the mean over pixels and channels of (x - r)^2 / (r^2 + 0.01).
  Both as gmonrt computes them for --checkpoints with --reference.
- SSIM: scikit-image's structural_similarity on display images (each value
  clamped to [0, 1], then the sRGB transfer function: what the PNG preview
  shows at exposure 1), data_range 1, per channel (channel_axis 2), Gaussian
  window sigma 1.5 (11 x 11), use_sample_covariance False: the settings of
  Wang et al. 2004. The whole image's SSIM is scikit-image's mean (it leaves
  out a 5-pixel border); a crop's is the mean of the SSIM map over the crop.
- rel_bias: (mean(x) - mean(r)) / mean(r), the relative difference of the
  averages (G-MoN's darkening shows here); NaN where mean(r) is 0.
- FLIP: HDR-FLIP (flip-evaluator) with its defaults: 67 pixels per degree,
  ACES tone mapper, exposure range from the reference. One error map on the
  whole image; a region's FLIP is the map's mean over it.
MSE and relMSE with the reference's own variance taken out, and intervals
over seeds: uncertainty.py (docs/estimators.md, "Error you can trust").
"""

import numpy as np
from flip_evaluator import evaluate as flip_evaluate
from skimage.metrics import structural_similarity

RELMSE_EPSILON = 0.01

# Region: (x0, y0, x1, y1) in pixels, x1 and y1 excluded; None is the whole image.


def crop(values, region):
    if region is None:
        return values
    x0, y0, x1, y1 = region
    return values[y0:y1, x0:x1]


def rmse(image, reference, region=None):
    difference = crop(image, region) - crop(reference, region)
    return float(np.sqrt(np.mean(difference**2)))


def relmse(image, reference, region=None):
    image, reference = crop(image, region), crop(reference, region)
    return float(np.mean((image - reference) ** 2 / (reference**2 + RELMSE_EPSILON)))


def relative_bias(image, reference, region=None):
    average = float(np.mean(crop(reference, region)))
    return (float(np.mean(crop(image, region))) - average) / average if average else float("nan")


def to_display(image):
    """Linear radiance to sRGB-encoded values in [0, 1]."""
    x = np.clip(image, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def ssim_map(image, reference):
    """(SSIM of the whole image, per-pixel SSIM map averaged over channels)."""
    mean, full = structural_similarity(
        to_display(reference),
        to_display(image),
        data_range=1.0,
        channel_axis=2,
        gaussian_weights=True,
        sigma=1.5,
        use_sample_covariance=False,
        full=True,
    )
    return float(mean), full.mean(axis=2)


def flip_map(image, reference):
    """HDR-FLIP's per-pixel error map (height x width)."""
    error_map, _, _ = flip_evaluate(
        np.ascontiguousarray(reference, dtype=np.float32),
        np.ascontiguousarray(image, dtype=np.float32),
        "HDR",
        applyMagma=False,
        computeMeanError=False,
    )
    return np.asarray(error_map, dtype=np.float64).reshape(reference.shape[:2])


def evaluate(image, reference, regions):
    """Every metric on each region: {name: {"rmse", "relmse", "ssim",
    "flip"}}; `regions` maps names to a region (None: the whole image)."""
    ssim_whole, ssim_pixels = ssim_map(image, reference)
    flip_pixels = flip_map(image, reference)
    results = {}
    for name, region in regions.items():
        results[name] = {
            "rmse": rmse(image, reference, region),
            "relmse": relmse(image, reference, region),
            "ssim": ssim_whole if region is None else float(np.mean(crop(ssim_pixels, region))),
            "flip": float(np.mean(crop(flip_pixels, region))),
            "rel_bias": relative_bias(image, reference, region),
        }
    return results
