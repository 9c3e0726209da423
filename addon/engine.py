"""The "LPV Preview" render engine: F12 and batch renders, and the viewport.

`render()` extracts the evaluated scene, runs the pipeline in our own GL context and
writes Combined and our passes (registered in `update_render_passes`) into the
RenderResult, so they reach the compositor and multi-layer EXRs. Blender 5.0 writes a
multi-layer EXR as one part per pass: a reader must walk every part. The viewport keeps one `ViewportSession` per 3D view: `view_update`
notes which parts of the scene changed, `view_draw` re-extracts just those, renders from
the view's matrices and draws the image with Blender's `gpu` module. Errors a user can
fix are reported in one line, never as a traceback.
"""
import time

import bpy
import numpy as np

from ..gpu.errors import LPVError
from ..gpu.scene import Camera
from . import overlay
from .extract import extract_scene, render_resolution
from .properties import display_settings_from_properties, settings_from_properties
from .sync import EVERYTHING, SceneSync, changed_parts, record_updates

ENGINE_ID = "LPV_PREVIEW"

RESULT_PASSES = (("Direct", "direct"), ("Indirect", "indirect"))
"""Our colour passes beside Combined: the Blender pass name, and the pipeline's."""

DEBUG_RESULT_PASSES = (("VPL Splats", "vpl_splats"), ("Warp Status", "warp_status"))
"""The debug passes written when the scene's `debug_passes` is on (gpu/debug_views.py)."""

_last_stats = {}


def last_stats():
    """The statistics of the last frame rendered (F12 or viewport), for the panels."""
    return _last_stats


def _remember(stats):
    _last_stats.clear()
    _last_stats.update(stats)


def result_pixels(image, alpha=None):
    """A (height, width, c) top-row-first image as a RenderPass rect: bottom row first,
    one row per pixel, with an alpha channel appended when given."""
    rows = image[::-1].reshape(-1, image.shape[-1])
    if alpha is not None:
        rows = np.concatenate([rows, np.full((len(rows), 1), alpha, dtype=rows.dtype)], axis=1)
    return np.ascontiguousarray(rows, dtype=np.float32)


def viewport_camera(region_data):
    """The 3D view's own camera (view and window matrices, OpenGL conventions)."""
    return Camera(np.array(region_data.view_matrix, dtype=np.float64),
                  np.array(region_data.window_matrix, dtype=np.float64))


class DisplayRows:
    """Where a viewport frame's combined image lands: one float32 buffer of the view's
    size that the pipeline reads into directly (Pipeline.render's `display_into`).
    Here a numpy array; viewport_draw.ViewportImage makes it Blender's GPU buffer, so the
    image goes from our GL context to Blender's texture with one copy."""

    def __init__(self):
        self.size = None
        self.rows = None
        self.fresh = False  # rows hold a frame not yet drawn

    def allocate(self, count):
        return np.empty(count, dtype=np.float32)

    def target(self, size):
        """The buffer the next frame of `size` (width, height) goes into."""
        if self.size != size:
            self.rows = self.allocate(size[0] * size[1] * 4)
            self.size = size
        self.fresh = True
        return self.rows


class ViewportSession:
    """A viewport's pipeline and scene: what changed since the last draw decides what
    is extracted again; the pipeline's caches decide which stages run again."""

    def __init__(self, display=None):
        from ..gpu.pipeline import Pipeline
        self.pipeline = Pipeline()
        self.sync = SceneSync()
        self.display = display or DisplayRows()
        self.overlays = overlay.OverlayData()
        self.pending = set(EVERYTHING)
        self._shown = None  # (what the last drawn frame depends on, that frame)

    def note_updates(self, updates):
        self.pending |= changed_parts(updates)

    def frame(self, depsgraph, camera, size, view3d=None, settings=None):
        """Render the current scene from `camera` at `size` (width, height), with the
        scene's settings unless given."""
        start = time.perf_counter()
        scene = self.sync.scene(depsgraph, self.pending, camera, view3d)
        self.pending = set()
        extract_ms = (time.perf_counter() - start) * 1000.0
        if settings is None:
            settings = settings_from_properties(depsgraph.scene.lpv_preview, width=size[0], height=size[1])
        frame = self.pipeline.render(scene, settings, passes=(), display_into=self.display.target(size))
        frame.stats["extract_ms"] = extract_ms
        frame.stats["extracted"] = list(self.sync.extracted)
        _remember(frame.stats)
        return frame

    def frame_to_draw(self, depsgraph, camera, size, view3d=None):
        """The frame for a redraw: the last one again when no edit is pending and the
        view, its size and the settings are unchanged (Blender redraws the viewport for
        many reasons that change nothing we show), else a new one."""
        settings = settings_from_properties(depsgraph.scene.lpv_preview, width=size[0], height=size[1])
        depends_on = (camera.key(), settings)
        if self.pending or self._shown is None or self._shown[0] != depends_on:
            self._shown = (depends_on, self.frame(depsgraph, camera, size, view3d, settings))
        self.overlays.update(self.pipeline, display_settings_from_properties(depsgraph.scene.lpv_preview))
        return self._shown[1]

    def release(self):
        self.pipeline.release()


