"""The sweep's metric code on pairs with known answers (run by CTest as
test_metrics, with the scripts' virtual environment)."""

import argparse
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from gmon_sweep import crops, exr, metrics, references, results, sweep, uncertainty  # noqa: E402


def smooth_image(width=48, height=40):
    """A smooth HDR image with values from about 0.05 to 3."""
    y, x = np.mgrid[0:height, 0:width] / 10.0
    return np.stack([1.5 + 1.4 * np.sin(x), 1 + 0.9 * np.cos(y), 0.05 + 0.02 * x * y], axis=-1)


class IdenticalImages(unittest.TestCase):
    def test_no_error_and_ssim_one(self):
        image = smooth_image()
        results = metrics.evaluate(image, image.copy(), {"image": None, "corner": (0, 0, 8, 6)})
        for name, values in results.items():
            self.assertEqual(values["rmse"], 0.0, name)
            self.assertEqual(values["relmse"], 0.0, name)
            self.assertEqual(values["flip"], 0.0, name)
            self.assertEqual(values["rel_bias"], 0.0, name)
            self.assertAlmostEqual(values["ssim"], 1.0, places=12, msg=name)


class ConstantOffset(unittest.TestCase):
    def test_known_rmse_relmse_and_bias(self):
        reference = smooth_image()
        offset = 0.25
        results = metrics.evaluate(reference + offset, reference, {"image": None, "band": (10, 5, 30, 25)})
        for name in results:
            self.assertAlmostEqual(results[name]["rmse"], offset, places=12)
        self.assertAlmostEqual(results["image"]["relmse"], np.mean(offset**2 / (reference**2 + 0.01)), places=12)
        self.assertAlmostEqual(results["image"]["rel_bias"], offset / reference.mean(), places=12)
        self.assertLess(results["image"]["ssim"], 1.0)
        self.assertGreater(results["image"]["flip"], 0.0)

    def test_offset_on_a_crop_only(self):
        reference = smooth_image()
        image = reference.copy()
        image[0:10, 0:12] += 2.0  # rows 0..9, columns 0..11: 120 of 1920 pixels
        self.assertAlmostEqual(metrics.rmse(image, reference, (0, 0, 12, 10)), 2.0, places=12)
        self.assertEqual(metrics.rmse(image, reference, (20, 20, 30, 30)), 0.0)
        self.assertAlmostEqual(metrics.rmse(image, reference), 2.0 * np.sqrt(120 / 1920), places=12)

    def test_larger_error_scores_worse(self):
        reference = smooth_image()
        noise = np.random.default_rng(1).normal(0, 1, reference.shape)
        small = metrics.evaluate(np.abs(reference + 0.02 * noise), reference, {"image": None})["image"]
        large = metrics.evaluate(np.abs(reference + 0.2 * noise), reference, {"image": None})["image"]
        for key in ("rmse", "relmse", "flip"):
            self.assertLess(small[key], large[key], key)
        self.assertGreater(small["ssim"], large["ssim"])


class Display(unittest.TestCase):
    def test_srgb_encoding(self):
        values = metrics.to_display(np.array([-1.0, 0.0, 0.0031308, 0.5, 1.0, 7.0]))
        np.testing.assert_allclose(values, [0.0, 0.0, 0.0031308 * 12.92, 0.735357, 1.0, 1.0], rtol=1e-5)


class Residual(unittest.TestCase):
    def test_halves_with_known_noise(self):
        """Two halves with independent noise of deviation s: their average's
        error has deviation s / sqrt(2), which the residual must estimate."""
        rng = np.random.default_rng(7)
        truth = np.ones((200, 200, 3))
        s = 0.05
        half_a = truth + rng.normal(0, s, truth.shape)
        half_b = truth + rng.normal(0, s, truth.shape)
        residual = references.residuals(half_a, half_b, {"image": None})["image"]
        actual = metrics.rmse((half_a + half_b) / 2, truth)
        self.assertAlmostEqual(residual["rmse"], s / np.sqrt(2), delta=0.01 * s)
        self.assertAlmostEqual(residual["rmse"], actual, delta=0.01 * s)
        # relMSE divides by the reference squared plus 0.01, here about 1.01.
        self.assertAlmostEqual(residual["relmse"], s**2 / 2 / 1.01, delta=0.01 * s**2)

    def test_furnace_reference_residual_is_its_actual_error(self):
        """The furnace's every pixel has expectation 1.96875 (scenes/furnace.pbrt):
        the residual estimated from the halves must match the actual error."""
        root = Path(__file__).resolve().parents[2]
        image, record = references.load(root / "references" / "furnace.exr")
        actual = metrics.rmse(image, np.full_like(image, 1.96875))
        self.assertAlmostEqual(record["residual"]["image"]["rmse"], actual, delta=0.03 * actual)

    def test_floor_flag(self):
        floor = {"rmse": 1.0, "relmse": 0.01}
        self.assertEqual(sweep.floor_columns({"rmse": 1.5, "relmse": 0.03}, floor)["at_floor"], 0)
        self.assertEqual(sweep.floor_columns({"rmse": 1.3, "relmse": 0.03}, floor)["at_floor"], 1)
        self.assertEqual(sweep.floor_columns({"rmse": 1.5, "relmse": 0.015}, floor)["at_floor"], 1)
        self.assertEqual(sweep.floor_columns({"rmse": 1.5, "relmse": 0.03}, None)["at_floor"], "")


