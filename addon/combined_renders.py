"""Each engine's F12 Combined pass of a scene with the scene's own settings (bounces,
pixel filter, light threshold, EEVEE's samples and ray tracing): what a user who presses
F12 in Cycles or EEVEE sees, for the artist-scene benchmark (bench/artist.py).

Only what a benchmark must fix is set: the image size, Cycles' sample count and seed,
and raw output (no compositor, no adaptive sampling or denoising unless asked). Each
render is of a temporary copy of the scene, so the scene is never changed. The
comparison's references (cycles_reference.py) differ on purpose: they split diffuse
light and sample at pixel centres.
"""
import os

from ..gpu.context import GLContext
from ..gpu.temporary_folders import temporary_folder
from .cycles_reference import render_cycles_denoised, temporary_copy
from .cycles_render import (apply_output_settings, apply_render_settings, enable_cycles, read_exr_passes,
                            render_to_file, settings_in_use, view_layer_to_render)


def cycles_combined(scene, samples, resolution, seed=0):
    """Cycles' Combined pass at `samples` with the scene's own bounces, pixel filter and
    light threshold; (image (H, W, 3) linear, top row first, settings used). In one
    render, not in parts: each part syncs the scene again and, with an HDRI or a sky,
    builds the world's importance map again, which at a small size costs more than the
    part's samples."""
    enable_cycles()
    view_layer_name = view_layer_to_render(scene).name
    with temporary_folder() as folder, temporary_copy(scene) as copy:
        view_layer = copy.view_layers[view_layer_name]
        path = os.path.join(folder, "combined.exr")
        apply_render_settings(copy, view_layer, path, ("Combined",), samples, (0, samples), resolution, seed,
                              None, copy.cycles.light_sampling_threshold, None, denoise=False)
        settings = settings_in_use(copy, view_layer)
        settings["render_seconds"] = render_to_file(copy, path)
        image = read_exr_passes(path, view_layer_name, {"Combined": "Combined"})["Combined"]
    return image, settings


def cycles_denoised_combined(scene, samples, resolution, seed=1):
    """Cycles' Combined pass at `samples` denoised by OpenImageDenoise as its viewport
    denoises, with the scene's own bounces and pixel filter; (image, settings used)."""
    images = render_cycles_denoised(scene, samples, resolution, seed, None, None)
    return images["Combined"], images["settings"]


def eevee_combined(scene, resolution, samples=None):
    """EEVEE's Combined pass with the scene's own EEVEE settings (its samples unless
    `samples` is given); (image, settings used). One sample renders first so that the
    timed render finds its shaders compiled."""
    view_layer_name = view_layer_to_render(scene).name
    with temporary_folder(prefix="lpv_eevee_") as folder, temporary_copy(scene) as copy:
        view_layer = copy.view_layers[view_layer_name]
        copy.render.engine = "BLENDER_EEVEE"
        samples = samples or copy.eevee.taa_render_samples

        def render(name, samples):
            path = os.path.join(folder, f"{name}.exr")
            apply_output_settings(copy, view_layer, path, resolution)
            copy.eevee.taa_render_samples = samples
            with GLContext.foreign_render():  # EEVEE leaves its GPU context current
                seconds = render_to_file(copy, path, "EEVEE")
            return read_exr_passes(path, view_layer_name, {"Combined": "Combined"})["Combined"], seconds

        render("warm", 1)
        image, seconds = render("combined", samples)
    return image, {"samples": samples, "resolution": list(resolution), "render_seconds": seconds,
                   "ray_tracing": eevee_ray_tracing_text(scene)}


def eevee_ray_tracing_text(scene):
    """EEVEE's ray tracing as the scene sets it, in a few words."""
    eevee = scene.eevee
    return f"ray tracing {'on' if eevee.use_raytracing else 'off'}, Fast GI {'on' if eevee.use_fast_gi else 'off'}"
