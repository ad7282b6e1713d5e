"""bench/compare_pbrt.py's statistics and scene rewriting on synthetic inputs
with known answers (run by CTest as compare_pbrt_stats, with the scripts'
virtual environment)."""

import sys
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
import compare_pbrt as cp  # noqa: E402


def seeds(noise, level=1.0, shape=(16, 16, 3)):
    """Two seed images around `level` whose difference is exactly 2 * noise,
    so each pixel's variance estimate is 2 * noise^2 (half the square)."""
    base = np.full(shape, level)
    return base + noise, base - noise


class PixelVariance(unittest.TestCase):
    def test_half_squared_difference_averaged_over_channels(self):
        a = np.zeros((2, 2, 3))
        b = np.zeros((2, 2, 3))
        b[..., 0], b[..., 1], b[..., 2] = 1.0, 2.0, 3.0  # (1 + 4 + 9) / 2 / 3
        np.testing.assert_allclose(cp.pixel_variance(a, b), np.full((2, 2), 14 / 6))

    def test_luminance_weights(self):
        a = np.zeros((1, 1, 3))
        b = np.array([[[1.0, -1.0, 2.0]]])  # luminance difference 0.2126 - 0.7152 + 0.1444
        d = 0.2126 - 0.7152 + 2 * 0.0722
        np.testing.assert_allclose(cp.pixel_variance(a, b, cp.LUMINANCE), [[0.5 * d * d]])