class TimeToReach(unittest.TestCase):
    curve = [{"seconds": 1.0, "rmse": 1.0}, {"seconds": 2.0, "rmse": 0.5}, {"seconds": 4.0, "rmse": 0.25}]

    def test_interpolates_in_log_log(self):
        # Error halves when time doubles: error 0.35355 = 2^-1.5 at time 2^1.5.
        self.assertAlmostEqual(uncertainty.time_to_reach(self.curve, 2**-1.5, "rmse"), 2**1.5, places=12)
        self.assertEqual(uncertainty.time_to_reach(self.curve, 0.5, "rmse"), 2.0)

    def test_reached_at_once_or_never(self):
        self.assertEqual(uncertainty.time_to_reach(self.curve, 3.0, "rmse"), 1.0)
        self.assertIsNone(uncertainty.time_to_reach(self.curve, 0.2, "rmse"))


class Crops(unittest.TestCase):
    def test_fractions_to_pixels(self):
        self.assertEqual(crops.to_pixels([0.25, 0.5, 0.75, 1.0], 128, 64), (32, 32, 96, 64))
        self.assertEqual(crops.to_pixels([0.5, 0.5, 0.51, 0.51], 8, 8), (4, 4, 5, 5))  # at least one pixel

    def test_every_scene_has_valid_crops(self):
        root = Path(__file__).resolve().parents[2]
        for scene in sorted((root / "scenes").glob("*.pbrt")):
            named = crops.regions(root / "scenes" / "crops.json", crops.scene_name(scene), 32, 32)
            self.assertGreater(len(named), 1, scene.name)


class SweepEstimators(unittest.TestCase):
    def test_the_mean_is_required(self):
        self.assertEqual(sweep.estimator_list("mean,trimmed"), "mean,trimmed")
        self.assertEqual(sweep.estimator_list("all"), "all")
        with self.assertRaises(argparse.ArgumentTypeError):
            sweep.estimator_list("gmon,trimmed")

    def test_listing(self):
        self.assertEqual(results.listing(["MoN", "G-MoN"]), "MoN and G-MoN")
        self.assertEqual(results.listing(["mean", "MoN", "G-MoN"]), "mean, MoN and G-MoN")


class Files(unittest.TestCase):
    def test_reference_exr_round_trip(self):
        image = smooth_image().astype(np.float32)
        with tempfile.TemporaryDirectory() as directory:
            path = Path(directory) / "r.exr"
            exr.write_mean(path, image, {"gmon.samples": 64, "residualRmse": "0.5"})
            layers, header = exr.read(path)
        self.assertEqual(list(layers), ["mean"])
        np.testing.assert_array_equal(layers["mean"], image)
        self.assertEqual(header["gmon.samples"], "64")
        self.assertEqual(header["residualRmse"], "0.5")

    def test_layers_and_estimators_round_trip(self):
        image = smooth_image().astype(np.float32)
        with tempfile.TemporaryDirectory() as directory:
            path = Path(directory) / "r.exr"
            exr.write_layers(path, {"mean": image, "trimmed": 2 * image}, {"gmon.estimators": "mean,trimmed"})
            layers, header = exr.read(path)
        self.assertEqual(sorted(layers), ["mean", "trimmed"])
        np.testing.assert_array_equal(layers["trimmed"], 2 * image)
        self.assertEqual(exr.estimators(header), ["mean", "trimmed"])
        with self.assertRaises(ValueError):
            exr.estimators({})

    def test_csv_round_trip(self):
        row = {"scene": "s", "sets": 21, "seed": 3, "estimator": "gmon", "spp": 64, "seconds": 1.5, "region": "image",
               "rmse": 0.125, "relmse": 0.5, "ssim": 0.75, "flip": 0.25, "rel_bias": -0.01, "rmse_floor": "",
               "relmse_floor": "", "at_floor": "", "mse": 0.015625, "mse_debiased": 0.0125,
               "mse_debiased_lo": -0.001, "mse_debiased_hi": 0.026, "mse_debiased_includes_zero": 1,
               "relmse_debiased": None, "relmse_debiased_lo": None, "relmse_debiased_hi": None,
               "relmse_debiased_includes_zero": None, "variance_source": "sets"}
        self.assertEqual(tuple(row), sweep.COLUMNS)
        with tempfile.TemporaryDirectory() as directory:
            sweep.write_csv([row], Path(directory) / "s.csv")
            (back,) = sweep.read_csv(Path(directory) / "s.csv")
        self.assertEqual(back, {**row, "rmse_floor": None, "relmse_floor": None, "at_floor": None})


if __name__ == "__main__":
    unittest.main()
