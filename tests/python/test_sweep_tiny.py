"""The sweep end to end on a tiny case (CTest sweep_tiny): a 32x32 reference
of the diffuse Cornell box, a sweep to 64 spp for M = 5 and 21 and two seeds
with the real renderer (debiased metrics, intervals over the seeds), and a
results page from it; a sweep with an extra estimator; the
standard errors' calibration in its quick mode.
Environment: GMONRT (the renderer), WORK_DIR (scratch).
Without an OpenCL device: exit 77 (skipped), or a failure under CI=true."""

import contextlib
import io
import json
import os
import re
import sys
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
from gmon_sweep import calibration, references, renderer, results, sweep, uncertainty  # noqa: E402

GMONRT = Path(os.environ.get("GMONRT", ROOT / "build" / "gmonrt"))
WORK = Path(os.environ.get("WORK_DIR", ROOT / "build")) / "sweep-tiny"
SCENE = ROOT / "scenes" / "cornell-diffuse.pbrt"
# The set-based estimators ("all"), from the rows of kernels/film/passes.h, so
# that a new row needs no change here.
SET_ESTIMATORS = re.findall(r'PASS\(\w+, "([^"]+)", PASS_FLOAT, PASS_ESTIMATE,',
                            (ROOT / "kernels" / "film" / "passes.h").read_text())
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


class TinySweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.reference = WORK / "references" / "cornell-diffuse.exr"
        references.make_reference(GMONRT, SCENE, cls.reference.parent, 1024, "32x32", 1000,
                                  ROOT / "scenes" / "crops.json", WORK)
        cls.out = WORK / "sweeps" / "cornell-diffuse"
        sweep.main([str(SCENE), "--reference", str(cls.reference), "--max-spp", "64", "--sets", "5,21",
                    "--seeds", "2", "--out", str(cls.out), "--gmonrt", str(GMONRT), "--sampler", "sobol-pixel"])
        cls.all_rows = sweep.read_csv(cls.out / "sweep.csv")
        cls.rows = [r for r in cls.all_rows if r["seed"] == 0]
        cls.summary = sweep.read_csv(cls.out / "summary.csv")

    def lines(self):
        """{(sets, estimator, region): rows in file order} of the first seed."""
        lines = {}
        for row in self.rows:
            lines.setdefault((row["sets"], row["estimator"], row["region"]), []).append(row)
        return lines

    def test_columns(self):
        for name, columns in (("sweep.csv", sweep.COLUMNS), ("summary.csv", uncertainty.SUMMARY_COLUMNS),
                              ("reach.csv", uncertainty.REACH_COLUMNS)):
            with open(self.out / name) as f:
                self.assertEqual(f.readline().strip().split(","), list(columns), name)

    def test_two_seeds_rendered_independently(self):
        self.assertEqual(json.loads((self.out / "sweep.json").read_text())["seeds"], [0, 1])
        final = {r["seed"]: r for r in self.all_rows
                 if (r["sets"], r["estimator"], r["region"], r["spp"]) == (21, "mean", "image", 64)}
        self.assertEqual(sorted(final), [0, 1])
        self.assertNotEqual(final[0]["rmse"], final[1]["rmse"])

    def test_debiased_metrics(self):
        """The tiny reference (1024 spp) has a variance layer from its sets:
        every row is debiased, below the raw MSE, with an interval around it."""
        for row in self.all_rows:
            self.assertEqual(row["variance_source"], "sets")
            self.assertLess(row["mse_debiased"], row["mse"])
            self.assertLessEqual(row["mse_debiased_lo"], row["mse_debiased"])
            self.assertGreaterEqual(row["mse_debiased_hi"], row["mse_debiased"])
            self.assertIn(row["mse_debiased_includes_zero"], (0, 1))
            self.assertAlmostEqual(row["mse"], row["rmse"] ** 2, delta=1e-5 * row["mse"])

    def test_summary_over_seeds(self):
        """Two seeds per row; the mean's paired ratio to itself exactly 1 with
        a zero-width interval; every interval around its value."""
        self.assertEqual({r["seeds"] for r in self.summary}, {2})
        self.assertEqual(len(self.summary), len(self.all_rows) // 2)
        for row in self.summary:
            for metric in uncertainty.SUMMARY_METRICS:
                self.assertLessEqual(row[f"{metric}_lo"], row[metric], (metric, row))
                self.assertGreaterEqual(row[f"{metric}_hi"], row[metric], (metric, row))
            if row["estimator"] == "mean":
                for metric in uncertainty.RATIO_METRICS:
                    self.assertEqual((row[f"{metric}_ratio"], row[f"{metric}_ratio_lo"], row[f"{metric}_ratio_hi"]),
                                     (1.0, 1.0, 1.0), metric)
                    self.assertEqual(row[f"{metric}_verdict"], "undecided")

    def test_every_line_has_rising_spp_and_time(self):
        lines = self.lines()
        self.assertEqual({k[:2] for k in lines}, {(m, e) for m in (5, 21) for e in ("mean", "mon", "gmon")})
        self.assertEqual({k[2] for k in lines}, {"image", "light", "shadow", "wall"})
        for key, line in lines.items():
            self.assertEqual([r["spp"] for r in line], [1, 2, 4, 8, 16, 32, 64], key)
            seconds = [r["seconds"] for r in line]
            self.assertTrue(all(a < b for a, b in zip(seconds, seconds[1:])), (key, seconds))

    def test_values_are_sane_and_the_mean_converges(self):
        for row in self.rows:
            self.assertGreaterEqual(row["rmse"], 0)
            self.assertLessEqual(row["ssim"], 1)
            self.assertIn(row["at_floor"], (0, 1))
            self.assertGreater(row["rmse_floor"], 0)
        mean = self.lines()[(21, "mean", "image")]
        self.assertLess(mean[-1]["relmse"], mean[0]["relmse"] / 8)
        self.assertGreater(mean[-1]["ssim"], mean[0]["ssim"])

    def test_the_mean_is_the_same_for_every_m_up_to_rounding(self):
        """sobol-pixel draws sample s of a pixel whatever M is (sobol-sets
        gives each set its own sequence, so its samples depend on M)."""
        self.assertEqual(json.loads((self.out / "sweep.json").read_text())["sampler"], "sobol-pixel")
        lines = self.lines()
        for region in ("image", "light"):
            for a, b in zip(lines[(5, "mean", region)], lines[(21, "mean", region)]):
                for key in ("rmse", "ssim", "flip"):  # the same samples, summed into other sets
                    self.assertAlmostEqual(a[key], b[key], delta=1e-5 * abs(a[key]), msg=(region, key))

    def test_plots_are_written(self):
        for name in ("error-vs-spp.png", "error-vs-time.png", "crops.png"):
            with open(self.out / name, "rb") as f:
                self.assertEqual(f.read(8), PNG_SIGNATURE, name)

    def test_results_page(self):
        docs = WORK / "docs"
        results.main([str(SCENE), "--no-render", "--sweeps", str(WORK / "sweeps"), "--docs", str(docs)])
        page = (docs / "results.md").read_text()
        self.assertIn("# Results: error of mean, MoN and G-MoN against time and samples", page)
        self.assertIn("| 21 | G-MoN |", page)
        self.assertIn("| crop | mean | MoN | G-MoN |", page)
        self.assertIn("| cornell-diffuse | 1024 | 32x32 | 1000 |", page)
        self.assertIn("results/cornell-diffuse-error-vs-time.png", page)
        self.assertIn("Over 2 seeds at 64 spp", page)
        self.assertRegex(page, r"\| 21 \| mean \| [0-9.e-]+ \[[0-9.e-]+, [0-9.e-]+\] \|")
        self.assertIn("| 21 | G-MoN |", page)
        for name in ("cornell-diffuse.csv", "cornell-diffuse-summary.csv", "cornell-diffuse-reach.csv",
                     "cornell-diffuse-error-vs-spp.png", "cornell-diffuse-crops.png"):
            self.assertTrue((docs / "results" / name).is_file(), name)

    def test_an_extra_estimator_is_swept_and_listed(self):
        """--estimators with trimmed: its rows, plots and place on the results
        page come from the renderer's files, not from a fixed list."""
        sweeps = WORK / "sweeps-trimmed"
        out = sweeps / "cornell-diffuse"
        sweep.main([str(SCENE), "--reference", str(self.reference), "--max-spp", "8", "--sets", "5", "--seeds", "1",
                    "--estimators", "mean,mon,gmon,trimmed", "--out", str(out), "--gmonrt", str(GMONRT)])
        rows = sweep.read_csv(out / "sweep.csv")
        self.assertEqual(list(dict.fromkeys(r["estimator"] for r in rows)), ["mean", "mon", "gmon", "trimmed"])
        docs = WORK / "docs-trimmed"
        results.main([str(SCENE), "--no-render", "--sweeps", str(sweeps), "--docs", str(docs)])
        page = (docs / "results.md").read_text()
        self.assertIn("# Results: error of mean, MoN, G-MoN and trimmed against time and samples", page)
        self.assertIn("| 5 | trimmed |", page)
        self.assertIn("| crop | mean | MoN | G-MoN | trimmed |", page)
        self.assertIn("the same for the 4 estimators of one render", page)
        with open(docs / "results" / "cornell-diffuse-crops.png", "rb") as f:
            self.assertEqual(f.read(8), PNG_SIGNATURE)

    def test_per_sample_estimators_are_swept_by_layer(self):
        """clamp (one layer a level) and gabmm: the renderer's checkpoint rows
        name each layer, their RMSE agrees with this script's (sweep.measure_run
        checks it), and the page counts the pixels below zero."""
        sweeps = WORK / "sweeps-per-sample"
        out = sweeps / "cornell-diffuse"
        sweep.main([str(SCENE), "--reference", str(self.reference), "--max-spp", "8", "--sets", "5", "--seeds", "1",
                    "--estimators", "mean,clamp,gabmm", "--out", str(out), "--gmonrt", str(GMONRT)])
        rows = sweep.read_csv(out / "sweep.csv")
        self.assertEqual(list(dict.fromkeys(r["estimator"] for r in rows)),
                         ["mean", "clamp-1", "clamp-1e+01", "clamp-1e+02", "gabmm"])
        final = {r["estimator"]: r for r in rows if r["spp"] == 8 and r["region"] == "image"}
        self.assertLess(final["clamp-1"]["rel_bias"], final["clamp-1e+02"]["rel_bias"])  # clamping darkens
        docs = WORK / "docs-per-sample"
        results.main([str(SCENE), "--no-render", "--sweeps", str(sweeps), "--docs", str(docs)])
        page = (docs / "results.md").read_text()
        self.assertIn("| 5 | clamp-1e+01 |", page)
        self.assertIn("| estimator | M = 5 |", page)
        self.assertRegex(page, r"\| mean \| (0|[0-9]+ of 1024 \(-[0-9.e+-]+\)) \|")

    def test_calibration_quick(self):
        """Every estimator's standard error at 32 and 64 spp against the tiny
        reference: the mean's covers about as t_20 says (0.935), the
        robust estimators' less (their bias is not in the stderr)."""
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            rows = calibration.main([str(SCENE), "--quick", "--references", str(self.reference.parent),
                                     "--out", str(WORK / "calibration"), "--gmonrt", str(GMONRT)])
        self.assertEqual(sorted(r["estimator"] for r in rows), sorted(SET_ESTIMATORS * 2))
        self.assertEqual({r["spp"] for r in rows}, {32, 64})
        mean = {r["spp"]: r for r in rows if r["estimator"] == "mean"}
        for r in mean.values():
            self.assertGreater(r["coverage"], 0.8)
            self.assertLess(r["coverage"], 0.97)
            self.assertEqual(r["nan_stderr"], 0.0)
        mon = next(r for r in rows if r["estimator"] == "mon" and r["spp"] == 64)
        self.assertLess(mon["coverage"], mean[64]["coverage"])
        self.assertIn("| cornell-diffuse | 64 | 21 | 1024 | ", printed.getvalue())

    def test_a_time_budget_stops_early(self):
        out = WORK / "sweep-timed"
        sweep.main([str(SCENE), "--reference", str(self.reference), "--max-spp", "64", "--time", "0.001",
                    "--seeds", "1", "--out", str(out), "--gmonrt", str(GMONRT)])
        spps = sorted({row["spp"] for row in sweep.read_csv(out / "sweep.csv")})
        self.assertGreaterEqual(len(spps), 1)
        self.assertLess(spps[-1], 64)

    def test_the_reference_seed_is_refused(self):
        with self.assertRaises(SystemExit):
            sweep.main([str(SCENE), "--reference", str(self.reference), "--seed", "1000", "--out", str(WORK / "x"),
                        "--gmonrt", str(GMONRT)])
        with self.assertRaises(SystemExit):  # seeds 998, 999, 1000, 1001
            sweep.main([str(SCENE), "--reference", str(self.reference), "--seed", "998", "--seeds", "4",
                        "--out", str(WORK / "x"), "--gmonrt", str(GMONRT)])

    def test_another_resolution_is_refused(self):
        with self.assertRaises(SystemExit):
            sweep.main([str(SCENE), "--reference", str(self.reference), "--resolution", "16x16",
                        "--out", str(WORK / "x"), "--gmonrt", str(GMONRT)])


if __name__ == "__main__":
    renderer.pocl_cache(ROOT / "build" / "pocl-cache")
    if not renderer.has_device(GMONRT):
        if os.environ.get("CI") == "true":
            sys.exit(f"{GMONRT} lists no OpenCL device and CI=true: a missing device is a failure")
        print(f"{GMONRT} lists no OpenCL device: skipping (this fails under CI=true)", file=sys.stderr)
        sys.exit(77)
    unittest.main()
