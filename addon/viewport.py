"""The viewport's side of the engine: one session per 3D view keeps a pipeline and the
extracted scene, so a redraw re-extracts only what an edit touched and reruns only the
stages that depend on it (docs/architecture.md, "What each edit redoes").

`DisplayRows` is where a frame's combined image lands; addon/viewport_draw.py makes it
Blender's GPU buffer and draws it. Nothing here draws, so it runs and is tested in
background mode.
"""
import time
from dataclasses import dataclass, replace

import numpy as np

from ..gpu.gl_thread import GLThread
from ..gpu.pipeline import Pipeline
from ..gpu.scene import Camera
from ..gpu.shade import DISPLAY_CHANNELS
from . import frame_stats, overlay
from .properties import (correction_settings_from_properties, display_settings_from_properties,
                         settings_from_properties)
from .sync import CAMERA, EVERYTHING, SceneSync, changed_parts, edits_cycles_sees
from .viewport_corrections import ViewportCorrections, corrected_size


def viewport_camera(region_data):
    """The 3D view's own camera (view and window matrices, OpenGL conventions)."""
    return Camera(np.array(region_data.view_matrix, dtype=np.float64),
                  np.array(region_data.window_matrix, dtype=np.float64))


class DisplayRows:
    """Where viewport frames' combined images land: two float32 buffers, the one drawn
    (`rows`, of `size`) and the one the GL thread renders the next frame into (`target`;
    Pipeline.render's `display_into`), swapped when that frame is done (`present`), so
    Blender's thread never draws a frame being written. Here numpy arrays;
    viewport_draw.ViewportImage makes them Blender's GPU buffers, so the image goes from
    our GL context to Blender's texture with one copy."""

    def __init__(self):
        self._front = self._back = None  # (size, rows, what allocate gave for drawing them)
        self.fresh = False  # the front rows hold a frame not yet drawn

    def allocate(self, count):
        """Rows for `count` floats, and what draws them (nothing here)."""
        return np.empty(count, dtype=np.float32), None

    @property
    def size(self):
        return self._front[0] if self._front is not None else None

    @property
    def rows(self):
        """The rows drawn: the last finished frame's."""
        return self._front[1] if self._front is not None else None

    @property
    def handle(self):
        return self._front[2] if self._front is not None else None

    def target(self, size):
        """The buffer the next frame of `size` (width, height) goes into."""
        if self._back is None or self._back[0] != size:
            self._back = (size, *self.allocate(size[0] * size[1] * DISPLAY_CHANNELS))
        return self._back[1]

    def present(self):
        """The frame rendered into `target` is done: it becomes the one drawn."""
        self._front, self._back = self._back, self._front
        self.fresh = True


@dataclass
class FrameJob:
    """A frame the GL thread renders for the view: the extracted scene, its settings and
    size, whether it adds a VPL set to the last one, and what it depends on."""

    scene: object
    settings: object  # the frame's own: the view's, or refined (Settings.refined)
    display: object  # DisplaySettings
    size: tuple
    accumulate: bool
    depends_on: tuple
    extract_ms: float
    refined: bool = False
    future: object = None


