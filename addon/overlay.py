"""Viewport overlays: the VPLs as points coloured by flux, a slice through the LPV, and
the warp status map of the first warped light.

What to draw is computed from a viewport's last frame (gpu/debug_views.py) by
`OverlayData.update`, which runs and is tested without a display. Two 3D-view draw
handlers, added by `register` and removed by `unregister`, hand it to Blender's `gpu`
module: points and slice in the scene (depth-tested), the status map in a corner.
"""
import bpy
import numpy as np

from ..gpu.debug_views import lpv_slice, vpl_points, warp_status_image

STATUS_MAP_HEIGHT = 256   # pixels the warp status map takes in the view's corner
STATUS_MAP_MARGIN = 16

_handlers = []
_shown = {}  # region pointer -> the OverlayData its render engine keeps


class OverlayData:
    """What one viewport's overlays show; each is recomputed only when the frame's light
    maps or LPV, or its own settings, change."""

    def __init__(self):
        self.vpls = None          # VPLPoints
        self.slice = None         # LPVSlice
        self.warp_status = None   # (height, width, 4) colours
        self.point_size = 1.0
        self.keys = {}            # overlay -> what its data was computed from
        self.drawables = {}       # overlay -> Blender GPU batches and textures, made when first drawn

    def update(self, pipeline, display):
        """Bring the overlays up to `pipeline`'s last frame and `display` (DisplaySettings);
        returns whether any changed."""
        self.point_size = display.vpl_point_size
        light = pipeline.last_indirect_key  # names every light's maps and the indirect grids' own settings
        maps = pipeline.last_light_maps
        origin = pipeline.last_origin  # the frame's positions are relative to it; Blender draws in world space
        warped = next((m.warp for m in maps if m.warp is not None), None)
        wanted = {
            "vpls": ((light, display.show_vpls), lambda: vpl_points(maps, origin) if display.show_vpls else None),
            "slice": ((light, display.show_lpv_slice, display.lpv_slice_axis, display.lpv_slice_position),
                      lambda: lpv_slice(pipeline.last_indirect, display.lpv_slice_axis, display.lpv_slice_position,
                                        origin)
                      if display.show_lpv_slice and pipeline.last_indirect is not None else None),
            "warp_status": ((light, display.show_warp_status),
                            lambda: warp_status_image(warped) if display.show_warp_status and warped else None),
        }
        changed = False
        for name, (key, compute) in wanted.items():
            if self.keys.get(name) != key:
                self.keys[name] = key
                setattr(self, name, compute())
                self.drawables.pop(name, None)
                changed = True
        return changed

    @property
    def empty(self):
        return self.vpls is None and self.slice is None and self.warp_status is None


def show(region_pointer, data):
    """Let the draw handlers draw `data` in the region (None: draw nothing there)."""
    if data is None:
        _shown.pop(region_pointer, None)
    else:
        _shown[region_pointer] = data


def _current():
    context = bpy.context
    if context.region is None or not context.space_data.overlay.show_overlays:
        return None
    data = _shown.get(context.region.as_pointer())
    return None if data is None or data.empty else data


def _texture(image):
    import gpu
    height, width = image.shape[:2]
    buffer = gpu.types.Buffer("FLOAT", image.size)
    np.asarray(buffer)[:] = image.ravel()
    return gpu.types.GPUTexture((width, height), format="RGBA16F", data=buffer)


def draw_in_scene():
    """POST_VIEW: the LPV slice and the VPL points, depth-tested against the scene."""
    data = _current()
    if data is None or (data.vpls is None and data.slice is None):
        return
    import gpu
    from gpu_extras.batch import batch_for_shader
    gpu.state.depth_test_set("LESS_EQUAL")
    gpu.state.blend_set("ALPHA")
    if data.slice is not None:
        shader = gpu.shader.from_builtin("IMAGE")
        if "slice" not in data.drawables:
            corners = [tuple(map(float, c)) for c in data.slice.corners]
            batch = batch_for_shader(shader, "TRIS", {"pos": corners, "texCoord": ((0, 0), (1, 0), (1, 1), (0, 1))},
                                     indices=((0, 1, 2), (2, 3, 0)))
            data.drawables["slice"] = (batch, _texture(data.slice.image))
        batch, texture = data.drawables["slice"]
        shader.uniform_sampler("image", texture)
        batch.draw(shader)
    if data.vpls is not None and len(data.vpls.positions):
        shader = gpu.shader.from_builtin("POINT_FLAT_COLOR")
        if "vpls" not in data.drawables:
            data.drawables["vpls"] = batch_for_shader(shader, "POINTS", {"pos": data.vpls.positions,
                                                                          "color": data.vpls.colours})
        shader.uniform_float("size", data.point_size)
        data.drawables["vpls"].draw(shader)
    gpu.state.blend_set("NONE")
    gpu.state.depth_test_set("NONE")


def draw_in_corner():
    """POST_PIXEL: the warp status map in the lower left corner."""
    data = _current()
    if data is None or data.warp_status is None:
        return
    import gpu
    from gpu_extras.presets import draw_texture_2d
    if "warp_status" not in data.drawables:
        data.drawables["warp_status"] = _texture(data.warp_status)
    height, width = data.warp_status.shape[:2]
    gpu.state.blend_set("ALPHA")
    draw_texture_2d(data.drawables["warp_status"], (STATUS_MAP_MARGIN, STATUS_MAP_MARGIN),
                    STATUS_MAP_HEIGHT * width / height, STATUS_MAP_HEIGHT)
    gpu.state.blend_set("NONE")


def handler_count():
    return len(_handlers)


def register():
    space = bpy.types.SpaceView3D
    _handlers.append((space.draw_handler_add(draw_in_scene, (), "WINDOW", "POST_VIEW"), "WINDOW"))
    _handlers.append((space.draw_handler_add(draw_in_corner, (), "WINDOW", "POST_PIXEL"), "WINDOW"))


def unregister():
    while _handlers:
        handle, region_type = _handlers.pop()
        bpy.types.SpaceView3D.draw_handler_remove(handle, region_type)
    _shown.clear()
