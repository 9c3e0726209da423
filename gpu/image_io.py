"""Writing passes: one multi-layer EXR (linear float) and 8-bit PNGs through a view
transform (gpu/colour_management.py), via OpenImageIO.

OpenImageIO is imported when an image is written, so the rest of gpu/ runs where it is
missing (the GPU machine); where this Python lacks it, Blender's bundled copy serves.
"""
import os

import numpy as np

from .colour_management import ViewTransform, display_values
from .errors import LPVError
from .image_library import openimageio

CHANNELS = ("R", "G", "B")


def _open_output(path, spec):
    oiio = openimageio()
    directory = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(directory, exist_ok=True)
    except OSError as error:
        raise LPVError(f"Cannot create the output folder '{directory}' ({error.strerror}); choose a writable folder.")
    output = oiio.ImageOutput.create(path)
    if output is None or not output.open(path, spec):
        message = oiio.geterror() if output is None else output.geterror()
        raise LPVError(f"Cannot write '{path}' ({message or 'not writable'}); choose a writable output folder.")
    return output


def write_exr(path, passes, metadata=None):
    """All passes in one float EXR, channels named '<pass>.R', '<pass>.G', '<pass>.B' (and
    '<pass>.A' for a pass with alpha); `metadata` ({name: text}) goes into its header
    (`read_exr_metadata`)."""
    oiio = openimageio()
    names = list(passes)
    height, width, _ = passes[names[0]].shape
    channels = [f"{name}.{c}" for name in names for c in (*CHANNELS, "A")[:passes[name].shape[2]]]
    spec = oiio.ImageSpec(width, height, len(channels), "float")
    spec.channelnames = tuple(channels)
    spec.attribute("compression", "zip")
    for name, text in (metadata or {}).items():
        spec.attribute(name, text)
    pixels = np.concatenate([np.asarray(passes[name], dtype=np.float32) for name in names], axis=2)
    output = _open_output(path, spec)
    output.write_image(np.ascontiguousarray(pixels))
    output.close()


def read_exr_metadata(path, name):
    """The text attribute `name` of an EXR's header, or None when the file has none or
    cannot be read."""
    oiio = openimageio()
    image = oiio.ImageInput.open(str(path))
    if image is None:
        oiio.geterror()  # an unreadable file is an answer here: take OpenImageIO's message
        return None
    value = image.spec().getattribute(name)
    image.close()
    return value if isinstance(value, str) else None


def read_exr_channels(path):
    """{channel name: (height, width) float32, top row first} over every part of an EXR
    (Blender 5.0 writes a multi-layer EXR as one part per pass)."""
    oiio = openimageio()
    image = oiio.ImageInput.open(str(path))
    if image is None:
        raise LPVError(f"Cannot read '{path}' ({oiio.geterror()}); check the path.")
    channels, part = {}, 0
    while image.seek_subimage(part, 0):
        spec = image.spec()
        pixels = image.read_image(part, 0, 0, spec.nchannels, "float")
        for index, name in enumerate(spec.channelnames):
            channels[name] = np.ascontiguousarray(pixels[..., index], dtype=np.float32)
        part += 1
    image.close()
    return channels


def read_exr(path):
    """{layer: (height, width, 3)} of every layer with '<layer>.R/G/B' channels in an EXR
    (one written by write_exr, or Blender's multi-part ones)."""
    channels = read_exr_channels(path)
    layers = {name.rpartition(".")[0] for name in channels}
    return {layer: np.stack([channels[f"{layer}.{c}"] for c in CHANNELS], axis=2) for layer in layers
            if all(f"{layer}.{c}" in channels for c in CHANNELS)}


def write_png(path, image, view_transform=ViewTransform()):
    """An 8-bit PNG of a linear image (premultiplied (height, width, 4) with alpha, kept
    straight in the PNG) through `view_transform` (gpu/colour_management.py: a scene's
    colour management, as F12 saves a PNG; by default Blender's "Standard" view on sRGB),
    or of display values in [0, 1] as they are with `view_transform=None` (a false-colour
    heat map). Values are rounded to the nearest code value, as Blender rounds them, with
    no dither."""
    oiio = openimageio()
    height, width, channels = image.shape
    if view_transform is None:
        display = np.clip(np.asarray(image, dtype=np.float32), 0.0, 1.0)
    else:
        display = display_values(image, view_transform)
    output = _open_output(path, oiio.ImageSpec(width, height, channels, "uint8"))
    output.write_image(np.ascontiguousarray(np.round(display * 255).astype(np.uint8)))
    output.close()