class ViewportSession:
    """A viewport's pipeline and scene: what changed since the last draw decides what
    is extracted again; the pipeline's caches decide which stages run again. The pipeline
    lives on the GL thread (gpu/gl_thread.py): Blender's thread extracts the scene and
    hands frames over, `frame_to_draw` waiting for each, `redraw` never."""

    def __init__(self, display=None, gl=None):
        self.gl = gl or GLThread.shared()
        self.pipeline = self.gl.call(Pipeline)
        self.sync = SceneSync()
        self.display = display or DisplayRows()
        self.overlays = overlay.OverlayData()
        self.corrections = ViewportCorrections(self.gl)
        self.pending = set(EVERYTHING)
        self.edited = True  # what Cycles renders changed since the last redraw
        self.scene = None  # the Scene last extracted
        self._shown = None  # (what the last drawn frame depends on, that frame)
        self._job = None  # the FrameJob the GL thread renders now
        self._refined = False  # whether the frame shown gathered at the finer grids

    def note_updates(self, updates):
        parts = changed_parts(updates, self.sync.emitters_alone)
        self.pending |= parts
        self.edited |= edits_cycles_sees(updates, parts)

    def frame(self, depsgraph, camera, size, view3d=None, settings=None, accumulate=False):
        """Render the current scene from `camera` at `size` (width, height), with the
        scene's settings unless given, and wait for it; with `accumulate`, another VPL
        set averaged into the last frame's indirect light (Pipeline.render)."""
        properties = depsgraph.scene.lpv_preview
        if settings is None:
            settings = settings_from_properties(properties, width=size[0], height=size[1])
        job = self._job_for(depsgraph, camera, size, view3d, settings, display_settings_from_properties(properties),
                            accumulate, correction_settings_from_properties(properties).viewport_corrections)
        return self._finish(job, self.gl.call(self._render, job))

    def _job_for(self, depsgraph, camera, size, view3d, settings, display, accumulate, corrected):
        """The scene extracted for a frame (on Blender's thread: bpy), as a FrameJob;
        `corrected`: whether the view is corrected toward Cycles (it never refines)."""
        start = time.perf_counter()
        # A still view refines its grids; once refined, a move of the view alone keeps the
        # finer grids (built already, so nothing on the light side is made again), and an
        # edit goes back to the coarser ones for speed.
        finer = settings.refined(self.pipeline.glc.is_software)
        shown = self._shown[0][1] if self._shown is not None else None
        edited = bool(self.pending - {CAMERA}) or shown is None or \
            replace(shown, width=settings.width, height=settings.height) != settings  # the panel's settings
        refined = finer is not settings and not edited and not corrected and (accumulate or self._refined)
        scene = self.sync.scene(depsgraph, self.pending, camera, view3d)
        self.scene = scene
        self.pending = set()
        return FrameJob(scene, finer if refined else settings, display, size, accumulate, (camera.key(), settings),
                        (time.perf_counter() - start) * 1000.0, refined)

    def _render(self, job):
        """On the GL thread: the job's frame into the display's back rows, the overlays
        brought up to it."""
        frame = self.pipeline.render(job.scene, job.settings, passes=(), display_into=self.display.target(job.size),
                                     vpl_set=self.pipeline.vpl_pattern + 1 if job.accumulate else None,
                                     accumulate=job.accumulate)
        self.overlays.update(self.pipeline, job.display)
        return frame

    def _finish(self, job, frame):
        """On Blender's thread: the job's frame is done, and shown from now on."""
        self.display.present()
        self._refined = job.refined
        frame.stats["extract_ms"] = job.extract_ms
        frame.stats["extracted"] = list(self.sync.extracted)
        frame_stats.remember(frame.stats)
        self._shown = (job.depends_on, frame)
        return frame

    def _next_job(self, depsgraph, camera, size, view3d, properties):
        """The FrameJob a redraw needs (`redraw`), or None: the frame shown is still the
        view's (Blender redraws the viewport for many reasons that change nothing we show)."""
        correction = correction_settings_from_properties(properties)
        settings = settings_from_properties(properties, width=size[0], height=size[1])
        display = display_settings_from_properties(properties)
        if self._shown is None or self._shown[0] != (camera.key(), settings):
            return self._job_for(depsgraph, camera, size, view3d, settings, display, False,
                                 correction.viewport_corrections)
        if self.pending or self.converging(display, correction):  # the pipeline starts again if the scene changed
            return self._job_for(depsgraph, camera, size, view3d, settings, display, True,
                                 correction.viewport_corrections)
        return None

    def _view_size(self, properties, size):
        """The size a view of `size` renders at: at most `correction_viewport_width` wide
        while corrected toward Cycles."""
        correction = correction_settings_from_properties(properties)
        return corrected_size(size, correction.correction_viewport_width) if correction.viewport_corrections else size

    def frame_to_draw(self, depsgraph, camera, size, view3d=None):
        """The frame for a redraw, as `redraw` gives it but waiting for the frame the view
        needs to render (scripts and tests)."""
        frame = self.redraw(depsgraph, camera, size, view3d)
        if self._job is not None:
            self._job.future.exception()  # waits; the next redraw raises what it raised
            frame = self.redraw(depsgraph, camera, size, view3d)
        return frame

    def redraw(self, depsgraph, camera, size, view3d=None):
        """A redraw on Blender's thread, which never waits for a render: the frame the GL
        thread finished is taken, and the next one the view needs starts while none is
        being made: a new frame when an edit is pending or the view, its size or the
        settings changed; while they stay, one more VPL set averaged in until the still
        view has `viewport_vpl_sets`. With viewport corrections on, the view is rendered at
        most `correction_viewport_width` wide, and corrected by what the Cycles samples of
        it brought (addon/viewport_corrections.py) instead of converging. Returns the
        frame to draw (None until the first is done)."""
        if self._job is not None:
            if not self._job.future.done():
                return self._shown[1] if self._shown is not None else None
            job, self._job = self._job, None
            self._finish(job, job.future.result())
            return self._corrected(depsgraph, camera)
        properties = depsgraph.scene.lpv_preview
        job = self._next_job(depsgraph, camera, self._view_size(properties, size), view3d, properties)
        if job is not None:
            job.future = self.gl.submit(self._render, job)
            self._job = job
            return self._shown[1] if self._shown is not None else None
        self.gl.call(self.overlays.update, self.pipeline, display_settings_from_properties(properties))
        return self._corrected(depsgraph, camera)

    @property
    def rendering(self):
        """Whether the GL thread makes a frame a later redraw takes."""
        return self._job is not None

    @property
    def frame_done(self):
        """Whether the frame the GL thread makes is done, for a redraw to take."""
        return self._job is not None and self._job.future.done()

    def _corrected(self, depsgraph, camera):
        """The frame shown, corrected toward Cycles while viewport corrections are on."""
        properties = depsgraph.scene.lpv_preview
        correction = correction_settings_from_properties(properties)
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
        if self._job is not None:
            self._job.future.cancel()
        self.gl.call(self.pipeline.release)
