"""bench/compare_samplers.py's statistics on synthetic renders with known
answers, no rendering (run by CTest as compare_samplers_stats, with the
scripts' virtual environment)."""

import math
import sys
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
import compare_samplers as cs  # noqa: E402


def synthetic_render(set_means, seconds=1.0):
    """A render's channels from its M set means (M x H x W x C): the mean of
    the sets and its standard error from their spread, as gmonrt's --stderr
    reports it (sample standard deviation over sqrt(M)); MoN and G-MoN stand
    in as the median of the sets and the mean again."""
    m = set_means.shape[0]
    return {"mean": set_means.mean(axis=0),
            "mean.stderr": set_means.std(axis=0, ddof=1) / math.sqrt(m),
            "mon": np.median(set_means, axis=0),
            "gmon": set_means.mean(axis=0),
            "seconds": seconds}


class VarianceOfMean(unittest.TestCase):
    def test_two_seeds_half_squared_difference(self):
        # ddof=1: two seeds a, b give (a - b)^2 / 2 (ddof=0 would give a quarter)
        a = np.zeros((2, 2, 3))
        b = np.zeros((2, 2, 3))
        b[..., 0], b[..., 1], b[..., 2] = 1.0, 2.0, 3.0
        self.assertAlmostEqual(cs.variance_of_mean([a, b]), (1 + 4 + 9) / 2 / 3, places=12)

    def test_per_pixel_not_across_the_image(self):
        # every seed sees the same image: no variance, however much the pixels differ
        image = np.arange(48, dtype=np.float64).reshape(4, 4, 3)
        self.assertEqual(cs.variance_of_mean([image, image, image]), 0.0)
        # a constant offset per seed: each pixel's variance is the offsets' (ddof=1)
        offsets = [0.0, 1.0, 2.0, 5.0]
        expected = np.var(offsets, ddof=1)
        self.assertAlmostEqual(cs.variance_of_mean([image + o for o in offsets]), expected, places=12)

    def test_one_seed_refused(self):
        with self.assertRaises(ValueError):
            cs.variance_of_mean(np.zeros((1, 2, 2, 3)))


class StderrRatio(unittest.TestCase):
    def test_iid_sets_are_honest(self):
        rng = np.random.default_rng(11)
        sets, seeds, shape = 21, 4, (64, 64, 3)
        level = rng.uniform(0.5, 2.0, size=shape)  # pixels differ in level and spread
        spread = rng.uniform(0.1, 1.0, size=shape)
        renders = [synthetic_render(level + spread * rng.exponential(1.0, size=(sets,) + shape))
                   for _ in range(seeds)]
        ratio = cs.stderr_ratio([r["mean"] for r in renders], [r["mean.stderr"] for r in renders])
        # 4 x 4096 x 3 pixel-channels: the ratio is 1 within a few percent
        self.assertAlmostEqual(ratio, 1.0, delta=0.05)

    def test_negatively_correlated_sets_report_too_large_errors(self):
        # antithetic sets (x, 2 - x): the mean is exact, the sets still spread (sobol-pixel's case)
        rng = np.random.default_rng(3)
        renders = []
        for _ in range(4):
            x = rng.uniform(0.0, 1.0, size=(10, 8, 8, 3))
            renders.append(synthetic_render(np.concatenate([x, 2.0 - x])))
        ratio = cs.stderr_ratio([r["mean"] for r in renders], [r["mean.stderr"] for r in renders])
        self.assertLess(ratio, 1e-12)

    def test_known_values(self):
        means = [np.zeros((2, 2)), np.full((2, 2), 2.0)]  # variance 2 everywhere
        stderrs = [np.full((2, 2), 1.0), np.full((2, 2), math.sqrt(3.0))]  # mean squared stderr 2
        self.assertAlmostEqual(cs.mean_squared_stderr(stderrs), 2.0, places=12)
        self.assertAlmostEqual(cs.stderr_ratio(means, stderrs), 1.0, places=12)
        self.assertTrue(math.isinf(cs.stderr_ratio(means, np.zeros((2, 2, 2)))))
        self.assertTrue(math.isnan(cs.stderr_ratio([means[0], means[0]], np.zeros((2, 2, 2)))))


class Compare(unittest.TestCase):
    def test_rows(self):
        shape = (4, 4, 3)
        # sampler "a": seeds at 1 +- 0.2; "b": at 1 +- 0.1 (a quarter of the variance)
        def render(value, stderr, mon, seconds):
            return {"mean": np.full(shape, value), "mean.stderr": np.full(shape, stderr),
                    "mon": np.full(shape, mon), "gmon": np.full(shape, value), "seconds": seconds}
        renders = {
            "a": [render(1.2, 0.2, 1.0, 2.0), render(0.8, 0.2, 1.0, 4.0)],
            "b": [render(1.1, 0.2, 0.5, 1.0), render(0.9, 0.2, 0.5, 1.0)],
        }
        rows, reference = cs.compare(renders)
        np.testing.assert_allclose(reference, np.ones(shape))  # mean of all four renders
        a, b = rows
        self.assertEqual((a["sampler"], b["sampler"]), ("a", "b"))
        self.assertAlmostEqual(a["var_mean"], 0.08, places=12)  # (0.4)^2 / 2
        self.assertAlmostEqual(b["var_mean"], 0.02, places=12)
        self.assertAlmostEqual(a["var_relative"], 1.0, places=12)
        self.assertAlmostEqual(b["var_relative"], 0.25, places=12)
        self.assertAlmostEqual(a["var_over_stderr2"], 0.08 / 0.04, places=12)
        self.assertAlmostEqual(b["var_over_stderr2"], 0.02 / 0.04, places=12)
        self.assertAlmostEqual(a["mse_mon"], 0.0, places=12)
        self.assertAlmostEqual(b["mse_mon"], 0.25, places=12)
        self.assertAlmostEqual(a["mse_gmon"], 0.04, places=12)
        self.assertAlmostEqual(b["mse_mean"], 0.01, places=12)
        self.assertAlmostEqual(a["seconds"], 3.0, places=12)
        # another order: "b" becomes the baseline, the reference stays the same
        rows, _ = cs.compare(renders, ["b", "a"])
        self.assertAlmostEqual(rows[1]["var_relative"], 4.0, places=12)


class Arguments(unittest.TestCase):
    def test_gmonrt_args_beginning_with_dashes(self):
        args = cs.parse_args(["scene.pbrt", "--gmonrt-args", "--integrator nee", "--seeds", "3"])
        self.assertEqual(args.gmonrt_args, "--integrator nee")
        self.assertEqual(args.seeds, 3)
        self.assertEqual(args.sampler_list, ["independent", "sobol-pixel", "sobol-sets"])
        self.assertEqual((args.sets, args.spp), (21, 64))


if __name__ == "__main__":
    unittest.main()
