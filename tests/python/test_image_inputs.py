"""Every image input is a right image or a clear error (CTest image_inputs,
issue 33). Malformed files built here (tests/python/image_files.py), a
FIFO, a directory and /dev/zero, each named by a scene as an environment
map and as a texture: `gmonrt render` and `gmonrt check` exit 1 within a
timeout (a hang fails) with a printable message that names the scene's
file:line, the image and the cause. Valid one-colour images of every format
render that colour, as an environment map and as a texture.
Environment: GMONRT (the renderer), WORK_DIR (scratch)."""

import os
import shutil
import subprocess
import sys
import unittest
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import image_files  # noqa: E402
from gmon_sweep import exr  # noqa: E402

GMONRT = Path(os.environ.get("GMONRT", ROOT / "build" / "gmonrt"))
WORK = Path(os.environ.get("WORK_DIR", ROOT / "build")) / "image-inputs"
TIMEOUT = 120  # seconds; a hang fails the test

CAMERA = """LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 10
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
WorldBegin
"""
# Line 5 names the image in both scenes.
ENVIRONMENT = CAMERA + 'LightSource "infinite" "string filename" "{image}"\n'
TEXTURE = CAMERA + """Texture "t" "spectrum" "imagemap" "string filename" "{image}" "string encoding" "sRGB"
LightSource "infinite" "rgb L" [ 1 1 1 ]
Material "diffuse" "texture reflectance" "t"
Shape "trianglemesh" "point3 P" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ] "integer indices" [ 0 1 2  0 2 3 ]
    "point2 uv" [ 0 0  1 0  1 1  0 1 ]
"""
USES = {"environment": ENVIRONMENT, "texture": TEXTURE}


def printable(text):
    return all(c == "\n" or " " <= c <= "~" for c in text)


def gmonrt(*args):
    return subprocess.run([str(GMONRT), *args], cwd=WORK, capture_output=True, timeout=TIMEOUT,
                          env=dict(os.environ, LC_ALL="C"))


class ImageInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        WORK.mkdir(parents=True)

    def scene(self, use, image):
        path = WORK / f"{use}-{Path(image).name.replace(chr(27), '')}.pbrt"
        path.write_text(USES[use].format(image=image))
        return path.name

    def assert_refused(self, image, expected):
        """Both uses, both commands: exit 1, one clear printable message."""
        for use in USES:
            scene = self.scene(use, image)
            commands = {"check": ["check", scene], "render": [scene, "--spp", "1", "--quiet", "--outfile", "no.exr"]}
            for command, args in commands.items():
                with self.subTest(image=image, use=use, command=command):
                    done = gmonrt(*args)
                    stderr = done.stderr.decode("latin-1")
                    print(f"{use:11} {command:6} exit {done.returncode}: {stderr.strip()}")
                    self.assertEqual(done.returncode, 1, stderr)
                    self.assertTrue(printable(stderr), repr(stderr))
                    self.assertIn(f"{scene}:5:", stderr)
                    self.assertIn(image.replace("\x1b", "\\x1b"), stderr)
                    self.assertIn(expected, stderr)

    def test_malformed_files(self):
        for name, (data, expected) in image_files.malformed_images().items():
            (WORK / name).write_bytes(data)
            self.assert_refused(name, expected)

    def test_fifo_directory_and_device(self):
        os.mkfifo(WORK / "fifo.png")
        (WORK / "directory.png").mkdir()
        for name in ("fifo.png", "directory.png", "/dev/zero"):
            self.assert_refused(name, "not a regular file")

    def test_control_bytes_in_the_name_are_escaped(self):
        name = "esc\x1b[2J.png"
        (WORK / name).write_bytes(image_files.tga(64, 64, header_only=True))
        self.assert_refused(name, "truncated")

    def test_valid_files_render_their_colour(self):
        for name, (data, expected) in image_files.valid_images().items():
            (WORK / name).write_bytes(data)
            for use in USES:
                with self.subTest(image=name, use=use):
                    scene = self.scene(use, name)
                    out = f"{scene}.exr"
                    done = gmonrt(scene, "--spp", "16", "--quiet", "--estimators", "mean", "--outfile", out)
                    self.assertEqual(done.returncode, 0, done.stderr.decode("latin-1"))
                    mean = exr.read_layer(WORK / out, "mean").reshape(-1, 3).mean(axis=0)
                    print(f"{name:18} {use:11} {np.round(mean, 4)} expected {np.round(expected, 4)}")
                    # A spectral round trip of the colour (and, for the
                    # texture, the sampled light): within 3 %.
                    np.testing.assert_allclose(mean, expected, rtol=0.03)


if __name__ == "__main__":
    unittest.main()
