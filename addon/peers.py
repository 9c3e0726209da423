"""What a user would pick instead of LPV Preview, rendered to set beside it: EEVEE with
ray tracing, and Cycles at a few samples denoised as its viewport shows it.

Each peer's Combined pass, as F12 renders the scene with that engine and its own
settings, is measured against the F12 reference (cycles_reference.py), as our combined
image is. EEVEE also gets diffuse images, measured against the diffuse references:
EEVEE 5.0 writes no Diffuse Indirect pass, its Diffuse Light pass (the "Diffuse Direct"
layer of the EXR) being all the diffuse light a surface receives, ray-traced light
included. So EEVEE renders the scene twice, with ray tracing and without: its indirect
light is (diffuse light with - diffuse light without) x diffuse colour, its diffuse
combined the diffuse light with ray tracing x colour. Without ray tracing EEVEE lights a
surface by its lights and its light probes (the world, when none was baked), which
Cycles counts as direct light too. The scene's own EEVEE settings are kept (its samples,
Fast GI, thickness, pixel filter): a user who picks EEVEE renders with them.

Cycles' denoiser works on its Combined pass alone, so denoised Cycles has no diffuse
images. Each render is of a temporary copy of the scene, timed in wall seconds, and kept
in the references' cache under a key of what F12 renders (addon/render_signature.py).
"""
import os
from dataclasses import dataclass, field

from ..gpu.context import GLContext
from ..gpu.errors import LPVError
from ..gpu.temporary_folders import temporary_folder
from .cycles_reference import F12, cache_key, render_cycles_denoised, temporary_copy
from .cycles_render import (REFERENCE_BOUNCES, REFERENCE_FILTER_WIDTH, apply_output_settings, read_exr_passes,
                            render_to_file, view_layer_to_render)
from .render_signature import plain_values

EEVEE = "EEVEE ray tracing"
DENOISED_SAMPLES = (1, 4)
"""Samples of the denoised Cycles renders: a first glance and a settled viewport."""


def denoised_name(samples):
    return f"Cycles {samples} spp + OIDN"


@dataclass
class PeerRender:
    """A peer's images measured against the F12 reference (`images`: "combined") and
    against the diffuse references (`diffuse_images`: "indirect" and "combined", none for
    denoised Cycles), each (H, W, 3) linear float32 top row first; the wall seconds a
    user waits for it and how it was rendered. `missing` says why a peer could not render
    (its images are then empty)."""

    name: str
    images: dict
    seconds: float
    settings: dict
    diffuse_images: dict = field(default_factory=dict)
    missing: str = None


def eevee_render(scene, resolution, signature, cache=None):
    """EEVEE with ray tracing of `scene` from its camera at `resolution`; `signature` is
    what F12 renders (for the cache key). Its time is the ray-traced render's after one
    sample of it compiled the shaders (ours is timed with warm shaders)."""
    key = cache_key(signature, EEVEE, eevee_values(scene.eevee), tuple(resolution))
    cached = _cached(cache, key, EEVEE)
    if cached is not None:
        return cached
    view_layer_name = view_layer_to_render(scene).name
    layers = {"Combined": "Combined", "DiffDir": "Diffuse Direct", "DiffCol": "Diffuse Color"}
    with temporary_folder() as folder, temporary_copy(scene) as copy:
        view_layer = copy.view_layers[view_layer_name]
        copy.render.engine = "BLENDER_EEVEE"
        view_layer.use_pass_combined = view_layer.use_pass_diffuse_direct = view_layer.use_pass_diffuse_color = True
        eevee, samples = copy.eevee, copy.eevee.taa_render_samples

        def render(name, ray_tracing, samples):
            path = os.path.join(folder, f"{name}.exr")
            apply_output_settings(copy, view_layer, path, resolution)
            eevee.use_raytracing, eevee.taa_render_samples = ray_tracing, samples
            with GLContext.foreign_render():  # EEVEE leaves its GPU context current
                seconds = render_to_file(copy, path, "EEVEE")
            return read_exr_passes(path, view_layer_name, layers), seconds

        render("warm", True, 1)
        traced, seconds = render("traced", True, samples)
        untraced, _ = render("untraced", False, samples)
    colour = traced["DiffCol"]
    diffuse = {"indirect": (traced["DiffDir"] - untraced["DiffDir"]) * colour, "combined": traced["DiffDir"] * colour}
    settings = {"samples": samples, "ray_tracing": eevee_settings_text(scene.eevee), "resolution": list(resolution),
                "pixel_filter_width": scene.render.filter_size, "render_seconds": seconds, "cached": False}
    peer = PeerRender(EEVEE, {"combined": traced["Combined"]}, seconds, settings, diffuse)
    _store(cache, key, peer)
    return peer


