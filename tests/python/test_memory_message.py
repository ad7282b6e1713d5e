"""A render refused for memory names what is large (CTest memory_message).
With a large environment map and a 4x4 image, the scene is most of what the
render needs: the refusal names the scene's largest buffers (the map's
texels and sampling distribution) and asks for smaller images, not for a
smaller --resolution, which would not help.
Environment: GMONRT (the renderer), WORK_DIR (scratch)."""

import os
import subprocess
import unittest
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
GMONRT = Path(os.environ.get("GMONRT", ROOT / "build" / "gmonrt"))
WORK = Path(os.environ.get("WORK_DIR", ROOT / "build")) / "memory-message"


def write_pfm(path, rgb):
    """A little-endian colour PFM, rows stored bottom to top."""
    height, width, _ = rgb.shape
    with open(path, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(rgb[::-1], dtype="<f4").tobytes())


SCENE = """LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
WorldBegin
LightSource "infinite" "string filename" "sky.pfm"
Shape "sphere" "float radius" 1
"""


class MemoryMessage(unittest.TestCase):
    def test_a_large_environment_map_is_named(self):
        WORK.mkdir(parents=True, exist_ok=True)
        rng = np.random.default_rng(1)
        write_pfm(WORK / "sky.pfm", rng.random((1024, 1024, 3), dtype=np.float32))
        (WORK / "scene.pbrt").write_text(SCENE)
        env = dict(os.environ, GMON_HOST_MEMORY="24M")
        done = subprocess.run([str(GMONRT), "scene.pbrt", "--spp", "1", "--estimators", "mean", "--outfile",
                               "out.exr"], cwd=WORK, env=env, capture_output=True, text=True)
        print(done.stderr.strip())
        self.assertEqual(done.returncode, 1, done.stderr)
        self.assertIn("GiB of host memory", done.stderr)
        self.assertIn("image texels 12.0 MiB", done.stderr)
        self.assertIn("the scene is most of it: smaller images", done.stderr)
        self.assertNotIn("lower --resolution", done.stderr)


if __name__ == "__main__":
    unittest.main()
