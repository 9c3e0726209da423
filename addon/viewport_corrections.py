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
import shutil
import tempfile
import time

import numpy as np

from ..gpu.errors import LPVError
from ..sample_tasks import check_projection
from .corrective import Corrector, write_scene
from .sample_workers import SampleWorkers

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
    """One viewport's workers, corrections and the frame they correct."""

    def __init__(self):
        self.workers = self.corrector = self.folder = None
        self.worker_count = None
        self.copies = []  # the scene copies written, newest last
        self.stale = False  # the scene was edited since its copy
        self.shown = self.rested = None  # (view key, frame) drawn last, and where the corrector rests
        self.last = None  # the last corrected frame
        self.rebuilt, self.received = 0.0, 0
        self.problem = None  # why the view is not corrected, in one sentence

    @property
    def streaming(self):
        """Whether a later redraw may show more: samples to come, a view to rest, edits to catch up with."""
        return self.workers is not None and self.problem is None and (self.stale or self.rested != self.shown
                                                                      or bool(self.corrector.in_flight))

    def show(self, bpy_scene, frame, scene, pipeline, camera, display, workers, edited):
        """Correct `frame` (a viewport Frame of `scene`, its combined image in `display`'s
        rows, `camera` the 3D view's) with what has come, from `workers` local workers;
        `edited`: the scene changed since the last redraw. Returns the corrections'
        statistics (and `correction_problem`, a sentence, when the view is not corrected)."""
        if edited:
            self.stale = True
            if self.corrector is not None:
                self.corrector.cancel()
        height, width = frame.display.shape[:2]
        key = f"{camera.key()}:{width}x{height}"
        projection = tuple(map(tuple, camera.projection))
        try:
            if self.stale and not edited or self.worker_count != workers:
                self._start(bpy_scene, workers)
            self.problem = None
            check_projection(projection, (width, height))
            if (key, frame) != self.shown:  # moved (or edited): shown as it is until it rests
                self.shown = (key, frame)
            elif self.rested != self.shown:
                self.rested = self.shown
                preview = np.ascontiguousarray(frame.display[::-1, :, :3])
                self._write(self.corrector.rest(key, scene.camera, tuple(map(tuple, np.linalg.inv(camera.view))),
                                                preview, pipeline.read_guide(scene), projection), frame, display)
                self.corrector.fill()
            else:
                self.corrector.receive(timeout=0)
                if (self.corrector.samples_received > self.received
                        and time.perf_counter() - self.rebuilt >= REBUILD_SECONDS):
                    self._write(self.corrector.frame(), frame, display)
        except LPVError as error:
            self.problem = str(error)
            if self.corrector is not None:
                self.corrector.cancel()
        stats = self.corrector.stats(self.last) if self.corrector is not None else {}
        return {**stats, "correction_problem": self.problem} if self.problem else stats

    def _start(self, bpy_scene, workers):
        """Workers (started again for another count) on a copy of `bpy_scene` as it is now;
        the corrections start empty."""
        if self.workers is None or self.worker_count != workers:
            self.stop()
            self.folder = tempfile.mkdtemp(prefix="lpv_viewport_corrections_")
            self.worker_count = workers
            self.workers = SampleWorkers(self._copy(bpy_scene), workers=workers)
        else:
            self.corrector.cancel()
            self.workers.blend_path = self._copy(bpy_scene)  # each worker opens it with its next request
        self.corrector = Corrector(self.workers)
        self.stale, self.shown, self.rested, self.last, self.received = False, None, None, None, 0

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
            shutil.rmtree(self.folder, ignore_errors=True)
        self.workers = self.corrector = self.folder = self.worker_count = None
        self.copies, self.shown, self.rested, self.last, self.problem = [], None, None, None, None
