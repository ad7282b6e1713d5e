#!/usr/bin/env python3
"""The input-robustness audit of issue 33, rerun: builds hostile inputs
(malformed and mutated images as texture and as environment map, gzip'd
scenes, instancing scenes, light, texture and spectrum parameters), checks
and renders each with gmonrt, and counts the outcomes per family.

Every input must end in one of two ways: a render that exits 0 with finite
pixels, or an error (exit 1, 2 or 3) with a printable message. A crash (a
signal), a hang (past --timeout), an unprintable or empty message, or an
outcome other than the case expects (an input that must be refused but
renders, or a valid one refused) counts as a failure, and the script exits 1.

    scripts/run-python.sh tests/python/input_audit.py [--gmonrt build/gmonrt]
        [--work DIR] [--jobs 2] [--timeout 60] [--only FAMILY] [-v]

CTest runs it as `input_audit`. Needs numpy and OpenEXR (build/venv); the image
files come from image_files.py, shared with the image_inputs test.
"""

import argparse
import gzip
import os
import random
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import OpenEXR

import image_files

ROOT = Path(__file__).resolve().parents[2]

# Outcomes.
OK, ERROR, CRASH, HANG, BAD_MESSAGE, UNEXPECTED = "ok", "error", "crash", "hang", "bad message", "unexpected"
FAILURES = (CRASH, HANG, BAD_MESSAGE, UNEXPECTED)


@dataclass
class Case:
    family: str
    name: str
    files: dict  # relative path -> bytes, or a callable(path) that makes it
    scene: str  # the scene text (scene.pbrt), or a file name among `files` to render
    expect: str  # the render's outcome: OK, ERROR or "any"
    outcome: str = ""
    detail: str = field(default="", repr=False)


# ---------------------------------------------------------------- images


def image_scene(image_name, use):
    """A 4x4 scene using `image_name` as a texture or an environment map."""
    head = ('LookAt 0 0 5  0 0 0  0 1 0\nCamera "perspective" "float fov" 30\n'
            'Film "rgb" "integer xresolution" 4 "integer yresolution" 4 "string filename" "out.exr"\nWorldBegin\n')
    if use == "texture":
        return head + ('LightSource "infinite" "rgb L" [1 1 1]\n'
                       f'Texture "t" "spectrum" "imagemap" "string filename" "{image_name}"\n'
                       'Material "diffuse" "texture reflectance" "t"\nShape "sphere" "float radius" 1\n')
    return head + f'LightSource "infinite" "string filename" "{image_name}"\nShape "sphere" "float radius" 1\n'


def make_fifo(path):
    os.mkfifo(path)


def make_directory(path):
    path.mkdir()


def make_link_to_dev_zero(path):
    os.symlink("/dev/zero", path)


