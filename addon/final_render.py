"""F12 and batch renders through the engine: the evaluated scene at the render resolution,
written into the RenderResult as Combined and our passes (gpu/passes.py), so they reach
the compositor and multi-layer EXRs. Blender 5.0 writes a multi-layer EXR as one part
per pass: a reader must walk every part.
"""
from dataclasses import dataclass

import numpy as np

from ..gpu.errors import LPVError
from ..gpu.passes import render_passes
from ..gpu.pipeline import render_once
from . import frame_stats
from .extract import extract_scene, render_resolution
from .properties import display_settings_from_properties, settings_from_properties


@dataclass
class ExtractionRequest:
    """A render asked for its Scene only (render_scene.py): the camera's resolution in,
    the extracted Scene or the error out."""

    resolution: tuple = None
    scene: object = None
    error: LPVError = None


pending_extractions = []
"""The ExtractionRequests waiting for the render Blender is starting."""


def take_extraction(depsgraph):
    """Fulfil the newest ExtractionRequest from `depsgraph`; False when none is waiting."""
    if not pending_extractions:
        return False
    request = pending_extractions[-1]
    try:
        request.scene = extract_scene(depsgraph, resolution=request.resolution)
    except LPVError as error:
        request.error = error
    return True


def result_pixels(image, alpha=None):
    """A (height, width, c) top-row-first image as a RenderPass rect: bottom row first,
    one row per pixel, with an alpha channel appended when given."""
    rows = image[::-1].reshape(-1, image.shape[-1])
    if alpha is not None:
        rows = np.concatenate([rows, np.full((len(rows), 1), alpha, dtype=rows.dtype)], axis=1)
    return np.ascontiguousarray(rows, dtype=np.float32)


def scene_passes(scene):
    """The render passes of `scene` (None: a view layer without one): ours, and the debug
    ones when its "Debug passes" is on."""
    properties = getattr(scene, "lpv_preview", None)  # None: only the engine is registered (render_scene.py)
    return render_passes(properties is not None and display_settings_from_properties(properties).debug_passes)


def render_final(engine, depsgraph):
    """Render `depsgraph`'s scene from its camera into `engine`'s RenderResult, or hand
    the extracted Scene to a waiting ExtractionRequest."""
    if take_extraction(depsgraph):
        return
    scene = depsgraph.scene_eval
    width, height = render_resolution(scene)
    engine.update_stats("", "LPV Preview: reading the scene")
    settings = settings_from_properties(scene.lpv_preview, width=width, height=height)
    display = display_settings_from_properties(scene.lpv_preview)
    passes = scene_passes(scene)
    lpv_scene = extract_scene(depsgraph)
    if lpv_scene.camera is None:
        raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
    engine.update_progress(0.2)
    engine.update_stats("", "LPV Preview: rendering")
    frame = render_once(lpv_scene, settings, passes=tuple(p.name for p in passes), display_settings=display,
                        stop=engine.test_break,
                        progress=lambda sets: engine.update_stats("", f"LPV Preview: {sets} VPL sets averaged"))
    frame_stats.remember(frame.stats)
    engine.update_progress(0.9)
    result = engine.begin_result(0, 0, width, height)
    layer = result.layers[0]
    for render_pass in passes:
        alpha = 1.0 if render_pass.channels == "RGBA" else None  # the pipeline's images are RGB
        # foreach_set of a flat array: ~300 times faster than assigning `rect` a 2-D array.
        layer.passes[render_pass.blender_name].rect.foreach_set(
            result_pixels(frame.passes[render_pass.name], alpha=alpha).ravel())
    engine.end_result(result)
    engine.update_progress(1.0)
    engine.update_stats("", f"LPV Preview: {frame.stats['converge_ms']:.0f} ms, {frame.stats['accumulated_vpls']} VPLs")
