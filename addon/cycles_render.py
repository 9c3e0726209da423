"""Cycles renders of ours into a multilayer EXR read back: the settings every one sets
(passes, samples and their subset, seed, denoising, output; for the diffuse references
and the sample workers also bounces and pixel filter, F12's references keep the scene's), the
render call and the passes read from the file. In Blender 5.0 every view-layer pass
reaches the file only once `image_settings.media_type` is 'MULTI_LAYER_IMAGE' (only then
can `file_format` be 'OPEN_EXR_MULTILAYER'); plain 'OPEN_EXR' holds Combined alone.
The references (cycles_reference.py), the peers (peers.py) and the sample workers
(cycles_samples.py) render through it."""
import os
import time
from collections import namedtuple

import bpy
import numpy as np

import addon_utils  # on the path only once bpy is imported
from mathutils import Matrix

from ..gpu.ctrl_c import ctrl_c_held
from ..gpu.errors import LPVError, first_line
from ..gpu.image_io import read_exr_channels

ColourPass = namedtuple("ColourPass", "view_layer_flag exr_layer")

# Blender's short pass names, each with the view-layer switch that makes Cycles produce
# it and the layer name it gets in a multilayer EXR.
COLOUR_PASSES = {
    "Combined": ColourPass("use_pass_combined", "Combined"),
    "DiffDir": ColourPass("use_pass_diffuse_direct", "Diffuse Direct"),
    "DiffInd": ColourPass("use_pass_diffuse_indirect", "Diffuse Indirect"),
    "DiffCol": ColourPass("use_pass_diffuse_color", "Diffuse Color"),
    "GlossDir": ColourPass("use_pass_glossy_direct", "Glossy Direct"),
    "GlossInd": ColourPass("use_pass_glossy_indirect", "Glossy Indirect"),
    "GlossCol": ColourPass("use_pass_glossy_color", "Glossy Color"),
    "TransDir": ColourPass("use_pass_transmission_direct", "Transmission Direct"),
    "TransInd": ColourPass("use_pass_transmission_indirect", "Transmission Indirect"),
    "TransCol": ColourPass("use_pass_transmission_color", "Transmission Color"),
    "Emit": ColourPass("use_pass_emit", "Emission"),
    "Env": ColourPass("use_pass_environment", "Environment"),
    "AO": ColourPass("use_pass_ambient_occlusion", "Ambient Occlusion"),
}
PASS_BY_NAME = {**COLOUR_PASSES, **{p.exr_layer: p for p in COLOUR_PASSES.values()}}
BOUNCE_ATTRIBUTES = (
    "max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces")


REFERENCE_BOUNCES = {"one_bounce": 1, "full_gi": 12}
"""The references: Cycles' bounce limit (every bounce type) for each."""

REFERENCE_FILTER_WIDTH = 0.01
"""Pixel filter width of the references: our images are sampled at pixel centres, so the
reference is too (Cycles' default 1.5 px Blackman-Harris would blur it against ours)."""


def view_layer_to_render(scene):
    """The view layer the user is looking at when `scene` is the current one, else its first."""
    if bpy.context.scene == scene and bpy.context.view_layer is not None:
        return bpy.context.view_layer
    return scene.view_layers[0]


def enable_cycles():
    if not addon_utils.check("cycles")[1] and addon_utils.enable("cycles", default_set=True) is None:
        raise LPVError("The Cycles add-on could not be enabled; enable it in Preferences > Add-ons.")


def assign(holder, **values):
    """Set those of `holder`'s properties that differ from `values` (floats and matrices as
    Blender stores them, in single precision): a sample request changes few, and setting a
    border, codec, pass or camera anew makes Cycles sync the scene again, with persistent
    data too."""
    for name, value in values.items():
        current = getattr(holder, name)
        if isinstance(value, (float, Matrix)):
            differs = np.any(np.float32(current) != np.float32(value))
        else:
            differs = current != value
        if differs:
            setattr(holder, name, value)


