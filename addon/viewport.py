"""The viewport's side of the engine: one session per 3D view keeps a pipeline and the
extracted scene, so a redraw re-extracts only what an edit touched and reruns only the
stages that depend on it (docs/architecture.md, "What each edit redoes").

`DisplayRows` is where a frame's combined image lands; addon/viewport_draw.py makes it
Blender's GPU buffer and draws it. Nothing here draws, so it runs and is tested in
background mode.
"""
import time

import numpy as np

from ..gpu.pipeline import Pipeline
from ..gpu.scene import Camera
from . import frame_stats, overlay
from .properties import (correction_settings_from_properties, display_settings_from_properties,
                         settings_from_properties)
from .sync import EVERYTHING, SceneSync, changed_parts, edits_cycles_sees
from .viewport_corrections import ViewportCorrections, corrected_size


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
        self.pipeline = Pipeline()
        self.sync = SceneSync()
        self.display = display or DisplayRows()
        self.overlays = overlay.OverlayData()
        self.corrections = ViewportCorrections()
        self.pending = set(EVERYTHING)
        self.edited = True  # what Cycles renders changed since the last redraw
        self.scene = None  # the Scene last extracted
        self._shown = None  # (what the last drawn frame depends on, that frame)

    def note_updates(self, updates):
        parts = changed_parts(updates)
        self.pending |= parts
        self.edited |= edits_cycles_sees(updates, parts)

    def frame(self, depsgraph, camera, size, view3d=None, settings=None, accumulate=False):
        """Render the current scene from `camera` at `size` (width, height), with the
        scene's settings unless given; with `accumulate`, another VPL set averaged into
        the last frame's indirect light (Pipeline.render)."""
        start = time.perf_counter()
        scene = self.sync.scene(depsgraph, self.pending, camera, view3d)
        self.scene = scene
        self.pending = set()
        extract_ms = (time.perf_counter() - start) * 1000.0
        if settings is None:
            settings = settings_from_properties(depsgraph.scene.lpv_preview, width=size[0], height=size[1])
        frame = self.pipeline.render(scene, settings, passes=(), display_into=self.display.target(size),
                                     vpl_set=self.pipeline.vpl_pattern + 1 if accumulate else None,
                                     accumulate=accumulate)
        frame.stats["extract_ms"] = extract_ms
        frame.stats["extracted"] = list(self.sync.extracted)
        frame_stats.remember(frame.stats)
        return frame

    def frame_to_draw(self, depsgraph, camera, size, view3d=None):
        """The frame for a redraw: a new one when an edit is pending or the view, its size
        or the settings changed; while they stay, one more VPL set averaged in until the
        still view has `viewport_vpl_sets` (`converging`), then the last one again
        (Blender redraws the viewport for many reasons that change nothing we show).
        With viewport corrections on, the view is rendered at most
        `correction_viewport_width` wide, and corrected by what the Cycles samples
        of it brought (addon/viewport_corrections.py) instead of converging."""
        properties = depsgraph.scene.lpv_preview
        correction = correction_settings_from_properties(properties)
        if correction.viewport_corrections:
            size = corrected_size(size, correction.correction_viewport_width)
        settings = settings_from_properties(properties, width=size[0], height=size[1])
        display = display_settings_from_properties(properties)
        depends_on = (camera.key(), settings)
        if self._shown is None or self._shown[0] != depends_on:
            self._shown = (depends_on, self.frame(depsgraph, camera, size, view3d, settings))
        elif self.pending or self.converging(display, correction):  # the pipeline starts again if the scene changed
            self._shown = (depends_on, self.frame(depsgraph, camera, size, view3d, settings, accumulate=True))
        self.overlays.update(self.pipeline, display)
        frame = self._shown[1]
        edited, self.edited = self.edited, False
        if not correction.viewport_corrections:
            self.corrections.stop()
            return frame
        frame.stats.update(self.corrections.show(depsgraph.scene, frame, self.scene, self.pipeline, camera,
                                                 self.display, correction.correction_workers, edited))
        frame_stats.remember(frame.stats)
        return frame

    def converging(self, display, correction=None):
        """Whether the next redraw of the still view adds a VPL set (not while corrected)."""
        if correction is not None and correction.viewport_corrections:
            return False
        return self._shown is not None and self._shown[1].stats["vpl_sets"] < display.viewport_vpl_sets

    def release(self):
        self.corrections.stop()
        self.pipeline.release()
