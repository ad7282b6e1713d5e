"""gmonrt's EXR files (layout: host/io/exr_image.h) through OpenEXR's Python
bindings: RGB layers as height x width x 3 float64 arrays, and references
written as a lone float `mean` layer. A render names its estimators in the
attribute gmon.estimators (host/film/film_file.c)."""

import numpy as np
import OpenEXR

CHANNELS = ("R", "G", "B")


def read(path):
    """Returns (layers, header): every RGB layer of the file by name ("mean",
    "mon", "gmon", ...) and the header's attributes (metadata included)."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        header = dict(exr.header())
        channels = {name: channel.pixels for name, channel in exr.channels().items()}
    layers = {}
    for name in channels:
        layer, _, channel = name.rpartition(".")
        if channel == "R" and all(f"{layer}.{c}" in channels for c in CHANNELS):
            layers[layer] = np.stack([channels[f"{layer}.{c}"] for c in CHANNELS], axis=-1).astype(np.float64)
    return layers, header


def read_channels(path):
    """(channels, header): every channel of the file by its full name
    ("mean.R", "sets.grid", "sets.0.R.w0", ...) as stored (UINT as uint32)."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        return {name: channel.pixels for name, channel in exr.channels().items()}, dict(exr.header())


def read_layer(path, layer):
    """One RGB layer of a file; a clear error when the file lacks it."""
    layers, _ = read(path)
    if layer not in layers:
        raise ValueError(f"{path} has no '{layer}' layer (it has: {', '.join(sorted(layers)) or 'none'})")
    return layers[layer]


def estimators(header):
    """The estimators a render holds, in its order, from gmon.estimators."""
    listed = header.get("gmon.estimators")
    if not listed:
        raise ValueError("the file has no gmon.estimators attribute (not a gmonrt render)")
    return str(listed).split(",")


def write_layers(path, layers, attributes):
    """Writes `layers` (name -> height x width x 3 image) as float RGB layers
    with ZIP compression, and `attributes` (name -> string) as string
    metadata."""
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    header.update({key: str(value) for key, value in attributes.items()})
    channels = {}
    for name, image in layers.items():
        pixels = np.asarray(image, dtype=np.float32)
        channels.update({f"{name}.{c}": np.ascontiguousarray(pixels[..., i]) for i, c in enumerate(CHANNELS)})
    with OpenEXR.File(header, channels) as exr:
        exr.write(str(path))


def write_mean(path, image, attributes):
    """A reference: `image` as the lone layer `mean` (write_layers)."""
    write_layers(path, {"mean": image}, attributes)
