"""Corrections in the viewport (issue 18): while the view rests, Cycles samples of it
stream in from local sample workers and each redraw shows the preview corrected by what
has come; a camera move keeps the corrections that still apply; an edit of the scene
starts them again on a fresh copy of it once the edits stop. The view is rendered at most
`correction_viewport_width` pixels wide while corrections are on (Cycles' samples are
the cost), and drawn over the whole region.

A view rests when a redraw shows the same frame as the one before: only then is its
G-buffer read and a request sent, so orbiting costs nothing and leaves the layers of the
views that rested. Nothing here draws: it fills the session's display rows, so it runs in
background mode.
"""
import os
import time
from dataclasses import replace

import numpy as np

from ..corrections.corrector import Corrector
from ..corrections.sample_request import check_projection
from ..corrections.sample_workers import SampleWorkers
from ..gpu.errors import LPVError
from ..gpu.temporary_folders import make_temporary_folder, remove_temporary_folder
from .corrected_render import write_scene
from .sample_renderer import open_sample_renderer

REBUILD_SECONDS = 0.25
"""A still view's corrected frame is rebuilt at most this often (the rebuild costs CPU the
workers could use); a moved or edited view is looked at again after as long."""
COPIES_KEPT = 2
"""Scene copies kept: the one the workers open now and the one before (a request may
still be reading it)."""


def corrected_size(size, width):
    """The (width, height) a view of `size` is rendered at with corrections of at most `width` pixels."""
    if size[0] <= width:
        return size
    return width, max(1, round(size[1] * width / size[0]))


class ViewportCorrections:
    """One viewport's workers, corrections and the frame they correct; the G-buffer is
    read on `gl`, the GL thread that owns the pipeline (gpu/gl_thread.py)."""

    def __init__(self, gl):
        self.gl = gl
        self.workers = self.corrector = self.folder = None
        self.worker_count = None
        self.copies = []  # the scene copies written, newest last
        self.stale = False  # the scene was edited since its copy
        self.shown = self.rested = None  # (view key, frame) drawn last, and where the corrector rests
        self.preview = None  # the shown frame's own image, before any correction (top row first)
        self.last = None  # the last corrected frame
        self.rebuilt, self.received = 0.0, 0
        self.problem = None  # (why the view is not corrected in one sentence, the view and edit it holds for)

    @property
    def streaming(self):
        """Whether a later redraw may show more: samples to come, a view to rest, edits to catch up with."""
        return self.problem is None and self.shown is not None and (
            self.stale or not self._same(self.rested, self.shown)
            or (self.corrector is not None and bool(self.corrector.in_flight)))

    @staticmethod
    def _same(one, other):
        return one is not None and other is not None and one[0] == other[0] and one[1] is other[1]

    def show(self, bpy_scene, frame, scene, pipeline, camera, display, workers, edited):
        """Correct `frame` (a viewport Frame of `scene`, its combined image in `display`'s
        rows, `camera` the 3D view's) with what has come, from `workers` local workers;
        `edited`: the scene changed since the last redraw. Returns the corrections'
        statistics (and `correction_problem`, a sentence, while the view is not corrected)."""
        height, width = frame.display.shape[:2]
        key = f"{camera.key()}:{width}x{height}"
        if edited:
            self.stale = True
            if self.corrector is not None:
                self.corrector.cancel()
        if self.problem is not None and self.problem[1:] != (key, self.stale, workers):
            self.problem = None  # its cause may have gone: try again
        if self.problem is None:
            try:
                self._correct(bpy_scene, frame, scene, pipeline, camera, display, workers, key, edited)
            except LPVError as error:
                self.problem = (str(error), key, self.stale, workers)
                if self.corrector is not None:
                    self.corrector.cancel()
        stats = self.corrector.stats(self.last) if self.corrector is not None else {}
        return {**stats, "correction_problem": self.problem[0]} if self.problem else stats

    def _correct(self, bpy_scene, frame, scene, pipeline, camera, display, workers, key, edited):
        width, height = frame.display.shape[1], frame.display.shape[0]
        projection = tuple(map(tuple, camera.projection))
        check_projection(projection, (width, height))  # before any work
        if bpy_scene.camera is None:
            raise LPVError("The scene has no camera, which Cycles renders from; add one to correct the view.")
        if not self._same((key, frame), self.shown):  # moved or edited: shown as it is until it rests
            self.shown = (key, frame)
            self.preview = np.ascontiguousarray(frame.display[::-1, :, :3])
            return
        if edited:
            return  # edits go on: nothing asked of the old copy, none written yet
        if self.corrector is None or self.worker_count != workers or self.stale:
            self._start(bpy_scene, workers)
        if not self._same(self.rested, self.shown):
            self.rested = self.shown
            settings = replace(pipeline.settings, width=1, height=1)  # what the preview depends on but the size
            self._write(self.corrector.rest(key, scene.camera, tuple(map(tuple, np.linalg.inv(camera.view))),
                                            self.preview, self.gl.call(pipeline.read_gbuffer, scene), projection, settings), frame,
                        display)
            return
        self.corrector.receive(timeout=0)
        if self.corrector.samples_received > self.received and time.perf_counter() - self.rebuilt >= REBUILD_SECONDS:
            self._write(self.corrector.frame(), frame, display)

    def _start(self, bpy_scene, workers):
        """Workers (started again for another count) on a copy of `bpy_scene` as it is now;
        the corrections start empty."""
        if self.workers is None or self.worker_count != workers:
            self.stop()
            self.folder = make_temporary_folder("lpv_viewport_corrections_")
            try:
                self.workers = SampleWorkers(self._copy(bpy_scene), open_sample_renderer, workers=workers)
            except LPVError:
                self.stop()
                raise
            self.worker_count = workers
        else:
            self.corrector.cancel()
            self.workers.blend_path = self._copy(bpy_scene)  # each worker opens it with its next request
        self.corrector = Corrector(self.workers)
        self.stale, self.rested, self.last, self.received = False, None, None, 0

    def _copy(self, bpy_scene):
        path = os.path.join(self.folder, f"scene_{len(self.copies) + 1}.blend")
        write_scene(bpy_scene, path)
        self.copies.append(path)
        for old in self.copies[:-COPIES_KEPT]:
            if os.path.exists(old):
                os.remove(old)
        return path

    def _write(self, reconstruction, frame, display):
        frame.display[::-1, :, :3] = reconstruction.image
        display.fresh = True
        self.last, self.rebuilt, self.received = reconstruction, time.perf_counter(), self.corrector.samples_received

    def stop(self):
        """Close the workers and remove the scene copies."""
        if self.workers is not None:
            self.corrector.cancel()
            self.workers.close()
        if self.folder is not None:
            remove_temporary_folder(self.folder)
        self.workers = self.corrector = self.folder = self.worker_count = None
        self.copies, self.shown, self.rested, self.last, self.problem = [], None, None, None, None
