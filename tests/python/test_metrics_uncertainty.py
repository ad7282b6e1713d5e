"""Debiased metrics and intervals over seeds (gmon_sweep.uncertainty) on
synthetic data whose truth is known (CTest test_metrics_uncertainty, with the
scripts' virtual environment; no renderer needed)."""

import math
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from gmon_sweep import metrics, sweep, uncertainty  # noqa: E402


def smooth_image(width=64, height=48):
    """A smooth image with values from about 0.2 to 3."""
    y, x = np.mgrid[0:height, 0:width] / 10.0
    return np.stack([1.5 + 1.2 * np.sin(x), 1 + 0.8 * np.cos(y), 0.3 + 0.02 * x * y], axis=-1)


def words(values):
    """Signed integers (below 2^126 in magnitude) as the four uint32 words of
    gmonrt's sets.* channels, w0 the lowest."""
    out = [np.zeros(np.shape(values), dtype=np.uint32) for _ in range(4)]
    for index, value in np.ndenumerate(np.asarray(values, dtype=object)):
        unsigned = int(value) % 2**128  # two's complement
        for k in range(4):
            out[k][index] = (unsigned >> (32 * k)) & 0xFFFFFFFF
    return out


def set_channels(sums_in_units, grid_word):
    """sets.* channels of integer sums (M x height x width x 3) in units of
    2^(grid_word - 1024)."""
    channels = {"sets.grid": np.full(sums_in_units.shape[1:3], grid_word, dtype=np.uint32)}
    for j in range(sums_in_units.shape[0]):
        for c, name in enumerate("RGB"):
            for k, word in enumerate(words(sums_in_units[j, ..., c])):
                channels[f"sets.{j}.{name}.w{k}"] = word
    return channels


class Intervals(unittest.TestCase):
    def test_student_t(self):
        mean, low, high = uncertainty.t_interval([1.0, 2.0, 3.0, 4.0])
        # sd = 1.29099, t_{0.975, 3} = 3.18245: half width 2.05426.
        self.assertEqual(mean, 2.5)
        self.assertAlmostEqual(high - mean, 3.182446305 * 1.290994449 / 2, places=6)
        self.assertAlmostEqual(mean - low, high - mean, places=12)

    def test_constant_values_give_a_zero_width_interval(self):
        self.assertEqual(uncertainty.t_interval([1.0] * 4), (1.0, 1.0, 1.0))

    def test_one_value_has_no_interval(self):
        mean, low, high = uncertainty.t_interval([2.0])
        self.assertEqual(mean, 2.0)
        self.assertTrue(math.isnan(low) and math.isnan(high))

    def test_coverage_of_normal_means(self):
        """Over many draws of 4 normal values, the interval covers the true
        mean about 95% of the time (t, not z: z would cover about 88%)."""
        rng = np.random.default_rng(3)
        covered = [low <= 0 <= high for low, high in
                   (uncertainty.t_interval(rng.normal(0, 1, 4))[1:] for _ in range(4000))]
        self.assertAlmostEqual(np.mean(covered), 0.95, delta=0.015)

    def test_verdict_and_zero(self):
        self.assertEqual(uncertainty.verdict(0.5, 0.9), "better")
        self.assertEqual(uncertainty.verdict(1.1, 1.3), "worse")
        self.assertEqual(uncertainty.verdict(0.9, 1.1), "undecided")
        self.assertEqual(uncertainty.verdict(math.nan, math.nan), "undecided")
        self.assertEqual(uncertainty.includes_zero(-0.1, 0.2), 1)
        self.assertEqual(uncertainty.includes_zero(0.1, 0.2), 0)
        self.assertEqual(uncertainty.includes_zero(math.nan, math.nan), 1)


