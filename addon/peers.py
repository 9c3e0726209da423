"""What a user would pick instead of LPV Preview, rendered to set beside it: EEVEE with
ray tracing, and Cycles at a few samples denoised as its viewport shows it.

EEVEE 5.0 writes no Diffuse Indirect pass: its Diffuse Light pass (the "Diffuse Direct"
layer of the EXR) is all the diffuse light a surface receives, ray-traced light included.
So EEVEE renders the scene twice, with ray tracing and without: its indirect light is
(diffuse light with - diffuse light without) x diffuse colour, its combined the diffuse
light with ray tracing x colour. Without ray tracing EEVEE lights a surface by its lights
and its light probes (the world, when none was baked), which Cycles counts as direct
light too. The scene's own EEVEE settings are kept (its samples, Fast GI, thickness): a
user who picks EEVEE renders with them; only the pixel filter is the references'.

Cycles' denoiser works on its Combined pass alone, so denoised Cycles is compared with the
reference's Combined pass and has no indirect image. Each render is of a temporary copy of
the scene, timed in wall seconds, and kept in the references' cache.
"""
import os
from dataclasses import dataclass, field

from ..gpu.context import GLContext
from ..gpu.errors import LPVError
from ..gpu.temporary_folders import temporary_folder
from .cycles_reference import content_key, render_cycles_denoised, temporary_copy
from .cycles_render import (REFERENCE_BOUNCES, REFERENCE_FILTER_WIDTH, apply_output_settings, read_exr_passes,
                            render_to_file, view_layer_to_render)

EEVEE = "EEVEE ray tracing"
DENOISED_SAMPLES = (1, 4)
"""Samples of the denoised Cycles renders: a first glance and a settled viewport."""


def denoised_name(samples):
    return f"Cycles {samples} spp + OIDN"


@dataclass
class PeerRender:
    """A peer's images (compared image name -> (H, W, 3) linear float32, top row first), the
    wall seconds a user waits for it, how it was rendered, and the reference image each of
    its images is compared with (`against`; the same name when absent). `kind` is the
    reference it was rendered for (denoised Cycles: that reference's bounces), None for all;
    `missing` says why a peer could not render (its images are then empty)."""

    name: str
    images: dict
    seconds: float
    settings: dict
    kind: str = None
    against: dict = field(default_factory=dict)
    missing: str = None


def eevee_render(scene, resolution, content, cache=None):
    """EEVEE with ray tracing of `scene` from its camera at `resolution`; `content` is the
    scene extracted at that resolution (for the cache key). Its time is the ray-traced
    render's after one sample of it compiled the shaders (ours is timed with warm shaders)."""
    key = content_key(content, scene.world, EEVEE, rna_values(scene.eevee), tuple(resolution),
                      REFERENCE_FILTER_WIDTH)
    cached = _cached(cache, key, EEVEE)
    if cached is not None:
        return cached
    view_layer_name = view_layer_to_render(scene).name
    layers = {"DiffDir": "Diffuse Direct", "DiffCol": "Diffuse Color"}
    with temporary_folder() as folder, temporary_copy(scene) as copy:
        view_layer = copy.view_layers[view_layer_name]
        copy.render.engine = "BLENDER_EEVEE"
        copy.render.filter_size = REFERENCE_FILTER_WIDTH
        view_layer.use_pass_diffuse_direct = view_layer.use_pass_diffuse_color = True
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
    images = {"indirect": (traced["DiffDir"] - untraced["DiffDir"]) * colour, "combined": traced["DiffDir"] * colour}
    settings = {"samples": samples, "ray_tracing": eevee_settings_text(scene.eevee), "resolution": list(resolution),
                "render_seconds": seconds, "cached": False}
    peer = PeerRender(EEVEE, images, seconds, settings)
    _store(cache, key, peer)
    return peer


def eevee_settings_text(eevee):
    """EEVEE's ray tracing in a few words, like 'screen tracing, Fast GI on (global illumination)'."""
    return (f"{eevee.ray_tracing_method.lower()} tracing, Fast GI {'on' if eevee.use_fast_gi else 'off'}"
            f" ({eevee.fast_gi_method.lower().replace('_', ' ')})")


def cycles_denoised(scene, kind, samples, resolution, content, cache=None):
    """Cycles at `samples` with the `kind` reference's bounces and pixel filter and another
    seed than it, denoised by OpenImageDenoise; compared on Combined."""
    cycles = scene.cycles
    denoiser = (cycles.preview_denoising_input_passes, cycles.preview_denoising_prefilter,
                cycles.preview_denoising_quality)
    name = denoised_name(samples)
    key = content_key(content, scene.world, name, kind, REFERENCE_BOUNCES[kind], denoiser, tuple(resolution),
                      REFERENCE_FILTER_WIDTH)
    cached = _cached(cache, key, name, kind)
    if cached is not None:
        return cached
    images = render_cycles_denoised(scene, samples, resolution, 1, REFERENCE_BOUNCES[kind], REFERENCE_FILTER_WIDTH)
    settings = {**images["settings"], "cached": False}
    peer = PeerRender(name, {"combined": images["Combined"]}, settings["render_seconds"], settings, kind,
                      {"combined": "combined_pass"})
    _store(cache, key, peer)
    return peer


def missing_peer(name, error, kind=None):
    """The row of a peer that could not render: why, in the words of its LPVError."""
    return PeerRender(name, {}, None, {}, kind, missing=str(error))


def peer_renders(scene, kinds, resolution, content, cache=None):
    """(step label, a function rendering it) for every peer of a comparison with the `kinds`
    of reference: denoised Cycles per kind and sample count, then EEVEE. A peer that cannot
    render here gives a `missing_peer` instead of stopping the comparison."""
    def guarded(name, render, kind=None):
        def run():
            try:
                return render()
            except LPVError as error:
                return missing_peer(name, error, kind)
        return run

    steps = [(f"{denoised_name(samples)} at the {kind.replace('_', ' ')} reference's bounces",
              guarded(denoised_name(samples), lambda kind=kind, samples=samples:
                      cycles_denoised(scene, kind, samples, resolution, content, cache), kind))
             for kind in kinds for samples in DENOISED_SAMPLES]
    steps.append((f"{EEVEE}, rendered with and without ray tracing",
                  guarded(EEVEE, lambda: eevee_render(scene, resolution, content, cache))))
    return steps


def rna_values(struct):
    """Every plain setting of a Blender struct (EEVEE's), sorted, for a cache key."""
    values = []
    for prop in struct.bl_rna.properties:
        if prop.identifier == "rna_type" or prop.type in {"POINTER", "COLLECTION"}:
            continue
        value = getattr(struct, prop.identifier)
        if isinstance(value, set):  # an enum of flags
            value = tuple(sorted(value))
        values.append((prop.identifier, tuple(value) if getattr(prop, "is_array", False) else value))
    for prop in struct.ray_tracing_options.bl_rna.properties:
        if prop.identifier != "rna_type":
            values.append((f"ray_tracing_options.{prop.identifier}", getattr(struct.ray_tracing_options,
                                                                              prop.identifier)))
    return sorted(values, key=lambda item: item[0])


def _cached(cache, key, name, kind=None):
    data = None if cache is None else cache.load_arrays(key)
    if data is None:
        return None
    settings = {**data.pop("settings"), "cached": True}
    against = settings.pop("against", {})
    return PeerRender(name, data, settings["render_seconds"], settings, kind, against)


def _store(cache, key, peer):
    if cache is not None:
        cache.store_arrays(key, peer.images, {**peer.settings, "against": peer.against})