def _edge(pixel, size):
    """The border fraction Blender turns into the pixel edge `pixel` of `size`: it truncates
    fraction × size, and the fraction is single precision, so an exact `pixel / size` may
    land a pixel short; half a pixel on is safe."""
    return min((pixel + 0.5) / size, 1.0)


def apply_output_settings(scene, view_layer, exr_path, resolution, border=None):
    """Render `view_layer` alone at `resolution` (None: the scene's) into a float multilayer
    EXR at `exr_path` (uncompressed with a `border`), with no compositor, sequencer or
    Freestyle; only the pixels `border` (x0, y0, x1, y1, row 0 at the top) with one, the
    whole image without."""
    render = scene.render
    if resolution is not None:
        assign(render, resolution_x=resolution[0], resolution_y=resolution[1], resolution_percentage=100)
    if border is None:
        assign(render, use_border=False)
    else:
        x0, y0, x1, y1 = border
        width, height = render.resolution_x, render.resolution_y
        assign(render, use_border=True, use_crop_to_border=True, border_min_x=_edge(x0, width),
               border_max_x=_edge(x1, width), border_min_y=_edge(height - y1, height),
               border_max_y=_edge(height - y0, height))
    assign(render, use_multiview=False, use_file_extension=False, use_compositing=False, use_sequencer=False,
           use_freestyle=False)
    # set even when it is the same: a render property tags the scene for an update, the
    # Cycles add-on's own (samples, seed) do not, and without one Cycles renders the last
    # settings again
    render.filepath = exr_path
    # a border's image is written and read at once: compression would only cost
    assign(render.image_settings, media_type="MULTI_LAYER_IMAGE", file_format="OPEN_EXR_MULTILAYER",
           color_depth="32", exr_codec="ZIP" if border is None else "NONE", use_exr_interleave=False,
           color_management="FOLLOW_SCENE")
    for layer in scene.view_layers:
        assign(layer, use=layer == view_layer)


def apply_sample_settings(scene, samples, sample_range, seed, denoise, threads=None):
    """Cycles on the CPU (on `threads` threads, None: all) renders the `sample_range`
    (first, count) of `samples` plain samples with `seed`: no adaptive sampling, time
    limit or view-layer sample count, which change how many samples a pixel gets, and
    `denoise`d by OpenImageDenoise as the viewport denoises, or not at all."""
    cycles = scene.cycles
    assign(scene.render, engine="CYCLES")
    assign(scene.render, threads_mode="AUTO" if threads is None else "FIXED")
    if threads is not None:
        assign(scene.render, threads=threads)
    assign(cycles, device="CPU", samples=samples, use_adaptive_sampling=False, time_limit=0.0,
           use_layer_samples="IGNORE", use_sample_subset=True, sample_offset=sample_range[0],
           sample_subset_length=sample_range[1], seed=seed, use_animated_seed=False, use_denoising=denoise)
    if denoise:
        assign(cycles, denoiser="OPENIMAGEDENOISE", denoising_use_gpu=False,
               denoising_input_passes=cycles.preview_denoising_input_passes,
               denoising_prefilter=cycles.preview_denoising_prefilter,
               denoising_quality=cycles.preview_denoising_quality)


def apply_f12_settings(scene, view_layer, exr_path, samples, sample_range, resolution, seed, denoise=False):
    """Set `scene` up to render what F12 renders with its own settings (bounces, clamping,
    light threshold, film, pixel filter, world, view layer) into `exr_path`'s Combined
    pass, but for the samples (`apply_sample_settings`) and the size: `resolution`, the
    whole image (apply_output_settings)."""
    apply_output_settings(scene, view_layer, exr_path, resolution)
    apply_sample_settings(scene, samples, sample_range, seed, denoise)
    assign(view_layer, use_pass_combined=True)


