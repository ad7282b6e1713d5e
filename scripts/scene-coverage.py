#!/usr/bin/env python3
"""Runs `gmonrt check` on every top-level pbrt-v4 scene under one or more
corpus directories and prints, as Markdown, a table of what each scene needs
that gmonrt lacks, then the counts the scene-coverage page reports.

    scripts/scene-coverage.py [--gmonrt build/gmonrt] DIR...

A top-level scene is a .pbrt file with a WorldBegin line (include files have
none). Each unsupported feature `check` lists is put in one category:
media (MakeNamedMedium, MediumInterface, the "interface" material), hair
(the "hair" material, "curve" shapes), subsurface, measured, or other. A
scene check cannot read (it stops at the first error) counts as "error",
reported with the error and put with the other gaps. Missing files (geometry,
textures, includes that were not fetched) are counted apart: they are not
unsupported features. Only the Python standard library is used.
"""

import argparse
import os
import re
import subprocess
import sys
from collections import defaultdict

CATEGORIES = ("media", "hair", "subsurface", "measured")

UNSUPPORTED = re.compile(r"^(?P<file>.+?):(?P<line>\d+): unsupported: (?P<message>.*)$")
MISSING = re.compile(r"^(?P<file>.+?):(?P<line>\d+): missing file: .*\((?P<what>[^()]*)\)$")
ERROR = re.compile(r"^gmonrt: (?:(?P<file>/.+?):(?P<line>\d+): )?(?P<message>.*)$")
WORLD_BEGIN = re.compile(rb"^\s*WorldBegin\b", re.MULTILINE)
# Names of scene objects say nothing about the feature: one message for all.
NAMED = re.compile(r'^(MakeNamedMaterial|MakeNamedMedium|NamedMaterial|Texture|ObjectBegin|ObjectInstance) "[^"]*"')
TEXTURE_VALUE = re.compile(r'("texture [^"]+") "[^"]*"')
PATH_VALUE = re.compile(r'"(/[^"]*)"')


def category(message):
    """The category of one unsupported-feature message of `gmonrt check`."""
    if message.startswith(("MakeNamedMedium", "MediumInterface")) or 'Material "interface"' in message:
        return "media"
    if message.startswith(('Material "hair"', 'Shape "curve"')):
        return "hair"
    if message.startswith('Material "subsurface"'):
        return "subsurface"
    if message.startswith('Material "measured"'):
        return "measured"
    return "other"


def normalized(message):
    """The message without the names of the objects and files it is about."""
    message = NAMED.sub(lambda m: m.group(1) + ' "…"', message)
    message = TEXTURE_VALUE.sub(r'\1 "…"', message)
    return PATH_VALUE.sub(lambda m: '"' + os.path.basename(m.group(1)) + '"', message)


def top_level_scenes(roots):
    for root in roots:
        for directory, subdirs, files in os.walk(root):
            subdirs.sort()
            for name in sorted(files):
                path = os.path.join(directory, name)
                if name.endswith(".pbrt"):
                    with open(path, "rb") as f:
                        if WORLD_BEGIN.search(f.read()):
                            yield root, path


def check(gmonrt, path):
    """Runs `gmonrt check PATH`; returns (unsupported messages, missing files,
    missing Include/Import files among them, error or None)."""
    run = subprocess.run([gmonrt, "check", path], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    unsupported, missing, includes, error = [], 0, 0, None
    for line in run.stdout.splitlines():
        if m := UNSUPPORTED.match(line):
            unsupported.append(m.group("message"))
        elif m := MISSING.match(line):
            missing += 1
            includes += m.group("what") in ("Include", "Import")
        elif run.returncode == 1 and (m := ERROR.match(line)):
            error = m.group("message")
    if run.returncode not in (0, 1, 3):
        error = f"gmonrt check exited with status {run.returncode}"
    return unsupported, missing, includes, error


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--gmonrt", default=os.path.join(os.path.dirname(__file__), "..", "build", "gmonrt"))
    parser.add_argument("dirs", nargs="+", help="corpus directories (scenes are named relative to their parent)")
    args = parser.parse_args()

    rows, blocking = [], defaultdict(set)  # blocking: normalized "other" message -> scenes
    known = set()  # scenes that also need media, hair, subsurface or measured
    counts = defaultdict(int)
    for root, path in top_level_scenes(args.dirs):
        scene = os.path.relpath(path, os.path.dirname(os.path.abspath(root)))
        unsupported, missing, includes, error = check(args.gmonrt, path)
        features = sorted({normalized(m) for m in unsupported})
        blocked = sorted({category(m) for m in unsupported} | ({"error"} if error else set()))
        for m in features:
            if category(m) == "other":
                blocking[m].add(scene)
        if error:
            blocking["check stops: " + normalized(error)].add(scene)
        others = [c for c in blocked if c not in CATEGORIES]
        if len(others) < len(blocked):
            known.add(scene)
        if not blocked:
            counts["supported"] += 1
            counts["supported, includes missing"] += includes > 0
        elif not others:
            counts["known"] += 1
        else:
            counts["gaps"] += 1
        counts["scenes"] += 1
        rows.append((scene, features, missing, includes, error, blocked))

    print("| scene | unsupported features | missing files (includes) | blocked by |")
    print("| --- | --- | --- | --- |")
    for scene, features, missing, includes, error, blocked in rows:
        listed = "; ".join(f.split(";")[0] for f in features)
        if error:
            listed = (listed + "; " if listed else "") + "check stops: " + normalized(error)
        shown = listed.replace("|", "\\|") or "none"
        print(f"| {scene} | {shown} | {missing} ({includes}) | {', '.join(blocked) or '-'} |")
    print()
    print(f"{counts['scenes']} scenes: {counts['supported']} need nothing unsupported "
          f"({counts['supported, includes missing']} of them with missing Include files, not all read), "
          f"{counts['known']} are blocked only by media/hair/subsurface/measured, "
          f"{counts['gaps']} by something else (listed below).")
    print()
    print("| scenes | of them without media/hair/subsurface/measured | other unsupported feature or error (the check message) |")
    print("| --- | --- | --- |")
    for message, scenes in sorted(blocking.items(), key=lambda item: (-len(item[1]), item[0])):
        print(f"| {len(scenes)} | {len(scenes - known)} | {message.replace('|', chr(92) + '|')} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
