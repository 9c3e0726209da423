"""The comparison operator: Cycles references and the ticked methods, in one click.

Invoked from the panel it runs `addon.comparison.comparison_steps` one step per timer tick,
with the window's progress bar and the step in the status bar; Esc stops it between steps
(each Cycles render is of a temporary copy of the scene, removed also when it fails). The
results fill the panel's table and image datablocks ("LPV Compare ...") that the user can
open in an Image Editor.
"""
import bpy
import numpy as np

from ..addon.comparison import IMAGES, comparison_steps, forget, reference_label, remember
from ..addon.cycles_reference import ReferenceCache, run_to_end
from ..addon.extract import render_resolution
from ..addon.properties import comparison_settings_from_properties, settings_from_properties
from ..gpu.errors import LPVError
from ..gpu.image_library import openimageio

IMAGE_PREFIX = "LPV Compare"
TICK_SECONDS = 0.05


def comparison_of(scene):
    """The comparison generator for `scene`'s own settings at its render resolution."""
    openimageio()  # the references are read from EXRs: refused before any render where nothing can read one
    properties = scene.lpv_preview
    compare = comparison_settings_from_properties(properties)
    if not compare.methods:
        raise LPVError("No method is ticked for the comparison; tick at least one in the Comparison panel.")
    width, height = render_resolution(scene)
    settings = settings_from_properties(properties, width=width, height=height)
    if not compare.indirect_methods:
        raise LPVError("No indirect method is ticked for the comparison; tick at least one in the Comparison panel.")
    return comparison_steps(scene, compare.methods, compare.compare_samples, settings, ReferenceCache(),
                            noise_floor=compare.compare_noise_floor, indirect_methods=compare.indirect_methods,
                            peers=compare.compare_peers)


def image_names(comparison):
    """The datablock name of every image a comparison shows, with its pixels and colour space."""
    images = {}
    for kind, reference in comparison.references.items():
        for image in reference.compared_images:
            images[f"{IMAGE_PREFIX} Cycles {reference_label(kind)} {image}"] = (getattr(reference, image), "linear")
    for result in comparison.methods:
        for image in IMAGES:
            images[f"{IMAGE_PREFIX} {result.label} {image}"] = (result.images[image], "linear")
        for kind in comparison.references:
            images[f"{IMAGE_PREFIX} {result.label} error vs {reference_label(kind)}"] = (
                comparison.heat_map(result, kind), "display")
    for peer in comparison.peers:
        for image, pixels in peer.images.items():
            images[f"{IMAGE_PREFIX} {peer.name} {image}"] = (pixels, "linear")
        for image, pixels in peer.diffuse_images.items():
            images[f"{IMAGE_PREFIX} {peer.name} diffuse {image}"] = (pixels, "linear")
    return images


def store_images(comparison):
    """Create or update one float image datablock per picture of the comparison."""
    for name, (pixels, space) in image_names(comparison).items():
        height, width = pixels.shape[:2]
        image = bpy.data.images.get(name)
        if image is not None and tuple(image.size) != (width, height):
            bpy.data.images.remove(image)
            image = None
        if image is None:
            image = bpy.data.images.new(name, width, height, alpha=False, float_buffer=True)
        # Linear renders in the scene's linear space; heat maps are display values already.
        image.colorspace_settings.name = "Linear Rec.709" if space == "linear" else "sRGB"
        rgba = np.ones((height, width, 4), dtype=np.float32)
        rgba[..., :3] = pixels[::-1]
        image.pixels.foreach_set(rgba.ravel())
        image.update()


class LPV_OT_compare_with_cycles(bpy.types.Operator):
    bl_idname = "lpv_preview.compare_with_cycles"
    bl_label = "Compare with Cycles"
    bl_description = ("Render Cycles' Combined as F12 renders the current camera and frame (and, to diagnose, its "
                      "diffuse light with one bounce and full GI), run each ticked method and, when ticked, EEVEE "
                      "and denoised Cycles, and measure their errors; Esc stops")

    def execute(self, context):
        try:
            comparison = run_to_end(comparison_of(context.scene))
        except LPVError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self._finish(context, comparison)
        return {"FINISHED"}

    def invoke(self, context, event):
        try:
            self._steps = comparison_of(context.scene)
            _, label = next(self._steps)
        except LPVError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        manager = context.window_manager
        manager.progress_begin(0.0, 1.0)
        self._timer = manager.event_timer_add(TICK_SECONDS, window=context.window)
        manager.modal_handler_add(self)
        context.workspace.status_text_set(f"LPV Preview: {label} (Esc to stop)")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._steps.close()
            self._end(context)
            self.report({"INFO"}, "LPV Preview: comparison stopped; the scene's settings are as they were.")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}
        try:
            fraction, label = next(self._steps)
        except StopIteration as finished:
            self._end(context)
            self._finish(context, finished.value)
            return {"FINISHED"}
        except LPVError as error:
            self._end(context)
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        context.window_manager.progress_update(fraction)
        context.workspace.status_text_set(f"LPV Preview: {label} (Esc to stop)")
        return {"RUNNING_MODAL"}

    def _end(self, context):
        manager = context.window_manager
        manager.event_timer_remove(self._timer)
        manager.progress_end()
        context.workspace.status_text_set(None)

    def _finish(self, context, comparison):
        remember(comparison)
        store_images(comparison)
        for area in context.screen.areas if context.screen is not None else ():
            area.tag_redraw()
        self.report({"INFO"}, f"LPV Preview: compared {len(comparison.methods)} methods with Cycles.")


CLASSES = (LPV_OT_compare_with_cycles,)
register_classes, unregister_classes = bpy.utils.register_classes_factory(CLASSES)


def register():
    register_classes()


def unregister():
    unregister_classes()
    forget()