def eevee_settings_text(eevee):
    """EEVEE's ray tracing in a few words, like 'screen tracing, Fast GI on (global illumination)'."""
    return (f"{eevee.ray_tracing_method.lower()} tracing, Fast GI {'on' if eevee.use_fast_gi else 'off'}"
            f" ({eevee.fast_gi_method.lower().replace('_', ' ')})")


def cycles_denoised(scene, samples, resolution, signature, cache=None, kind=F12):
    """Cycles at `samples` with another seed than the references, denoised by
    OpenImageDenoise as the viewport denoises: as F12 renders the scene (`kind` F12), or
    with a diffuse reference's bounces and pixel filter (`kind` one of `REFERENCE_BOUNCES`,
    for scripts/time_to_equal_error.py); its Combined pass alone."""
    cycles = scene.cycles
    denoiser = (cycles.preview_denoising_input_passes, cycles.preview_denoising_prefilter,
                cycles.preview_denoising_quality)
    name = denoised_name(samples)
    own = () if kind == F12 else (REFERENCE_BOUNCES[kind], REFERENCE_FILTER_WIDTH)
    key = cache_key(signature, name, kind, *own, denoiser, tuple(resolution))
    cached = _cached(cache, key, name)
    if cached is not None:
        return cached
    if kind == F12:
        images = render_cycles_denoised(scene, samples, resolution, 1)
    else:
        images = render_cycles_denoised(scene, samples, resolution, 1, REFERENCE_BOUNCES[kind],
                                        REFERENCE_FILTER_WIDTH, as_f12=False)
    settings = {**images["settings"], "reference": kind, "cached": False}
    peer = PeerRender(name, {"combined": images["Combined"]}, settings["render_seconds"], settings)
    _store(cache, key, peer)
    return peer


def missing_peer(name, error):
    """The row of a peer that could not render: why, in the words of its LPVError."""
    return PeerRender(name, {}, None, {}, missing=str(error))


def peer_renders(scene, resolution, signature, cache=None):
    """(step label, a function rendering it) for every peer: denoised Cycles per sample
    count, then EEVEE; `signature` is what F12 renders (for the cache keys). A peer that
    cannot render here gives a `missing_peer` instead of stopping the comparison."""
    def guarded(name, render):
        def run():
            try:
                return render()
            except LPVError as error:
                return missing_peer(name, error)
        return run

    steps = [(f"{denoised_name(samples)} as F12 renders the scene",
              guarded(denoised_name(samples), lambda samples=samples:
                      cycles_denoised(scene, samples, resolution, signature, cache)))
             for samples in DENOISED_SAMPLES]
    steps.append((f"{EEVEE}, rendered with and without ray tracing",
                  guarded(EEVEE, lambda: eevee_render(scene, resolution, signature, cache))))
    return steps


def eevee_values(eevee):
    """Every plain setting of EEVEE and its ray tracing options, for a cache key."""
    return plain_values(eevee) + [(f"ray_tracing_options.{name}", value)
                                  for name, value in plain_values(eevee.ray_tracing_options)]


DIFFUSE_PREFIX = "diffuse_"
"""How a diffuse image's name begins in the cache, beside the F12 images."""


def _cached(cache, key, name):
    data = None if cache is None else cache.load_arrays(key)
    if data is None:
        return None
    settings = {**data.pop("settings"), "cached": True}
    images = {image: pixels for image, pixels in data.items() if not image.startswith(DIFFUSE_PREFIX)}
    diffuse = {image.removeprefix(DIFFUSE_PREFIX): pixels for image, pixels in data.items()
               if image.startswith(DIFFUSE_PREFIX)}
    return PeerRender(name, images, settings["render_seconds"], settings, diffuse)


def _store(cache, key, peer):
    if cache is not None:
        cache.store_arrays(key, {**peer.images, **{DIFFUSE_PREFIX + image: pixels
                                                   for image, pixels in peer.diffuse_images.items()}}, peer.settings)
