"""The linear pixels of the images materials read: a Blender image's, and each tile of a
tiled (UDIM) image, and which tile each triangle reads.

Each UDIM tile becomes a layer of the scene's texture array (gpu/surface_images.py), and
a triangle reads the tile under the centre of its UVs (tile 1001 + floor(u) + 10 floor(v)).
UDIM islands are laid out within one tile (a triangle across a tile border shows a seam
in UDIM painters too), so picking the tile per triangle leaves the shaders and the vertex
layout as they are, where a per-pixel tile table would add a lookup to every raster pass
and an atlas would need its own wrapping and mip-maps. The array repeats, so u 1.25 reads
its tile at 0.25. Blender's Python gives the pixels of a tiled image's first tile only;
the others are read from their files (<UDIM> or <UVTILE> in the image's path) or packed
data with OpenImageIO.
"""
import os
import tempfile

import bpy
import numpy as np

from ..gpu.image_library import openimageio

LINEAR_COLOUR_SPACES = ("linear", "non-color", "raw")
"""Image colour spaces (lower case, by prefix) whose pixel values are taken as they are."""

FIRST_TILE = 1001
TILE_COLUMNS = 10
NO_TILE = 0
"""The tile number of UVs outside the UDIM grid (u below 0 or from 10 on, v below 0)."""


def tile_numbers(uvs):
    """(T,) the UDIM tile under the centre of each triangle's corner UVs (T, 3, 2)
    (NO_TILE outside the grid)."""
    centre = np.floor(np.asarray(uvs, dtype=np.float64).mean(axis=1))
    column, row = centre[:, 0], centre[:, 1]
    inside = (column >= 0) & (column < TILE_COLUMNS) & (row >= 0)
    return np.where(inside, FIRST_TILE + column + TILE_COLUMNS * row, NO_TILE).astype(np.int64)


def linear_pixels(image):
    """(H, W, 3) linear float32 pixels of a Blender image (a tiled one's first tile), top
    row first, or None when it has none (a missing file)."""
    width, height = image.size
    channels = image.channels
    if width * height == 0 or channels == 0:
        return None
    pixels = np.empty(width * height * channels, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(height, width, channels)[::-1]  # Blender's rows start at the bottom
    return linear(pixels, image.is_float, image.colorspace_settings.name)


def alpha_channel(image):
    """(H, W) float32 alpha of a Blender image, top row first, or None when it has no
    alpha channel or no pixels."""
    width, height = image.size
    if width * height == 0 or image.channels != 4:
        return None
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return np.ascontiguousarray(pixels.reshape(height, width, 4)[::-1, :, 3])


def linear(pixels, is_float, colour_space):
    """(H, W, 3) linear float32 of (H, W, C) pixel values: float images hold scene-linear
    values; byte images hold their colour space's encoding, which for anything but linear
    or non-colour data is taken as sRGB."""
    channels = pixels.shape[2]
    rgb = pixels[..., :3] if channels >= 3 else np.repeat(pixels[..., :1], 3, axis=2)
    if not is_float and not colour_space.lower().startswith(LINEAR_COLOUR_SPACES):
        rgb = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    return np.ascontiguousarray(rgb, dtype=np.float32)


def tile_pixels(image, number):
    """(H, W, 3) linear float32 pixels of the tile `number` of the tiled `image`, top row
    first, or None when it has no such tile or its file cannot be read."""
    tiles = [tile.number for tile in image.tiles]
    if number not in tiles:
        return None
    packed = next((packed.packed_file for packed in image.packed_files
                   if getattr(packed, "tile_number", None) == number), None)
    if packed is not None:
        return _packed_pixels(packed, image)
    path = tile_path(image, number)
    if path is not None and os.path.isfile(path):
        return _file_pixels(path, image.colorspace_settings.name)
    return linear_pixels(image) if number == tiles[0] else None


def tile_path(image, number):
    """The absolute path of the tile `number`'s file (None: the image's path names no
    tile)."""
    import bpy
    path = bpy.path.abspath(image.filepath, library=image.library)
    column, row = (number - FIRST_TILE) % TILE_COLUMNS, (number - FIRST_TILE) // TILE_COLUMNS
    if "<UDIM>" in path:
        return path.replace("<UDIM>", str(number))
    if "<UVTILE>" in path:
        return path.replace("<UVTILE>", f"u{column + 1}_v{row + 1}")
    return None


def _file_pixels(path, colour_space):
    oiio = openimageio()
    source = oiio.ImageInput.open(path)
    if source is None:
        return None
    try:
        spec = source.spec()
        pixels = source.read_image(0, 0, 0, spec.nchannels, "float")
    finally:
        source.close()
    if pixels is None or spec.width * spec.height == 0:
        return None
    is_float = spec.format.basetype in (oiio.FLOAT, oiio.HALF, oiio.DOUBLE)
    return linear(np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, -1), is_float, colour_space)


def _packed_pixels(packed, image):
    extension = os.path.splitext(image.filepath)[1] or ".png"
    handle, path = tempfile.mkstemp(suffix=extension, prefix="lpv_tile_")
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(packed.data)
        return _file_pixels(path, image.colorspace_settings.name)
    finally:
        os.remove(path)
