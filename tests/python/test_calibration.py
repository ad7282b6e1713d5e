"""The standard-error calibration's arithmetic (scripts/gmon_sweep/calibration.py)
on arrays and a tiny synthetic EXR with known answers (CTest test_calibration,
with the scripts' virtual environment; no renderer)."""

import argparse
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from gmon_sweep import calibration, exr  # noqa: E402


def one_pixel_row(values):
    """Values as a 1 x n x 3 image (each value in every channel)."""
    return np.repeat(np.asarray(values, dtype=np.float64)[None, :, None], 3, axis=2)


class Calibration(unittest.TestCase):
    def test_known_coverage_median_and_nan(self):
        # |error| / stderr: 0.5, 1.96 (covered), 1.97, 3 (not), and a NaN stderr.
        errors = [0.5, 1.96, 1.97, 3.0, 1.0]
        stderrs = [1.0, 1.0, 1.0, 1.0, np.nan]
        reference = one_pixel_row([0.0] * 5)
        measured = calibration.calibration(-one_pixel_row(errors), one_pixel_row(stderrs), reference)
        self.assertAlmostEqual(measured["coverage"], 2 / 5, places=12)
        self.assertAlmostEqual(measured["median_ratio"], (1.96 + 1.97) / 2, places=12)
        self.assertAlmostEqual(measured["nan_stderr"], 1 / 5, places=12)
        self.assertEqual(measured["low"], 1.0)  # every estimate below the reference
        self.assertAlmostEqual(measured["rmse"], np.sqrt(np.mean(np.square(errors))), places=12)

    def test_a_zero_stderr_covers_only_no_error(self):
        reference = one_pixel_row([1.0, 1.0, 1.0])
        estimate = one_pixel_row([1.0, 1.5, 2.0])
        measured = calibration.calibration(estimate, one_pixel_row([0.0, 0.0, 0.0]), reference)
        self.assertAlmostEqual(measured["coverage"], 1 / 3, places=12)
        self.assertEqual(measured["median_ratio"], np.inf)  # ratios 0, inf, inf
        self.assertEqual(measured["nan_stderr"], 0.0)
        self.assertEqual(measured["low"], 0.0)  # 1.5 and 2 lie above 1

    def test_all_nan(self):
        reference = one_pixel_row([1.0, 2.0])
        measured = calibration.calibration(reference, one_pixel_row([np.nan, np.nan]), reference)
        self.assertEqual(measured["coverage"], 0.0)
        self.assertTrue(np.isnan(measured["median_ratio"]))
        self.assertEqual(measured["nan_stderr"], 1.0)


class Perfect(unittest.TestCase):
    def test_student_t_without_reference_noise(self):
        coverage, median = calibration.perfect(21, 1, 1e12)
        # By the trapezoid rule on t_20's density: P(|t_20| <= 1.96), its 0.75 quantile.
        self.assertAlmostEqual(coverage, 0.935922, places=6)
        self.assertAlmostEqual(median, 0.686954, places=6)

    def test_simulated_set_means_and_reference(self):
        """Normal samples: m set means of spp / m samples each give the mean
        and its standard error as gmonrt computes them, against a reference
        of as many independent samples (widening sqrt(2))."""
        rng = np.random.default_rng(3)
        pixels, sets, spp, sigma, truth = 200_000, 21, 1024, 2.0, 5.0
        set_means = truth + rng.normal(0, sigma / np.sqrt(spp / sets), (pixels, sets))
        estimate = set_means.mean(axis=1)
        stderr = set_means.std(axis=1, ddof=1) / np.sqrt(sets)
        reference = truth + rng.normal(0, sigma / np.sqrt(spp), pixels)
        measured = calibration.calibration(estimate, stderr, reference)
        coverage, median = calibration.perfect(sets, spp, spp)
        self.assertAlmostEqual(coverage, 0.818971, places=6)  # P(|t_20| <= 1.96 / sqrt(2)), as above
        self.assertAlmostEqual(measured["coverage"], coverage, delta=0.004)  # 4 sigma of 200 000 draws
        self.assertAlmostEqual(measured["median_ratio"], median, delta=0.01)


class Files(unittest.TestCase):
    def test_every_estimator_of_a_render_in_its_order(self):
        reference = np.ones((2, 4, 3))
        layers = {"mean": reference + 0.1, "mean.stderr": np.full((2, 4, 3), 0.1),
                  "trimmed": reference + 0.3, "trimmed.stderr": np.full((2, 4, 3), 0.1)}
        with tempfile.TemporaryDirectory() as directory:
            path = Path(directory) / "render.exr"
            exr.write_layers(path, layers, {"gmon.estimators": "trimmed,mean", "gmon.sets": 21})
            sets, measured = calibration.measure_file(path, reference)
            self.assertEqual(sets, 21)
            self.assertEqual(list(measured), ["trimmed", "mean"])
            self.assertEqual(measured["mean"]["coverage"], 1.0)
            self.assertEqual(measured["trimmed"]["coverage"], 0.0)
            self.assertAlmostEqual(measured["trimmed"]["median_ratio"], 3.0, places=5)  # float32 layers

            del layers["trimmed.stderr"]
            exr.write_layers(path, layers, {"gmon.estimators": "mean,trimmed", "gmon.sets": 21})
            with self.assertRaisesRegex(ValueError, "no trimmed.stderr layer"):
                calibration.measure_file(path, reference)

    def test_tables(self):
        row = {"scene": "box", "spp": 64, "sets": 21, "reference_spp": 8192, "residual_rmse": 0.01,
               "estimator": "mean", "coverage": 0.9, "median_ratio": 0.7, "nan_stderr": 0.0, "low": 0.75, "rmse": 0.1}
        rows = [row, {**row, "estimator": "gmon", "coverage": 0.5}]
        self.assertIn("| box | 64 | mean | 0.900 | 0.700 | 0.00% | 75% | 0.1 |", calibration.long_table(rows))
        self.assertEqual(calibration.pivot_table(rows, "coverage"),
                         ["| estimator | box 64 |", "| --- | --- |", "| mean | 0.900 |", "| gmon | 0.500 |"])
        # 1 + 64 / 8192 widens the error; the reference's MSE over the mean's: 0.01^2 / 0.1^2.
        (line,) = calibration.expectations_table(rows)[2:]
        self.assertEqual(line, "| box | 64 | 21 | 8192 | 0.935 | 0.690 | 0.01 | 1.0% |")

    def test_spp_must_be_checkpoints(self):
        self.assertEqual(calibration.spp_list("64,256,1024"), [64, 256, 1024])
        with self.assertRaises(argparse.ArgumentTypeError):
            calibration.spp_list("64,100")


if __name__ == "__main__":
    unittest.main()