class LPVPreviewEngine(bpy.types.RenderEngine):
    bl_idname = ENGINE_ID
    bl_label = "LPV Preview"
    bl_use_preview = False
    bl_use_postprocess = True

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.session = None
        self.region = None  # the 3D view region whose overlays this engine's session feeds

    def __del__(self):
        session = getattr(self, "session", None)
        if session is not None:
            overlay.show(self.region, None)
            session.release()

    @staticmethod
    def result_passes(scene):
        """(Blender pass name, pipeline pass name) beside Combined for a render of `scene`."""
        debug = scene is not None and display_settings_from_properties(scene.lpv_preview).debug_passes
        return RESULT_PASSES + (DEBUG_RESULT_PASSES if debug else ())

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        for name, _ in self.result_passes(scene):
            self.register_pass(scene, renderlayer, name, 3, "RGB", "COLOR")

    def render(self, depsgraph):
        """F12 and batch: the whole frame at the render resolution."""
        from ..gpu.pipeline import Pipeline
        scene = depsgraph.scene_eval
        width, height = render_resolution(scene)
        pipeline = None
        try:
            self.update_stats("", "LPV Preview: reading the scene")
            settings = settings_from_properties(scene.lpv_preview, width=width, height=height)
            display = display_settings_from_properties(scene.lpv_preview)
            result_passes = self.result_passes(scene)
            lpv_scene = extract_scene(depsgraph)
            if lpv_scene.camera is None:
                raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
            self.update_progress(0.2)
            self.update_stats("", "LPV Preview: rendering")
            pipeline = Pipeline(settings)
            frame = pipeline.render(lpv_scene, passes=("combined", *(source for _, source in result_passes)),
                                    display_settings=display)
        except LPVError as error:
            self.report({"ERROR"}, str(error))
            return
        finally:
            if pipeline is not None:
                pipeline.release()
        _remember(frame.stats)
        self.update_progress(0.9)
        result = self.begin_result(0, 0, width, height)
        layer = result.layers[0]
        # foreach_set of a flat array: ~300 times faster than assigning `rect` a 2-D array.
        layer.passes["Combined"].rect.foreach_set(result_pixels(frame.passes["combined"], alpha=1.0).ravel())
        for name, source in result_passes:
            layer.passes[name].rect.foreach_set(result_pixels(frame.passes[source]).ravel())
        self.end_result(result)
        self.update_progress(1.0)
        self.update_stats("", f"LPV Preview: {frame.stats['total_ms']:.0f} ms, {frame.stats['vpl_count']} VPLs")

    def view_update(self, context, depsgraph):
        if self.session is None:
            from .viewport_draw import ViewportImage
            try:
                self.session = ViewportSession(ViewportImage())
            except LPVError as error:
                self.report({"ERROR"}, str(error))
                return
        self.session.note_updates(record_updates(depsgraph))

    def view_draw(self, context, depsgraph):
        if self.session is None:
            return
        region = context.region
        size = (region.width, region.height)
        self.region = region.as_pointer()
        camera = viewport_camera(context.region_data)
        try:
            frame = self.session.frame_to_draw(depsgraph, camera, size, context.space_data)
        except LPVError as error:
            self.report({"ERROR"}, str(error))
            return
        self.session.display.draw(self, depsgraph.scene)
        overlay.show(self.region, self.session.overlays)
        self.update_stats("", f"LPV Preview: {frame.stats['total_ms']:.0f} ms")


SKIPPED_PANELS = {"VIEWLAYER_PT_filter", "VIEWLAYER_PT_layer_passes", "RENDER_PT_eevee_performance",
                  "RENDER_PT_freestyle"}
"""Built-in panels for Blender's own engines that mean nothing to ours."""


def shared_panels():
    """Blender's built-in panels (light, material, camera, output...) that list its own
    render engine: LPV Preview joins them, as Blender's RenderEngine example does."""
    return [panel for panel in bpy.types.Panel.__subclasses__()
            if "BLENDER_RENDER" in getattr(panel, "COMPAT_ENGINES", ()) and panel.__name__ not in SKIPPED_PANELS]


def register():
    bpy.utils.register_class(LPVPreviewEngine)
    for panel in shared_panels():
        panel.COMPAT_ENGINES.add(ENGINE_ID)


def unregister():
    for panel in shared_panels():
        panel.COMPAT_ENGINES.discard(ENGINE_ID)
    bpy.utils.unregister_class(LPVPreviewEngine)
    _last_stats.clear()
