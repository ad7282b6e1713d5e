"""Named crops of a scene, from scenes/crops.json: rectangles given as
fractions of the image, turned into pixel regions for one resolution."""

import json
from pathlib import Path


def scene_name(scene_path):
    """cornell-glass for scenes/cornell-glass.pbrt."""
    return Path(scene_path).stem


def load(crops_file, scene):
    """{crop name: (x0, y0, x1, y1) fractions} for `scene`; {} when the file
    names no crops for it."""
    with open(crops_file) as f:
        table = json.load(f)
    crops = table.get(scene, {})
    for name, box in crops.items():
        x0, y0, x1, y1 = box
        if not (0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1):
            raise ValueError(f"{crops_file}: crop {scene}/{name} {box} is not inside [0, 1] with x0 < x1, y0 < y1")
    return crops


def to_pixels(box, width, height):
    """Fractions to a pixel region (x0, y0, x1, y1), x1 and y1 excluded, at
    least one pixel wide and high."""
    x0, y0, x1, y1 = box
    px0, py0 = min(int(x0 * width), width - 1), min(int(y0 * height), height - 1)
    px1, py1 = max(round(x1 * width), px0 + 1), max(round(y1 * height), py0 + 1)
    return (px0, py0, px1, py1)


def regions(crops_file, scene, width, height):
    """{"image": None (the whole image), crop name: pixel region, ...}."""
    named = {name: to_pixels(box, width, height) for name, box in load(crops_file, scene).items()}
    if "image" in named:
        raise ValueError(f"{crops_file}: a crop of {scene} may not be called 'image'")
    return {"image": None, **named}
