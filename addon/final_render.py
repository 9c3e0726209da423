"""F12 and batch renders through the engine: the evaluated scene at the render resolution,
written into the RenderResult as Combined and our passes (gpu/passes.py), so they reach
the compositor and multi-layer EXRs; a render region writes its pixels alone, and Film
Transparent gives Combined the frame's coverage as alpha (gpu/output_layout.py). The
frame renders on the GL thread (gpu/gl_thread.py); Blender's thread waits, answering Esc. Blender 5.0 writes a multi-layer EXR as one part
per pass: a reader must walk every part.
"""
import threading
from dataclasses import dataclass

import numpy as np

from ..gpu.errors import LPVError
from ..gpu.gl_thread import GLThread
from ..gpu.passes import render_passes
from ..gpu.pipeline import render_once
from . import frame_stats
from .extract import extract_scene, output_layout
from .properties import display_settings_from_properties, settings_from_properties


@dataclass
class ExtractionRequest:
    """A render asked for its Scene only (render_scene.py): the camera's resolution in,
    the extracted Scene (and, `with_signature`, addon/render_signature.py's hash of what
    F12 renders) or the error out."""

    resolution: tuple = None
    with_signature: bool = False
    scene: object = None
    signature: str = None
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
        if request.with_signature:
            from .render_signature import render_signature
            request.signature = render_signature(depsgraph)
    except LPVError as error:
        request.error = error
    return True


def result_pixels(image, alpha=None):
    """A (height, width, c) top-row-first image as a RenderPass rect: bottom row first,
    one row per pixel, with the (height, width) `alpha` appended as a channel when given."""
    if alpha is not None:
        image = np.concatenate([image, alpha[..., None].astype(image.dtype)], axis=2)
    return np.ascontiguousarray(image[::-1].reshape(-1, image.shape[-1]), dtype=np.float32)


WAIT_SECONDS = 0.05
"""How often Blender's thread looks at Esc and the progress while the GL thread renders."""


def wait_for(job, engine, stop, averaged):
    """The frame of `job` (a Future of the GL thread), Blender's thread meanwhile showing
    the VPL sets `averaged` so far and setting `stop` when Esc (engine.test_break) or
    Ctrl-C asks, which ends the render after the set it is making."""
    shown = 0
    try:
        while True:
            try:
                return job.result(timeout=WAIT_SECONDS)
            except TimeoutError:
                if engine.test_break():
                    stop.set()
                if len(averaged) > shown:
                    shown = len(averaged)
                    engine.update_stats("", f"LPV Preview: {averaged[-1]} VPL sets averaged")
    except BaseException:
        stop.set()
        raise


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
    layout = output_layout(scene)
    if layout.empty:
        raise LPVError("The render region is narrower than a pixel; draw a larger one (Ctrl-B) or clear it "
                       "(Ctrl-Alt-B).")
    width, height = layout.size
    engine.update_stats("", "LPV Preview: reading the scene")
    settings = settings_from_properties(scene.lpv_preview, width=width, height=height)
    display = display_settings_from_properties(scene.lpv_preview)
    passes = scene_passes(scene)
    lpv_scene = extract_scene(depsgraph)
    if lpv_scene.camera is None:
        raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
    engine.update_progress(0.2)
    engine.update_stats("", "LPV Preview: rendering")
    stop, averaged = threading.Event(), []
    job = GLThread.shared().submit(render_once, lpv_scene, settings, passes=tuple(p.name for p in passes),
                                   display_settings=display, stop=stop.is_set, progress=averaged.append)
    frame = wait_for(job, engine, stop, averaged)
    frame_stats.remember(frame.stats)
    for warning in frame_stats.warnings(frame.stats):
        engine.report({"WARNING"}, warning)
    engine.update_progress(0.9)
    result = engine.begin_result(0, 0, *layout.region_size)  # Blender's result holds the region alone
    layer = result.layers[0]
    for render_pass in passes:
        alpha = layout.combined_alpha(frame.coverage) if render_pass.channels == "RGBA" else None  # ours are RGB
        # foreach_set of a flat array: ~300 times faster than assigning `rect` a 2-D array.
        layer.passes[render_pass.blender_name].rect.foreach_set(
            result_pixels(layout.region_of(frame.passes[render_pass.name]), alpha=alpha).ravel())
    engine.end_result(result)
    engine.update_progress(1.0)
    engine.update_stats("", f"LPV Preview: {frame.stats['converge_ms']:.0f} ms, {frame.stats['accumulated_vpls']} VPLs")
