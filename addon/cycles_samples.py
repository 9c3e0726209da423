"""Cycles samples of a view, for corrective texturing (issue 18, seed 001): a renderer
loads a .blend once and renders border regions of a camera on request, Cycles keeping its
scene between requests (persistent data), so a request costs little beyond its samples.
A worker process holds one (corrections/sample_workers.py)."""
import math
import os
import time

import bpy
import numpy as np
from mathutils import Matrix

from ..corrections.sample_request import SampleResult
from ..gpu.errors import LPVError
from ..gpu.temporary_folders import make_temporary_folder, remove_temporary_folder
from .cycles_render import (PASS_BY_NAME, REFERENCE_BOUNCES, REFERENCE_FILTER_WIDTH, apply_render_settings, assign,
                            enable_cycles, read_exr_passes, render_to_file, view_layer_to_render)

LENS_SETTINGS = ("type", "sensor_fit", "lens", "sensor_width", "sensor_height", "shift_x", "shift_y", "clip_start",
                 "clip_end")
"""The camera data a request's projection sets, and restores for a request without one
(with its depth of field, `dof.use_dof`)."""
SAMPLE_PASSES = ("Combined",)
"""What a request returns: all the light, what the corrections aim at (as the full-GI
reference: its bounces and pixel filter)."""


class SampleRenderer:
    """A .blend opened once, rendering requests with Cycles on the CPU."""

    def __init__(self, blend_path):
        if not os.path.isfile(blend_path):
            raise LPVError(f"There is no .blend file '{blend_path}' for the Cycles sample workers; give a path "
                           f"every worker can read.")
        bpy.ops.wm.open_mainfile(filepath=blend_path, load_ui=False)
        enable_cycles()
        self.scene = bpy.context.scene
        self.view_layer = view_layer_to_render(self.scene)
        self.scene.render.use_persistent_data = True
        self._camera, self._lens = self._own_camera()
        self.scene_frame = self.scene.frame_current
        self._folder = make_temporary_folder("lpv_cycles_samples_")  # one for every request: no setup each

    def close(self):
        remove_temporary_folder(self._folder)

    def render(self, request, threads=None):
        """The SampleResult of `request`, Cycles on `threads` threads (None: all)."""
        scene = self.scene
        self._go_to_frame(request.scene_frame)  # first: the animation may set what follows
        if scene.camera is None:
            raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
        exr_path = os.path.join(self._folder, "samples.exr")
        apply_render_settings(scene, self.view_layer, exr_path, SAMPLE_PASSES, request.samples, (0, request.samples),
                              request.resolution, request.seed, REFERENCE_BOUNCES["full_gi"], 0.0,
                              REFERENCE_FILTER_WIDTH, request.denoise, request.region, threads)
        x0, y0, x1, y1 = request.region
        camera = request.camera if request.camera is not None else self._camera
        if camera is not None:
            assign(scene.camera, matrix_world=Matrix(camera))  # a nested list would be read as columns
        self._set_lens(request.projection)
        started = time.perf_counter()
        render_to_file(scene, exr_path)
        passes = read_exr_passes(exr_path, self.view_layer.name,
                                 {name: PASS_BY_NAME[name].exr_layer for name in SAMPLE_PASSES})
        size = (y1 - y0, x1 - x0)
        for name, image in passes.items():
            if image.shape[:2] != size:
                raise LPVError(f"Cycles rendered a {image.shape[1]} x {image.shape[0]} region for a request of "
                               f"{size[1]} x {size[0]} pixels.")
        return SampleResult(request, {name: np.ascontiguousarray(image, np.float32) for name, image in passes.items()},
                            time.perf_counter() - started)

    def _own_camera(self):
        """The scene camera's world matrix and lens as they are now (None, None: no camera)."""
        camera = self.scene.camera
        if camera is None:
            return None, None
        return (tuple(map(tuple, camera.matrix_world)),
                {**{name: getattr(camera.data, name) for name in LENS_SETTINGS}, "use_dof": camera.data.dof.use_dof})

    def _go_to_frame(self, scene_frame):
        """Set the animation at `scene_frame` (None: stay); the camera as the animation sets
        it there (markers may bind another) is then the frame's own."""
        if scene_frame is None or scene_frame == self.scene_frame:
            return
        self.scene.frame_set(scene_frame)
        self.scene_frame = scene_frame
        self._camera, self._lens = self._own_camera()

    def _set_lens(self, projection):
        """The camera's lens as `projection` (an unshifted OpenGL perspective, a 3D view's:
        no depth of field) gives, or its own for None."""
        data = self.scene.camera.data
        if projection is None:
            wanted = self._lens
        else:
            p = np.asarray(projection, dtype=np.float64)
            wanted = {"type": "PERSP", "sensor_fit": "VERTICAL", "angle_y": 2 * math.atan(1 / p[1, 1]),
                      "shift_x": 0.0, "shift_y": 0.0, "clip_start": p[2, 3] / (p[2, 2] - 1),
                      "clip_end": p[2, 3] / (p[2, 2] + 1), "use_dof": False}
        assign(data, **{name: value for name, value in wanted.items() if name != "use_dof"})
        assign(data.dof, use_dof=wanted["use_dof"])

