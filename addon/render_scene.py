"""The Scene that F12 renders, for every entry point that is not F12 itself.

Blender evaluates a scene for rendering only while it renders: object and collection
render visibility, collections excluded from the view layer, instancers shown or hidden
in renders make that depsgraph differ from the viewport's that
`bpy.context.evaluated_depsgraph_get()` returns. So the command line, the comparison and
the Cycles references' cache keys ask for a render of our own engine, whose `render()`
extracts the Scene from the depsgraph Blender hands it and renders nothing
(final_render.py `take_extraction`). The engine is given back as it was, also on error
and on Ctrl-C (held back until the render call returns: gpu/ctrl_c.py).
"""
from contextlib import contextmanager

import bpy

from ..gpu.ctrl_c import ctrl_c_held
from ..gpu.errors import LPVError, first_line
from .cycles_render import view_layer_to_render
from .engine import ENGINE_ID, LPVPreviewEngine
from .final_render import ExtractionRequest, pending_extractions


@contextmanager
def _our_engine(scene):
    """`scene` renders with our engine (registered for the while when the add-on is not)."""
    registered_here = not LPVPreviewEngine.is_registered
    if registered_here:
        bpy.utils.register_class(LPVPreviewEngine)
    saved = scene.render.engine
    try:
        scene.render.engine = ENGINE_ID
        yield
    finally:
        scene.render.engine = saved
        if registered_here:
            bpy.utils.unregister_class(LPVPreviewEngine)


def scene_to_render(scene, resolution=None):
    """The sanitized gpu Scene that F12 renders of `scene`'s current frame, its camera
    projected for `resolution` (None: the render resolution)."""
    return _extraction(scene, ExtractionRequest(resolution)).scene


def scene_and_signature_to_render(scene, resolution=None):
    """`scene_to_render`'s Scene and the hash of what F12 renders (addon/render_signature.py),
    read from one render depsgraph."""
    request = _extraction(scene, ExtractionRequest(resolution, with_signature=True))
    return request.scene, request.signature


def _extraction(scene, request):
    """`request` fulfilled by a render of `scene` with our engine."""
    with _our_engine(scene):
        pending_extractions.append(request)
        try:
            with ctrl_c_held():
                bpy.ops.render.render(scene=scene.name, layer=view_layer_to_render(scene).name)
        except RuntimeError as error:  # Blender refused to start: no camera, say
            if scene.camera is None:
                raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
            reason = first_line(error).removeprefix("Error: ")
            if reason.startswith("Image too small"):
                render = scene.render
                raise LPVError(f"Scene '{scene.name}' renders {render.resolution_percentage} % of "
                               f"{render.resolution_x} x {render.resolution_y} pixels, too small for Blender; raise "
                               f"its Output resolution or percentage.") from None
            raise LPVError(f"Blender cannot render scene '{scene.name}': {reason}.") from None
        finally:
            pending_extractions.remove(request)
    if request.error is not None:
        raise request.error
    if request.scene is None:
        raise LPVError(f"Blender did not render scene '{scene.name}'; check that its view layer "
                       f"'{view_layer_to_render(scene).name}' is enabled for rendering.")
    return request
