"""Running gmonrt."""

import os
import shlex
import subprocess
import time
from pathlib import Path

import numpy as np

from . import exr

ROOT = Path(__file__).resolve().parents[2]  # the repository
GMONRT = ROOT / "build" / "gmonrt"

# Estimates lie between set means, and gmonrt rejects a sample of 2^38 or
# more as non-finite: no estimate it writes can exceed this.
IMPLAUSIBLE = 2.0**38


def shown(path):
    """A path as written to records: relative to the repository if inside it."""
    path = Path(path).resolve()
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def command_line(arguments):
    """The command `build/gmonrt ARGUMENTS` as text, paths shown()."""
    return shlex.join(["build/gmonrt", *(shown(a) if isinstance(a, Path) else str(a) for a in arguments)])


def run(gmonrt, arguments):
    """Runs gmonrt with `arguments` (strings); returns its wall-clock seconds.
    A failure raises RuntimeError with gmonrt's own message."""
    command = [str(gmonrt), *map(str, arguments)]
    start = time.monotonic()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.monotonic() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed (exit {done.returncode}):\n{done.stderr.strip()}")
    return seconds


def has_device(gmonrt):
    """Whether gmonrt lists at least one OpenCL device."""
    done = subprocess.run([str(gmonrt), "--list-devices"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    return done.returncode == 0 and len(done.stdout.strip().splitlines()) > 1


def pocl_cache(default_dir):
    """PoCL lists no device without a writable cache directory: sets
    POCL_CACHE_DIR to `default_dir` unless it is set already."""
    if not os.environ.get("POCL_CACHE_DIR"):
        os.makedirs(default_dir, exist_ok=True)
        os.environ["POCL_CACHE_DIR"] = str(default_dir)


def read_estimate(path, layer):
    """One estimator's image from a gmonrt EXR; RuntimeError when it holds
    non-finite or impossibly large values (a renderer fault, not an estimate)."""
    image = exr.read_layer(path, layer)
    largest = np.abs(image).max(initial=0.0)
    if not np.isfinite(largest) or largest >= IMPLAUSIBLE:
        raise RuntimeError(f"{path}: layer {layer} holds non-finite or impossible values (largest {largest:.3g})")
    return image
