"""Linear renders to display values as Blender's colour management makes them when F12
saves an 8-bit image: exposure, look, view transform, display, gamma, through OpenColorIO
(OpenImageIO's) with Blender's config.

Blender (intern/opencolorio, create_ocio_display_processor) builds its display processor
in this order, and `display_values` follows it:
  1. scene linear colour times 2^exposure;
  2. the look (unless "None"): a LookTransform from scene linear to the look's process
     space (the config's `process_space` of that look);
  3. the view on the display (DisplayViewTransform) from there, looks bypassed;
  4. display value ^ (1 / gamma).
An image with alpha is premultiplied, as Blender renders it; its colour is un-premultiplied
before all this and the alpha kept as it is (straight alpha, as Blender saves a PNG).
The view's curves (use_curve_mapping) and white balance (use_white_balance) are not
applied.

No bpy here: addon/view_transform.py reads a scene's settings and finds Blender's config.
OpenImageIO is imported only when a config is used, as gpu/image_io.py does.
"""
import os
import re
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .errors import LPVError
from .image_library import openimageio

SCENE_LINEAR = "scene_linear"
"""The OCIO role the renders are in: "Linear Rec.709" in Blender's config."""

NO_LOOK = "None"
"""Blender's name for no look (view_settings.look)."""


@dataclass(frozen=True)
class ViewTransform:
    """What a linear image goes through to become display values: the OCIO config at
    `config` (a config.ocio path), its `display` and `view`, a `look` of it (NO_LOOK: none),
    `exposure` in stops and `gamma`, as Blender's scene.view_settings and
    scene.display_settings hold them (addon/view_transform.py scene_view_transform).

    The default, where no scene is known (scripts, tests): Blender's "Standard" view on
    the "sRGB" display with no config: the sRGB transfer function of the colour clipped to
    [0, 1], computed here, which is what that view of Blender's config does (a test checks
    it against the config), so that a PNG can be written where Blender's config is not.
    Without a config only that view and display and no look can be asked for.
    """

    config: str = None
    display: str = "sRGB"
    view: str = "Standard"
    look: str = NO_LOOK
    exposure: float = 0.0
    gamma: float = 1.0

    @property
    def has_look(self):
        return bool(self.look) and self.look != NO_LOOK


def srgb_encode(linear):
    """The sRGB transfer function (IEC 61966-2-1) of values in [0, 1]."""
    linear = np.clip(linear, 0.0, 1.0)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1 / 2.4) - 0.055)


def display_values(image, view_transform):
    """(height, width, 3) display values in [0, 1] of a linear (height, width, 3) image, or
    (height, width, 4) with straight alpha of a premultiplied (height, width, 4) one, as
    `view_transform` (ViewTransform) makes them; float32."""
    image = np.asarray(image, dtype=np.float32)
    colour = image[..., :3]
    if image.shape[2] == 4:
        alpha = np.clip(image[..., 3:], 0.0, 1.0)
        colour = np.where(alpha > 0, colour / np.maximum(alpha, 1e-6), 0.0)
    colour = colour * np.float32(2.0 ** view_transform.exposure)
    if view_transform.config is None:
        display = _standard_srgb(colour, view_transform)
    else:
        display = _ocio_display(np.ascontiguousarray(colour, dtype=np.float32), view_transform)
    if view_transform.gamma != 1.0:
        display = np.power(np.maximum(display, 0.0), 1.0 / max(view_transform.gamma, 1e-6))
    display = np.clip(display, 0.0, 1.0).astype(np.float32)
    return np.concatenate([display, alpha], axis=2) if image.shape[2] == 4 else display


def _standard_srgb(colour, view_transform):
    if (view_transform.display, view_transform.view) != ("sRGB", "Standard") or view_transform.has_look:
        raise LPVError(f"The view '{view_transform.view}' on the display '{view_transform.display}'"
                       f"{' with the look ' + repr(view_transform.look) if view_transform.has_look else ''} needs "
                       f"Blender's colour management config (config.ocio), which was not found; choose the "
                       f"'Standard' view on 'sRGB' with no look, or set $OCIO to Blender's config.")
    return srgb_encode(colour)


def _ocio_display(colour, view_transform):
    oiio = openimageio()
    config = view_transform.config
    source, fromspace = oiio.ImageBuf(colour), SCENE_LINEAR
    if view_transform.has_look:
        process_space = look_process_space(config, view_transform.look)
        source = _checked(oiio.ImageBufAlgo.ociolook(source, view_transform.look, fromspace=fromspace,
                                                      tospace=process_space, colorconfig=config),
                          view_transform, f"the look '{view_transform.look}'")
        fromspace = process_space
    shown = _checked(oiio.ImageBufAlgo.ociodisplay(source, view_transform.display, view_transform.view,
                                                   fromspace=fromspace, colorconfig=config),
                     view_transform, f"the view '{view_transform.view}' on the display '{view_transform.display}'")
    return shown.get_pixels(oiio.FLOAT)[..., :3]


def _checked(buffer, view_transform, what):
    if buffer.has_error:
        message = " ".join(buffer.geterror().split())
        raise LPVError(f"Cannot apply {what} of the colour management config '{view_transform.config}' "
                       f"({message}); choose a view, display and look that the config has.")
    return buffer


@lru_cache(maxsize=8)
def _look_spaces(config, modified):
    """{look name: process space} of the config file `config` (its `looks:` section); the
    file's modification time keys the cache."""
    try:
        with open(config, encoding="utf-8") as handle:
            text = handle.read()
    except OSError as error:
        raise LPVError(f"Cannot read the colour management config '{config}' ({error.strerror}).")
    section = re.search(r"^looks:\s*\n(.*?)(?=^\S|\Z)", text, re.M | re.S)
    spaces = {}
    for look in re.split(r"^\s*-\s*!<Look>", section.group(1) if section else "", flags=re.M):
        name = re.search(r"^\s*name:\s*(.+?)\s*$", look, re.M)
        space = re.search(r"^\s*process_space:\s*(.+?)\s*$", look, re.M)
        if name and space:
            spaces[name.group(1).strip("\"'")] = space.group(1).strip("\"'")
    return spaces


def look_process_space(config, look):
    """The colour space the look `look` of the OCIO config file `config` works in (what
    OCIO's LookTransform::GetLooksResultColorSpace gives Blender), which OpenImageIO does
    not tell."""
    spaces = _look_spaces(config, os.path.getmtime(config) if os.path.exists(config) else None)
    if look not in spaces:
        raise LPVError(f"The colour management config '{config}' has no look '{look}' "
                       f"(it has: {', '.join(spaces) or 'none'}); choose one of its looks or 'None'.")
    return spaces[look]