class Sets(unittest.TestCase):
    def test_round_robin_counts(self):
        np.testing.assert_array_equal(uncertainty.set_counts(0, 10, 3), [4, 3, 3])
        # Samples 2..6 go to sets 2, 0, 1, 2, 0.
        np.testing.assert_array_equal(uncertainty.set_counts(2, 5, 3), [2, 1, 2])
        self.assertEqual(uncertainty.set_counts(4096, 4096, 21).sum(), 4096)

    def test_decoding_128_bit_sums(self):
        sums = np.array([2**100 + 12345, -(2**70) - 7, 0, -1], dtype=object).reshape(4, 1, 1, 1)
        sums = np.repeat(sums, 3, axis=3)  # the same value in R, G and B
        channels = set_channels(sums, 1024 - 40)  # units of 2^-40
        decoded, counts = uncertainty.set_sums(channels, {"gmon.sets": 4, "gmon.samples": "9"})
        expected = [(2**100 + 12345) * 2.0**-40, (-(2**70) - 7) * 2.0**-40, 0.0, -(2.0**-40)]
        for j in range(4):
            self.assertEqual(decoded[j, 0, 0, 1], expected[j], j)
        np.testing.assert_array_equal(counts, [3, 2, 2, 2])

    def test_a_render_without_sets(self):
        self.assertIsNone(uncertainty.set_sums({"mean.R": np.zeros((2, 2))}, {"gmon.sets": 21}))

    def test_variance_with_equal_counts_is_the_set_means_variance_over_m(self):
        rng = np.random.default_rng(5)
        means = rng.normal(2, 0.3, (8, 4, 5, 3))
        counts = np.full(8, 16)
        v = uncertainty.variance_from_sets([(means * 16, counts)])
        np.testing.assert_allclose(v, np.var(means, axis=0, ddof=1) / 8, rtol=1e-12)

    def test_variance_is_unbiased_with_unequal_counts(self):
        """Sets of 3, 3, 2 and 1 samples of deviation s: the mean of all 9
        has variance s^2 / 9, which v must estimate without bias."""
        rng = np.random.default_rng(6)
        counts = np.array([3, 3, 2, 1])
        s, shape = 0.5, (200, 200, 3)
        sums = np.stack([rng.normal(0, s, (n, *shape)).sum(axis=0) for n in counts])
        v = uncertainty.variance_from_sets([(sums, counts)])
        self.assertAlmostEqual(v.mean(), s**2 / 9, delta=0.02 * s**2 / 9)
        # Ignoring the counts (variance of the set means over M) is biased here.
        naive = np.var(sums / counts.reshape(-1, 1, 1, 1), axis=0, ddof=1).mean() / 4
        self.assertGreater(abs(naive - s**2 / 9), 0.1 * s**2 / 9)


class DebiasedKnownNoise(unittest.TestCase):
    """A smooth truth; a reference of M = 16 set means with per-sample
    deviation s_r; an independent estimate with deviation s_x. The true MSE
    is known: s_x^2 in expectation, mean((x - truth)^2) for this draw."""

    @classmethod
    def setUpClass(cls):
        rng = np.random.default_rng(11)
        # Values 1.2 to 12: the reference's relative noise stays under 5%, where
        # relMSE's denominator r^2 + 0.01 is close enough to the truth's.
        cls.truth = 4 * smooth_image()
        sets, per_set, s_r, cls.s_x = 16, 4, 0.4, 0.1
        counts = np.full(sets, per_set)
        sums = np.stack([per_set * cls.truth + rng.normal(0, s_r * math.sqrt(per_set), cls.truth.shape)
                         for _ in range(sets)])
        cls.reference = sums.sum(axis=0) / counts.sum()
        cls.reference_variance = s_r**2 / counts.sum()  # 0.0025: a quarter of the estimate's MSE
        cls.variance = uncertainty.variance_from_sets([(sums, counts)])
        cls.image = cls.truth + rng.normal(0, cls.s_x, cls.truth.shape)
        cls.true_mse = metrics.rmse(cls.image, cls.truth) ** 2
        cls.true_relmse = metrics.relmse(cls.image, cls.truth)

    def check_covers(self, result):
        self.assertLessEqual(result["mse_debiased_lo"], self.true_mse)
        self.assertGreaterEqual(result["mse_debiased_hi"], self.true_mse)
        self.assertLessEqual(result["mse_debiased_lo"], self.s_x**2)
        self.assertGreaterEqual(result["mse_debiased_hi"], self.s_x**2)
        # The raw MSE is off by the reference's variance, beyond the interval.
        self.assertGreater(result["mse"], result["mse_debiased_hi"])
        self.assertAlmostEqual(result["mse"] - result["mse_debiased"], self.reference_variance,
                               delta=0.15 * self.reference_variance)
        self.assertLessEqual(result["relmse_debiased_lo"], self.true_relmse)
        self.assertGreaterEqual(result["relmse_debiased_hi"], self.true_relmse)
        self.assertEqual(result["mse_debiased_includes_zero"], 0)

    def test_from_sets(self):
        noise = uncertainty.ReferenceNoise(self.variance, source="sets")
        self.check_covers(uncertainty.debiased(self.image, self.reference, noise))

    def test_from_halves(self):
        rng = np.random.default_rng(12)
        deviation = math.sqrt(2 * self.reference_variance)  # each half has twice the whole's variance
        half_a = self.truth + rng.normal(0, deviation, self.truth.shape)
        half_b = self.truth + rng.normal(0, deviation, self.truth.shape)
        reference = (half_a + half_b) / 2
        noise = uncertainty.ReferenceNoise(uncertainty.variance_from_halves(half_a, half_b), source="halves")
        self.check_covers(uncertainty.debiased(self.image, reference, noise))

    def test_from_a_record_of_averages(self):
        """Only the region averages a reference record holds (its residual)."""
        v = self.variance
        floors = {"image": {"rmse": math.sqrt(v.mean()),
                            "relmse": float(np.mean(v / (self.reference**2 + metrics.RELMSE_EPSILON)))}}
        noise = uncertainty.ReferenceNoise(floors=floors, source="halves")
        self.check_covers(uncertainty.debiased(self.image, self.reference, noise))

    def test_on_a_region(self):
        noise = uncertainty.ReferenceNoise(self.variance, source="sets")
        region = (0, 0, 32, 24)
        result = uncertainty.debiased(self.image, self.reference, noise, region, "corner")
        true_mse = metrics.rmse(self.image, self.truth, region) ** 2
        self.assertLessEqual(result["mse_debiased_lo"], true_mse)
        self.assertGreaterEqual(result["mse_debiased_hi"], true_mse)

    def test_no_error_but_the_reference_s_is_at_zero(self):
        """The truth itself as the estimate: the debiased MSE's interval
        includes 0 (marked), while the raw MSE is the reference's variance."""
        noise = uncertainty.ReferenceNoise(self.variance, source="sets")
        result = uncertainty.debiased(self.truth, self.reference, noise)
        self.assertEqual(result["mse_debiased_includes_zero"], 1)
        self.assertEqual(result["relmse_debiased_includes_zero"], 1)
        self.assertGreater(result["mse"], 0.5 * self.reference_variance)

    def test_unknown_noise_leaves_the_debiased_fields_empty(self):
        result = uncertainty.debiased(self.image, self.reference, uncertainty.ReferenceNoise())
        self.assertIsNone(result["mse_debiased"])
        self.assertIsNone(result["mse_debiased_includes_zero"])
        self.assertAlmostEqual(result["mse"], metrics.rmse(self.image, self.reference) ** 2, places=12)


