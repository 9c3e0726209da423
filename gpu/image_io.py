"""Writing passes: one multi-layer EXR (linear float) and tone-mapped PNGs, via OpenImageIO.

OpenImageIO is imported when an image is written, so the rest of gpu/ runs where it is
missing (the GPU machine); where this Python lacks it, Blender's bundled copy serves.
"""
import importlib.machinery
import importlib.util
import os
import sys

import numpy as np

from .errors import LPVError
from .colour import LUMINANCE_WEIGHTS

CHANNELS = ("R", "G", "B")
NO_OPENIMAGEIO = ("Reading and writing images needs the OpenImageIO module, which neither this Python nor Blender's "
                  "bundled packages hold; use Blender 5.0 from blender.org, which ships it, or install "
                  "requirements.txt (bash scripts/setup.sh).")


def openimageio():
    """The OpenImageIO module: this Python's, else the copy Blender ships among its own
    Python's packages (Blender as a module leaves that folder off sys.path); refused in one
    sentence where neither is, so callers can check before any work."""
    try:
        import OpenImageIO
        return OpenImageIO
    except ImportError:
        pass
    for folder in blender_package_folders():
        spec = importlib.machinery.PathFinder.find_spec("OpenImageIO", [folder])
        if spec is not None:
            module = importlib.util.module_from_spec(spec)
            sys.modules["OpenImageIO"] = module
            try:
                spec.loader.exec_module(module)
            except ImportError:
                del sys.modules["OpenImageIO"]
                continue
            return module
    raise LPVError(NO_OPENIMAGEIO)


def blender_package_folders():
    """The folders of Blender's bundled Python packages (Linux and macOS, then Windows),
    when bpy is loaded; gpu/ does not import bpy itself."""
    bpy = sys.modules.get("bpy")
    utils = getattr(bpy, "utils", None)
    if utils is None:
        return []
    python = os.path.join(utils.resource_path("LOCAL"), "python", "lib")
    return [os.path.join(python, f"python{sys.version_info[0]}.{sys.version_info[1]}", "site-packages"),
            os.path.join(python, "site-packages")]


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


def tone_map(image, key=0.18, exposure_of=None):
    """Linear HDR to display sRGB in [0, 1]: Reinhard's photographic operator, auto exposure.

    The exposure maps the log-average luminance of the lit pixels of `exposure_of` (by
    default the image itself) to `key`: images tone-mapped with one `exposure_of` can be
    compared by eye.
    """
    image = np.maximum(np.asarray(image, dtype=np.float64), 0.0)
    source = image if exposure_of is None else np.maximum(np.asarray(exposure_of, dtype=np.float64), 0.0)
    luminance = source @ LUMINANCE_WEIGHTS
    lit = luminance[luminance > 1e-9]
    average = np.exp(np.mean(np.log(lit))) if lit.size else 1.0
    scaled = image * (key / average)
    mapped = scaled / (1.0 + scaled)
    return np.where(mapped <= 0.0031308, 12.92 * mapped, 1.055 * np.power(mapped, 1 / 2.4) - 0.055)


def write_png(path, image, tone_mapped=True, exposure_of=None):
    """An 8-bit PNG of a linear image, tone-mapped (`tone_map`, exposure from `exposure_of`
    when given), or of display values in [0, 1] as they are with `tone_mapped=False`; an
    image with alpha keeps it (premultiplied colour, as Blender renders it, unassociated
    for the PNG)."""
    oiio = openimageio()
    height, width, channels = image.shape
    colour = image[..., :3]
    if channels == 4:
        alpha = np.clip(image[..., 3:], 0.0, 1.0)
        colour = np.where(alpha > 0, colour / np.maximum(alpha, 1e-6), 0.0)
    display = tone_map(colour, exposure_of=exposure_of) if tone_mapped else np.clip(colour, 0.0, 1.0)
    if channels == 4:
        display = np.concatenate([display, alpha], axis=2)
    output = _open_output(path, oiio.ImageSpec(width, height, channels, "uint8"))
    output.write_image(np.ascontiguousarray(np.round(display * 255).astype(np.uint8)))
    output.close()
