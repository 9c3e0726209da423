"""The "LPV Preview" render engine: a thin RenderEngine, as the Cycles add-on's is.

F12 and batch renders go to final_render.render_final; the viewport keeps one
viewport.ViewportSession per 3D view: `view_update` notes which parts of the scene
changed, `view_draw` hands the session's GL thread (gpu/gl_thread.py) the frame they
need and draws the last finished one with Blender's `gpu` module (viewport_draw.py,
imported only when a viewport opens: in background mode Blender has no drawing); a frame
finished later tags a redraw. Blender's own GL context is never touched. Errors a user
can fix are reported in one line, never as a traceback.
"""
import bpy

from ..gpu.errors import LPVError
from . import frame_stats, overlay
from .final_render import render_final, scene_passes
from .properties import correction_settings_from_properties, display_settings_from_properties
from .sync import record_updates
from .viewport import ViewportSession, viewport_camera
from .viewport_corrections import REBUILD_SECONDS

ENGINE_ID = "LPV_PREVIEW"
POLL_SECONDS = 0.01
"""How often Blender's thread looks whether the GL thread has finished a frame."""


class LPVPreviewEngine(bpy.types.RenderEngine):
    bl_idname = ENGINE_ID
    bl_label = "LPV Preview"
    bl_use_preview = False
    bl_use_postprocess = True

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.session = None
        self.region = None  # the 3D view region whose overlays this engine's session feeds
        self.redraw_pending = False
        self.polling = False

    def __del__(self):
        try:
            session = self.session
        except (AttributeError, ReferenceError):  # never initialised, or its class unregistered since
            return
        if session is not None:
            overlay.show(self.region, None)
            session.release()

    def update_render_passes(self, scene=None, renderlayer=None):
        for render_pass in scene_passes(scene):
            self.register_pass(scene, renderlayer, render_pass.blender_name, len(render_pass.channels),
                               render_pass.channels, "COLOR")

    def render(self, depsgraph):
        try:
            render_final(self, depsgraph)
        except LPVError as error:
            self.report({"ERROR"}, str(error))

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
        self.region = region.as_pointer()
        camera = viewport_camera(context.region_data)
        try:
            frame = self.session.redraw(depsgraph, camera, (region.width, region.height), context.space_data)
        except LPVError as error:
            self.report({"ERROR"}, str(error))
            return
        if frame is not None:
            self.session.display.draw(self, depsgraph.scene, (region.width, region.height))
            overlay.show(self.region, self.session.overlays)
            sets = frame.stats["vpl_sets"]
            samples = frame.stats.get("correction_samples")
            self.update_stats("", f"LPV Preview: {frame.stats['total_ms']:.0f} ms" +
                              (f", {sets} VPL sets" if sets > 1 else "") +
                              (f", {samples:,} Cycles samples" if samples else ""))
        properties = depsgraph.scene.lpv_preview
        if self.session.rendering:
            self.redraw_when_rendered()
        elif self.session.converging(display_settings_from_properties(properties),
                                     correction_settings_from_properties(properties)):
            self.tag_redraw()  # a still view goes on converging
        elif self.session.corrections.streaming:
            self.redraw_later()  # samples go on coming

    def redraw_when_rendered(self):
        """Draw again once the GL thread has finished the frame it makes (once)."""
        self._redraw_once("polling", POLL_SECONDS,
                          lambda: self.session is not None and self.session.rendering and not self.session.frame_done)

    def redraw_later(self):
        """Draw again in REBUILD_SECONDS (once), to show the samples come by then."""
        self._redraw_once("redraw_pending", REBUILD_SECONDS)

    def _redraw_once(self, flag, interval, waiting=lambda: False):
        """Tag a redraw after `interval` seconds, and every `interval` after while
        `waiting()`, unless the attribute `flag` says one is on its way already."""
        if getattr(self, flag):
            return
        setattr(self, flag, True)

        def redraw():
            try:
                if waiting():
                    return interval
                setattr(self, flag, False)
                self.tag_redraw()
            except ReferenceError:  # the engine was freed meanwhile
                pass
            return None
        bpy.app.timers.register(redraw, first_interval=interval)


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
    frame_stats.forget()