def apply_render_settings(scene, view_layer, exr_path, passes, samples, sample_range, resolution, seed,
                          max_bounces, light_threshold, pixel_filter_width, denoise, border=None, threads=None):
    """Set `scene` up for a raw Cycles render on the CPU of `passes` into `exr_path`: the
    `sample_range` (first, count) of `samples` with `seed`, every bounce type capped at
    `max_bounces` (None: the scene's), no adaptive sampling, clamping or time limit, the
    pixel filter `pixel_filter_width` wide (None: the scene's), and `denoise`d by
    OpenImageDenoise as the viewport denoises; only the `border` (apply_output_settings)
    with one, on `threads` threads (None: all)."""
    cycles = scene.cycles
    apply_output_settings(scene, view_layer, exr_path, resolution, border)
    apply_sample_settings(scene, samples, sample_range, seed, denoise, threads)
    assign(cycles, light_sampling_threshold=light_threshold, sample_clamp_direct=0.0, sample_clamp_indirect=0.0)
    if pixel_filter_width is not None:
        assign(cycles, filter_width=pixel_filter_width)
    if max_bounces is not None:
        assign(cycles, **{name: max_bounces for name in BOUNCE_ATTRIBUTES})
    for name in passes:
        if name in PASS_BY_NAME:
            assign(view_layer, **{PASS_BY_NAME[name].view_layer_flag: True})


def settings_in_use(scene, view_layer):
    cycles, render = scene.cycles, scene.render
    return {
        "resolution": (render.resolution_x * render.resolution_percentage // 100,
                       render.resolution_y * render.resolution_percentage // 100),
        "device": cycles.device, "samples": cycles.samples, "seed": cycles.seed,
        "max_bounces": cycles.max_bounces, "diffuse_bounces": cycles.diffuse_bounces,
        "glossy_bounces": cycles.glossy_bounces, "transmission_bounces": cycles.transmission_bounces,
        "clamp_direct": cycles.sample_clamp_direct, "clamp_indirect": cycles.sample_clamp_indirect,
        "light_threshold": cycles.light_sampling_threshold, "pixel_filter": cycles.pixel_filter_type,
        "pixel_filter_width": cycles.filter_width, "film_transparent": render.film_transparent,
        "film_exposure": cycles.film_exposure, "frame": scene.frame_current,
        "view_layer": view_layer.name, "world": None if scene.world is None else scene.world.name,
        "denoiser": (f"OpenImageDenoise ({cycles.denoising_input_passes}, {cycles.denoising_prefilter} prefilter, "
                     f"{cycles.denoising_quality} quality)" if cycles.use_denoising else None),
    }


def render_to_file(scene, exr_path, engine="Cycles"):
    """Render `scene` (set up by `apply_output_settings`) into `exr_path`; its wall seconds."""
    started = time.perf_counter()
    try:
        with ctrl_c_held():
            bpy.ops.render.render(write_still=True, scene=scene.name)
    except RuntimeError as error:
        reason = first_line(error).removeprefix("Error: ")
        raise LPVError(f"{engine} could not render or save its image: {reason}.") from error
    if not os.path.isfile(exr_path):
        raise LPVError(f"{engine} rendered but wrote no image to '{exr_path}'.")
    return time.perf_counter() - started


def read_exr_passes(exr_path, view_layer_name, wanted_layers):
    """{pass name: (H, W, 3) float32} from the multilayer EXR, top row first."""
    channels = read_exr_channels(exr_path)
    prefix = f"{view_layer_name}."
    images = {}
    for name, layer in wanted_layers.items():
        names = [f"{prefix}{layer}.{c}" for c in "RGB"]
        if not all(channel in channels for channel in names):
            present = sorted({c[len(prefix):].rsplit(".", 1)[0] for c in channels if c.startswith(prefix)})
            raise LPVError(f"The Cycles render has no '{name}' pass with R, G and B channels; "
                           f"it has {', '.join(present)}.")
        images[name] = np.stack([channels[channel] for channel in names], axis=2)
    return images