def sweep_row(sets, seed, estimator, spp, seconds, error, region="image"):
    """A sweep.csv row whose error metrics all equal `error`."""
    return {"scene": "s", "sets": sets, "seed": seed, "estimator": estimator, "spp": spp, "seconds": seconds,
            "region": region, "rmse": math.sqrt(error), "relmse": error, "ssim": 1 - error, "flip": error,
            "rel_bias": 0.0, "mse": error, "mse_debiased": error, "relmse_debiased": error}


class OverSeeds(unittest.TestCase):
    """Four seeds: the mean's error 1/spp with a per-seed factor; G-MoN's
    0.5 to 0.6 of the mean's on each seed; MoN's 0.8 to 1.3 (its interval
    includes 1)."""

    @classmethod
    def setUpClass(cls):
        factors = {"gmon": (0.5, 0.6, 0.55, 0.52), "mon": (0.8, 1.3, 0.9, 0.95)}
        cls.rows = []
        for seed, luck in enumerate((1.0, 1.4, 0.7, 1.1)):
            for spp in (1, 2, 4):
                mean = luck / spp
                cls.rows.append(sweep_row(21, seed, "mean", spp, float(spp), mean))
                for estimator, factor in factors.items():
                    cls.rows.append(sweep_row(21, seed, estimator, spp, float(spp), factor[seed] * mean))
        cls.summary = uncertainty.summarise(cls.rows)

    def final(self, estimator):
        return next(r for r in self.summary if r["estimator"] == estimator and r["spp"] == 4)

    def test_the_mean_against_itself_is_exactly_one_with_zero_width(self):
        for row in (r for r in self.summary if r["estimator"] == "mean"):
            for metric in uncertainty.RATIO_METRICS:
                self.assertEqual(row[f"{metric}_ratio"], 1.0)
                self.assertEqual(row[f"{metric}_ratio_lo"], 1.0)
                self.assertEqual(row[f"{metric}_ratio_hi"], 1.0)
                self.assertEqual(row[f"{metric}_verdict"], "undecided")

    def test_paired_ratios_and_verdicts(self):
        gmon, mon = self.final("gmon"), self.final("mon")
        self.assertAlmostEqual(gmon["mse_ratio"], np.mean((0.5, 0.6, 0.55, 0.52)), places=12)
        self.assertLess(gmon["mse_ratio_hi"], 1)
        self.assertEqual(gmon["mse_verdict"], "better")
        self.assertEqual(mon["mse_verdict"], "undecided")
        # Unpaired, G-MoN's interval would overlap the mean's (the seeds' luck
        # spreads both): pairing is what decides.
        mean = self.final("mean")
        self.assertLess(mean["mse_lo"], gmon["mse_hi"])

    def test_metric_intervals_over_seeds(self):
        mean = self.final("mean")
        values = [luck / 4 for luck in (1.0, 1.4, 0.7, 1.1)]
        self.assertEqual(mean["seeds"], 4)
        self.assertEqual((mean["mse"], mean["mse_lo"], mean["mse_hi"]), uncertainty.t_interval(values))

    def test_one_seed_keeps_the_render_s_own_interval(self):
        """With one seed there is no spread over seeds: a debiased value keeps
        its interval over pixels and its mark; the ratios have no interval."""
        row = {**sweep_row(5, 0, "mean", 1, 1.0, 0.5), "mse_debiased_lo": 0.25, "mse_debiased_hi": 0.75,
               "mse_debiased_includes_zero": 0, "relmse_debiased_lo": -0.1, "relmse_debiased_hi": 1.1,
               "relmse_debiased_includes_zero": 1}
        (summary,) = uncertainty.summarise([row])
        self.assertEqual((summary["seeds"], summary["mse_debiased_lo"], summary["mse_debiased_hi"]), (1, 0.25, 0.75))
        self.assertEqual(summary["mse_debiased_includes_zero"], 0)
        self.assertEqual(summary["relmse_debiased_includes_zero"], 1)
        self.assertTrue(math.isnan(summary["mse_lo"]))
        self.assertEqual(summary["mse_ratio"], 1.0)
        self.assertEqual(summary["mse_verdict"], "undecided")

    def test_time_to_reach(self):
        reach = {(r["estimator"], r["metric"]): r for r in uncertainty.reach(self.rows)}
        # G-MoN gets under the mean's final error (luck / 4) by 2 to 4 spp on every seed.
        gmon = reach[("gmon", "relmse")]
        self.assertEqual((gmon["seeds"], gmon["reached"]), (4, 4))
        self.assertLess(gmon["time_ratio_hi"], 1)
        self.assertEqual(reach[("mean", "relmse")]["time_ratio"], 1.0)
        mon = reach[("mon", "relmse")]  # 1.3 x the mean on seed 1: not reached there
        self.assertEqual((mon["seeds"], mon["reached"]), (4, 3))
        self.assertIsNone(mon["time_ratio"])

    def test_summary_csv_columns_are_ordered(self):
        columns = uncertainty.SUMMARY_COLUMNS
        self.assertEqual(columns[:6], ("scene", "sets", "estimator", "spp", "region", "seeds"))
        for metric in uncertainty.SUMMARY_METRICS:
            at = columns.index(metric)
            self.assertEqual(columns[at:at + 3], (metric, f"{metric}_lo", f"{metric}_hi"))
        for metric in uncertainty.RATIO_METRICS:
            at = columns.index(f"{metric}_ratio")
            self.assertEqual(columns[at:at + 4], (f"{metric}_ratio", f"{metric}_ratio_lo", f"{metric}_ratio_hi",
                                                  f"{metric}_verdict"))
        with tempfile.TemporaryDirectory() as directory:
            path = Path(directory) / "summary.csv"
            sweep.write_csv(self.summary, path, columns)
            with open(path) as f:
                self.assertEqual(tuple(f.readline().strip().split(",")), columns)
            back = sweep.read_csv(path)
        gmon = next(r for r in back if r["estimator"] == "gmon" and r["spp"] == 4)
        self.assertEqual(gmon["mse_verdict"], "better")
        self.assertEqual(gmon["seeds"], 4)
        self.assertAlmostEqual(gmon["mse_ratio"], self.final("gmon")["mse_ratio"], places=5)

    def test_sweep_csv_columns(self):
        """sweep.csv: the raw metrics as before, then the debiased ones, each
        value followed by its interval and its includes-zero mark."""
        columns = sweep.COLUMNS
        self.assertEqual(columns[:3], ("scene", "sets", "seed"))
        for key in ("mse_debiased", "relmse_debiased"):
            at = columns.index(key)
            self.assertEqual(columns[at:at + 4], (key, f"{key}_lo", f"{key}_hi", f"{key}_includes_zero"))
        self.assertLess(columns.index("at_floor"), columns.index("mse"))
        self.assertLess(columns.index("mse"), columns.index("mse_debiased"))


if __name__ == "__main__":
    unittest.main()