class VarianceRatios(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(7)
        self.noise = rng.choice([-0.1, 0.1], size=(16, 16, 3))  # |noise| 0.1 everywhere
        self.p1, self.p2 = seeds(self.noise)
        self.g1, self.g2 = seeds(2 * self.noise)  # gmonrt: twice the spread, 4x the variance
        self.g1[4:8, 8:12] = 1 + 6 * self.noise[4:8, 8:12]  # one region (x 8, y 4): 36x ... with g2 below
        self.g2[4:8, 8:12] = 1 - 6 * self.noise[4:8, 8:12]

    def test_whole_image_and_regions(self):
        out = cp.compare(self.g1, self.g2, self.p1, self.p2, time_g=1.0, time_p=2.0)
        # 15 regions at 4x, one at 36x: image average (15 * 4 + 36) / 16 = 6
        self.assertAlmostEqual(out["var_ratio"], 6.0, places=12)
        self.assertEqual(out["regions"], 16)
        self.assertAlmostEqual(out["worst_region_ratio"], 36.0, places=12)
        self.assertEqual((out["worst_region_x"], out["worst_region_y"]), (8, 4))
        self.assertEqual(out["regions_at_most_one"], 0.0)
        self.assertAlmostEqual(out["efficiency"], 2.0 / 6.0, places=12)  # (1 x 2) / (6 x 1)
        self.assertAlmostEqual(out["mean_ratio"], 1.0, places=12)
        self.assertGreater(out["chance_worst"], 1.0)
        self.assertAlmostEqual(out["var_ratio_channels"], 6.0, places=12)

    def test_dark_regions_are_left_out(self):
        for image in (self.p1, self.p2, self.g1, self.g2):
            image[4:8, 8:12] *= 0.01  # the 36x region's mean falls to 1% of the others': below 5%
        out = cp.compare(self.g1, self.g2, self.p1, self.p2)
        self.assertEqual(out["regions"], 15)
        self.assertAlmostEqual(out["worst_region_ratio"], 4.0, places=12)

    def test_fraction_at_most_one_and_zero_variance(self):
        g1, g2 = self.p1.copy(), self.p2.copy()  # equal variances: every ratio 1
        g1[0:4, 0:4] = g2[0:4, 0:4] = 1.0  # gmonrt noiseless in region (0, 0): ratio 0
        p1, p2 = self.p1.copy(), self.p2.copy()
        g1[12:16, 12:16] = g2[12:16, 12:16] = p1[12:16, 12:16] = p2[12:16, 12:16] = 1.0  # both noiseless: left out
        p1[0:4, 4:8] = p2[0:4, 4:8] = 1.0  # pbrt-v4 noiseless, gmonrt not: inf
        region = cp.region_ratios(cp.pixel_variance(g1, g2), cp.pixel_variance(p1, p2), 0.5 * (p1 + p2))
        self.assertEqual(region["regions"], 15)
        self.assertEqual(region["worst"], np.inf)
        self.assertEqual((region["worst_x"], region["worst_y"]), (4, 0))
        self.assertAlmostEqual(region["at_most_one"], 14 / 15, places=12)

    def test_partial_edge_regions(self):
        sums, counts = cp.region_sums(np.ones((6, 9)))
        np.testing.assert_array_equal(counts, [[16, 16, 4], [8, 8, 2]])
        np.testing.assert_array_equal(sums, counts)


class LitPixels(unittest.TestCase):
    def test_dark_and_emitter_pixels_excluded(self):
        reference = np.ones((10, 10, 3))
        reference[0, 0] = 0.001  # below 1% of the mean
        reference[0, 1] = 1000.0  # the mean becomes about 11: above 50x it
        mask = cp.lit_mask(reference)
        self.assertFalse(mask[0, 0])
        self.assertFalse(mask[0, 1])
        self.assertEqual(int(mask.sum()), 98)


class MeanRatio(unittest.TestCase):
    def test_scaled_image_and_its_standard_error(self):
        noise = np.zeros((8, 8, 3))
        noise[0:4, 0:4] = 0.4  # one region of 4 whose seeds differ by 0.8 in every channel
        p1, p2 = seeds(noise, shape=(8, 8, 3))
        g1, g2 = 1.1 * p1, 1.1 * p2
        ratio, se, mg, mp = cp.mean_ratio(g1, g2, p1, p2)
        self.assertAlmostEqual(ratio, 1.1, places=12)
        self.assertAlmostEqual(mp, 1.0, places=12)
        # one seed's image-mean variance: (1/4 * 0.8)^2 / 2 = 0.02; two seeds averaged: 0.01
        # relative: gmonrt 0.01 * 1.21 / 1.21 and pbrt-v4 0.01 / 1: se = 1.1 * sqrt(0.02)
        self.assertAlmostEqual(se, 1.1 * np.sqrt(0.02), places=12)
        ratio, se, _, _ = cp.mean_ratio(g1, g2, p1, p2, reference=np.ones((8, 8, 3)), reference_spp=1024)
        self.assertAlmostEqual(ratio, 1.1, places=12)
        self.assertAlmostEqual(se, 1.1 * np.sqrt(0.01 + 0.02 / 16), places=12)


class SceneRewrite(unittest.TestCase):
    SCENE = """# a comment naming Film "rgb" "integer xresolution" [ 9 ]
LookAt 0 0 1  0 0 0  0 1 0
Sampler "halton"
    "integer pixelsamples" [ 16 ]
Film "rgb"
    "string filename" [ "out.exr" ]
    "integer xresolution" [ 1152 ]
    "integer yresolution" 864
WorldBegin
Include "geometry/a.pbrt"
"""

    def test_resolution_replaced(self):
        text = cp.rewrite_scene(self.SCENE, 320, 240)
        self.assertNotIn("1152", text)
        self.assertNotIn("864", text)
        self.assertIn('"integer xresolution" [ 320 ] "integer yresolution" [ 240 ]', text)
        self.assertIn('"string filename" [ "out.exr" ]', text)
        self.assertIn('Sampler "halton"\n    "integer pixelsamples" [ 16 ]', text)
        self.assertIn('[ 9 ]', text)  # comments untouched

    def test_sampler_replaced_or_added(self):
        text = cp.rewrite_scene(self.SCENE, 8, 8, "independent")
        self.assertIn('Sampler "independent"\nFilm "rgb"', text)
        self.assertNotIn("pixelsamples", text)
        without = self.SCENE.replace('Sampler "halton"\n    "integer pixelsamples" [ 16 ]\n', "")
        text = cp.rewrite_scene(without, 8, 8, "independent")
        self.assertIn('Sampler "independent"\nWorldBegin', text)

    def test_scene_sampler(self):
        self.assertEqual(cp.scene_sampler(self.SCENE), "halton")
        self.assertIn("halton", cp.UNSEEDED_PIXEL_SAMPLERS)
        self.assertEqual(cp.scene_sampler('Film "rgb"\nWorldBegin\n'), "zsobol")

    def test_film_resolution_added(self):
        text = cp.rewrite_scene('Film "rgb"\nWorldBegin\n', 5, 7)
        self.assertIn('Film "rgb"\n    "integer xresolution" [ 5 ] "integer yresolution" [ 7 ]\nWorldBegin', text)

    def test_integrator_variant(self):
        """A renders row "the same with `Integrator "volpath"`" takes the row
        above's scene, with its integrator replaced in a copy."""
        import tempfile
        from pathlib import Path
        with tempfile.TemporaryDirectory() as d:
            d = Path(d)
            (d / "renders").mkdir()
            (d / "renders" / "README.md").write_text(
                "| folder | scene file | resolution | integrator |\n| --- | --- | --- | --- |\n"
                "| box | box/box.pbrt | 8x8 | path |\n"
                "| box-volpath | the same with `Integrator \"volpath\"` | 8x8 | volpath |\n")
            table = cp.scene_table(d / "renders")
            self.assertEqual(table["box-volpath"], ("box/box.pbrt", 8, 8))
            self.assertEqual(cp.INTEGRATOR_VARIANTS["box-volpath"], "volpath")
            (d / "box").mkdir()
            (d / "box" / "box.pbrt").write_text('Integrator "path" "integer maxdepth" 5\nWorldBegin\n')
            (d / "box" / "mesh.ply").write_text("ply")
            copy = cp.integrator_variant(d / "box" / "box.pbrt", "volpath", d / "copy")
            self.assertEqual(copy.read_text(), 'Integrator "volpath" "integer maxdepth" 5\nWorldBegin\n')
            self.assertTrue((d / "copy" / "mesh.ply").is_symlink())


if __name__ == "__main__":
    unittest.main()