def malformed_images():
    """(name, file name, bytes or maker, expect): image_inputs' valid and
    malformed files (tests/python/image_files.py), every valid one cut at
    six lengths, and things that are not regular files."""
    cases = [(name, name, data, OK) for name, (data, _) in image_files.valid_images().items()]
    cases += [(name, name, data, ERROR) for name, (data, _) in image_files.malformed_images().items()]
    for name, (data, _) in image_files.valid_images().items():
        for keep in sorted({8, 18, 30, len(data) // 2, len(data) - 8, len(data) - 1}):
            if 0 < keep < len(data):
                # Damaged JPEG and GIF coded data that still ends properly
                # decodes (only their structure is checked: docs/scenes.md).
                lenient = name.endswith((".jpg", ".gif"))
                cases.append((f"{name} cut to {keep} bytes", name, data[:keep], "any" if lenient else ERROR))
    cases += [("fifo", "image.png", make_fifo, ERROR), ("directory", "image.png", make_directory, ERROR),
              ("/dev/zero", "image.png", make_link_to_dev_zero, ERROR), ("missing", "image.png", None, ERROR)]
    return cases


def image_family(kind, count_mutations, seed):
    cases = []
    if kind == "images":
        for name, file_name, data, expect in malformed_images():
            for use in ("texture", "environment"):
                files = {} if data is None else {file_name: data}
                cases.append(Case("images", f"{name} as {use}", files, image_scene(file_name, use), expect))
        return cases
    valid = image_files.valid_images()
    rng = random.Random(seed)
    names = sorted(valid)
    for i in range(count_mutations):
        name = names[i % len(names)]
        data = bytearray(valid[name][0])
        for _ in range(rng.randint(1, 4)):
            at = rng.randrange(len(data))
            data[at] = rng.choice((0, 255, rng.randrange(256), data[at] ^ (1 << rng.randrange(8))))
        if rng.random() < 0.2:
            data = data[:rng.randrange(1, len(data))]
        use = "texture" if i % 2 == 0 else "environment"
        cases.append(Case("mutated images", f"{name} mutation {i} as {use}", {name: bytes(data)},
                          image_scene(name, use), "any"))
    return cases


# ---------------------------------------------------------------- gzip

SMALL_SCENE = ('LookAt 0 0 5  0 0 0  0 1 0\nCamera "perspective" "float fov" 30\n'
               'Film "rgb" "integer xresolution" 4 "integer yresolution" 4 "string filename" "out.exr"\n'
               'WorldBegin\nLightSource "infinite" "rgb L" [1 1 1]\nShape "sphere" "float radius" 1\n')


def gzip_family():
    whole = gzip.compress(SMALL_SCENE.encode(), mtime=0)
    cases = [("valid", whole, OK), ("empty", b"", ERROR), ("magic-only", whole[:2], ERROR),
             ("header-only", whole[:10], ERROR), ("missing-trailer", whole[:-8], ERROR),
             ("bad-crc", whole[:-8] + b"\0\0\0\0" + whole[-4:], ERROR),
             ("bad-size", whole[:-4] + b"\x01\0\0\0", ERROR),
             ("two-members", gzip.compress(SMALL_SCENE[:60].encode(), mtime=0) +
              gzip.compress(SMALL_SCENE[60:].encode(), mtime=0), OK),
             ("trailing-garbage", whole + b"garbage", ERROR),
             ("bad-method", whole[:2] + b"\x07" + whole[3:], ERROR),
             ("reserved-flags", whole[:3] + b"\xe0" + whole[4:], ERROR),
             ("not-gzip", SMALL_SCENE.encode(), "any")]
    for keep in (12, 20, len(whole) // 2, len(whole) - 9, len(whole) - 1):
        cases.append((f"cut-to-{keep}", whole[:keep], ERROR))
    flipped = bytearray(whole)
    flipped[len(whole) // 2] ^= 0x55
    cases.append(("flipped-byte", bytes(flipped), ERROR))
    out = []
    for name, data, expect in cases:
        out.append(Case("gzip", name, {"scene.pbrt.gz": data}, "scene.pbrt.gz", expect))
    out.append(Case("gzip", "fifo", {"scene.pbrt.gz": make_fifo}, "scene.pbrt.gz", ERROR))
    return out


# ---------------------------------------------------------------- instancing

INSTANCE_HEAD = ('LookAt 0 0 8  0 0 0  0 1 0\nCamera "perspective" "float fov" 40\n'
                 'Film "rgb" "integer xresolution" 4 "integer yresolution" 4 "string filename" "out.exr"\n'
                 'WorldBegin\nLightSource "infinite" "rgb L" [1 1 1]\n')
BOX = ('Shape "trianglemesh" "point3 P" [-1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1]\n'
       '  "integer indices" [0 1 2 0 2 3 4 6 5 4 7 6 0 4 5 0 5 1 3 2 6 3 6 7 0 3 7 0 7 4 1 5 6 1 6 2]\n')


def instance_scene(body, object_body=BOX):
    return INSTANCE_HEAD + f'ObjectBegin "thing"\n{object_body}ObjectEnd\n' + body


def copies(n, transform=lambda i: ""):
    return "".join(f"AttributeBegin\n{transform(i)}ObjectInstance \"thing\"\nAttributeEnd\n" for i in range(n))


def instancing_family():
    cases = []
    for n in (1, 2, 8, 9, 64, 126, 127, 128, 129, 144, 160, 255, 256, 257, 1000, 4096):
        cases.append((f"{n} identical instances", instance_scene(copies(n)), OK))
    for n in (128, 1000, 5000):
        cases.append((f"{n} scaled copies about one point",
                      instance_scene(copies(n, lambda i: f"Scale {1 + i / n} {1 + i / n} {1 + i / n}\n")), OK))
        cases.append((f"{n} rotated copies", instance_scene(copies(n, lambda i: f"Rotate {i * 0.7} 0 1 1\n")), OK))
    for n in (100, 2000):
        cases.append((f"{n} copies in a row", instance_scene(copies(n, lambda i: f"Translate {i * 0.01} 0 0\n")), OK))
    for s in ("1e30", "1e20", "1e19", "1e-19", "1e-30", "0", "-1", "1e-10"):
        expect = OK if s in ("-1", "1e-10") else ERROR
        cases.append((f"instance scaled by {s}", instance_scene(f"Scale {s} {s} {s}\nObjectInstance \"thing\"\n"), expect))
        # Inside ObjectBegin the transform is the shape's, checked as for any
        # shape: overflow is an error, a mesh scaled to nothing is no error
        # (its triangles are degenerate and invisible, as in pbrt-v4).
        inside = ERROR if s in ("1e30", "1e20", "1e19") else "any"
        cases.append((f"object scaled by {s} inside ObjectBegin",
                      INSTANCE_HEAD + f'ObjectBegin "thing"\nScale {s} {s} {s}\n{BOX}ObjectEnd\nObjectInstance "thing"\n',
                      inside))
    singular = ("Transform [1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1]", "Transform [1 0 0 0  1 0 0 0  0 0 1 0  0 0 0 1]",
                "Scale 1 0 1", "Transform [0 0 0 0  0 0 0 0  0 0 0 0  0 0 0 0]")
    for i, t in enumerate(singular):
        cases.append((f"singular transform {i}", instance_scene(f"{t}\nObjectInstance \"thing\"\n"), ERROR))
    projective = ("Transform [1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1]", "Transform [1 0 0 0  0 1 0 0  0 0 1 1  0 0 0 2]",
                  "Perspective 45 0.1 100")
    for i, t in enumerate(projective):
        cases.append((f"projective transform {i}", instance_scene(f"{t}\nObjectInstance \"thing\"\n"), ERROR))
    for v in ("nan", "inf", "-inf", "1e39"):
        cases.append((f"translate by {v}", instance_scene(f"Translate {v} 0 0\nObjectInstance \"thing\"\n"), ERROR))
    cases += [
        ("unknown object", instance_scene('ObjectInstance "nothing"\n'), ERROR),
        ("instance before WorldBegin", INSTANCE_HEAD.replace("WorldBegin\n", 'ObjectInstance "x"\nWorldBegin\n'), ERROR),
        ("ObjectBegin without ObjectEnd", INSTANCE_HEAD + f'ObjectBegin "thing"\n{BOX}', ERROR),
        ("ObjectEnd without ObjectBegin", INSTANCE_HEAD + "ObjectEnd\n", ERROR),
        ("nested ObjectBegin", INSTANCE_HEAD + f'ObjectBegin "a"\nObjectBegin "b"\n{BOX}ObjectEnd\nObjectEnd\n', ERROR),
        ("instance inside its own object", INSTANCE_HEAD + 'ObjectBegin "a"\nObjectInstance "a"\nObjectEnd\n', ERROR),
        ("empty object", INSTANCE_HEAD + 'ObjectBegin "e"\nObjectEnd\nObjectInstance "e"\n' + BOX, OK),
        ("object defined twice", instance_scene(f'ObjectBegin "thing"\n{BOX}ObjectEnd\nObjectInstance "thing"\n'),
         "any"),
        ("instance of a light-emitting object",
         INSTANCE_HEAD + f'ObjectBegin "lamp"\nAreaLightSource "diffuse" "rgb L" [1 1 1]\n{BOX}ObjectEnd\n'
         'ObjectInstance "lamp"\n', "any"),
        ("sphere objects", instance_scene(copies(300, lambda i: f"Translate {i % 17} {i // 17} 0\n"),
                                         'Shape "sphere" "float radius" 0.4\n'), OK),
    ]
    return [Case("instancing", name, {}, scene, expect) for name, scene, expect in cases]


# ---------------------------------------------------------------- parameters


def parameter_family():
    def scene(world):
        return ('LookAt 0 0 5  0 0 0  0 1 0\nCamera "perspective" "float fov" 30\n'
                'Film "rgb" "integer xresolution" 4 "integer yresolution" 4 "string filename" "out.exr"\n'
                f'WorldBegin\n{world}')
    sphere = 'Shape "sphere" "float radius" 1\n'
    cases = []
    for radius in ("1", "1e-10", "1e-20", "1e-30", "1e20", "1e30"):
        for power in ("10", "1e30", "1e-30"):
            cases.append((f"sphere light power {power} radius {radius}",
                          scene(f'AttributeBegin\nAreaLightSource "diffuse" "float power" [{power}]\n'
                                f'Shape "sphere" "float radius" {radius}\nAttributeEnd\n' + sphere), "any"))
    for light in ("point", "spot", "distant", "infinite"):
        for param, value in (("scale", "1e30"), ("scale", "1e39"), ("scale", "-1"), ("scale", "nan"),
                             ("power", "1e39"), ("power", "-5"), ("power", "0")):
            cases.append((f"{light} {param} {value}",
                          scene(f'LightSource "{light}" "float {param}" [{value}]\n' + sphere), "any"))
    for name, spectrum in (("blackbody 0 K", '"blackbody L" [0]'), ("blackbody -10 K", '"blackbody L" [-10]'),
                           ("blackbody 1e30 K", '"blackbody L" [1e30]'), ("rgb inf", '"rgb L" [inf 1 1]'),
                           ("rgb nan", '"rgb L" [nan 1 1]'), ("rgb negative", '"rgb L" [-1 1 1]'),
                           ("spectrum odd count", '"spectrum L" [400 1 500]'),
                           ("spectrum unsorted", '"spectrum L" [500 1 400 1]'),
                           ("spectrum negative", '"spectrum L" [400 -1 700 -1]'),
                           ("spectrum empty", '"spectrum L" []'),
                           ("spectrum missing file", '"spectrum L" "missing.spd"'),
                           ("spectrum named", '"spectrum L" "stdillum-D65"'),
                           ("spectrum unknown name", '"spectrum L" "stdillum-Q99"')):
        cases.append((f"infinite light {name}", scene(f'LightSource "infinite" {spectrum}\n' + sphere), "any"))
    for name, texture in (("checkerboard huge scale", '"checkerboard" "float uscale" [1e38] "float vscale" [1e38]'),
                          ("checkerboard nan", '"checkerboard" "float uscale" [nan]'),
                          ("scale inf", '"scale" "float scale" [inf]'),
                          ("mix amount nan", '"mix" "float amount" [nan]'),
                          ("imagemap missing", '"imagemap" "string filename" "missing.png"'),
                          ("imagemap no name", '"imagemap"'),
                          ("unknown texture", '"nosuchtexture"'),
                          ("constant huge", '"constant" "rgb value" [1e39 1 1]')):
        cases.append((f"texture {name}",
                      scene('LightSource "infinite" "rgb L" [1 1 1]\n'
                            f'Texture "t" "spectrum" {texture}\nMaterial "diffuse" "texture reflectance" "t"\n'
                            + sphere), "any"))
    return [Case("parameters", name, {}, text, expect) for name, text, expect in cases]


# ---------------------------------------------------------------- running


def printable(text):
    return all(c.isprintable() or c in "\n\t" for c in text)


def exr_finite(path):
    with OpenEXR.File(str(path)) as f:
        for name, channel in f.channels().items():
            if name.startswith("mean") and not np.all(np.isfinite(channel.pixels)):
                return False
    return True


def run(command, directory, timeout):
    """(outcome, exit code, first line of its report) of one gmonrt
    command: CRASH, HANG, BAD_MESSAGE, or "" when it ended normally."""
    try:
        done = subprocess.run(command, cwd=directory, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return HANG, None, f"no exit within {timeout} s"
    # check reports on stdout, a render's errors go to stderr.
    text = done.stderr.decode("utf-8", "replace") + done.stdout.decode("utf-8", "replace")
    message = text.strip().splitlines()[0] if text.strip() else ""
    if done.returncode < 0 or done.returncode > 3:
        return CRASH, done.returncode, f"exit {done.returncode}: {message}"
    if not printable(text):
        return BAD_MESSAGE, done.returncode, repr(text[-200:])
    if done.returncode != 0 and not message:
        return BAD_MESSAGE, done.returncode, f"exit {done.returncode} with no message"
    return "", done.returncode, message


def run_case(index, case, gmonrt, work, timeout):
    """`gmonrt check`, then a render of 1 sample a pixel: neither may crash,
    hang or print an unreadable message; a scene check accepts must render;
    the render's outcome must be the one the case expects."""
    directory = work / f"{index:05d}"
    shutil.rmtree(directory, ignore_errors=True)
    directory.mkdir(parents=True)
    for name, content in case.files.items():
        path = directory / name
        if callable(content):
            content(path)
        else:
            path.write_bytes(content)
    scene = case.scene if case.scene in case.files else "scene.pbrt"
    if scene == "scene.pbrt":
        (directory / scene).write_text(case.scene)
    failure, checked, detail = run([str(gmonrt), "check", scene], directory, timeout)
    if not failure:
        failure, code, detail = run([str(gmonrt), scene, "--spp", "1", "--estimators", "mean", "--quiet", "--outfile",
                                     "out.exr"], directory, timeout)
    if failure:
        case.outcome, case.detail = failure, detail
    elif code == 0:
        finite = exr_finite(directory / "out.exr")
        case.outcome = OK if finite and case.expect != ERROR else UNEXPECTED
        case.detail = ("rendered" if case.expect != ERROR else "rendered, but should be refused") if finite else \
            "rendered non-finite pixels"
    else:
        case.outcome, case.detail = ERROR, detail
        if case.expect == OK or checked == 0:
            case.outcome = UNEXPECTED
            case.detail = f"{'check accepted it, but ' if checked == 0 else ''}the render failed: {detail}"
    if case.outcome not in FAILURES:
        shutil.rmtree(directory, ignore_errors=True)
    return case


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--gmonrt", default=str(ROOT / "build" / "gmonrt"))
    parser.add_argument("--work", default=str(ROOT / "build" / "input-audit"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=60)
    parser.add_argument("--mutations", type=int, default=600, help="mutated images (default 600)")
    parser.add_argument("--seed", type=int, default=33)
    parser.add_argument("--only", help="one family: images, mutated, gzip, instancing, parameters")
    parser.add_argument("-v", "--verbose", action="store_true", help="print every case's outcome")
    args = parser.parse_args()
    work = Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    families = {
        "images": lambda: image_family("images", 0, args.seed),
        "mutated": lambda: image_family("mutated", args.mutations, args.seed),
        "gzip": gzip_family,
        "instancing": instancing_family,
        "parameters": parameter_family,
    }
    cases = []
    for name, make in families.items():
        if not args.only or args.only == name:
            cases += make()
    os.environ.setdefault("POCL_CACHE_DIR", str(ROOT / "build" / "pocl-cache"))
    start = time.monotonic()
    with ThreadPoolExecutor(args.jobs) as pool:
        done = list(pool.map(lambda item: run_case(item[0], item[1], args.gmonrt, work, args.timeout),
                             enumerate(cases)))
    counts = {}
    for case in done:
        counts.setdefault(case.family, {}).setdefault(case.outcome, 0)
        counts[case.family][case.outcome] += 1
        if args.verbose or case.outcome in FAILURES:
            print(f"{case.outcome:>12}  {case.family}: {case.name}: {case.detail}")
    print(f"\n{len(done)} inputs in {time.monotonic() - start:.0f} s")
    outcomes = (OK, ERROR) + FAILURES
    print(f"{'family':<16}" + "".join(f"{o:>13}" for o in outcomes))
    for family, by_outcome in counts.items():
        print(f"{family:<16}" + "".join(f"{by_outcome.get(o, 0):>13}" for o in outcomes))
    failed = sum(1 for case in done if case.outcome in FAILURES)
    print(f"failures: {failed}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
