"""Corrections in the viewport (issue 18): while the view rests, Cycles samples of it
stream in from local sample workers and each redraw shows the preview corrected by what
has come; a camera move keeps the corrections that still apply; an edit of the scene
starts them again on a fresh copy of it. The view is rendered at most
`correction_viewport_width` pixels wide while corrections are on (Cycles' samples are
the cost), and drawn over the whole region.

Nothing here draws: it fills the session's display rows, so it runs in background mode.
"""
import os
import shutil
import tempfile
import time

import numpy as np

from .corrective import Corrector, write_scene
from .sample_workers import SampleWorkers

REBUILD_SECONDS = 0.25
"""A still view's corrected frame is rebuilt at most this often (the rebuild costs CPU the workers could use)."""


def corrected_size(size, width):
    """The (width, height) a view of `size` is rendered at with corrections of at most `width` pixels."""
    if size[0] <= width:
        return size
    return width, max(1, round(size[1] * width / size[0]))


class ViewportCorrections:
    """One viewport's workers, corrections and the preview they correct."""

    def __init__(self):
        self.workers = self.corrector = self.folder = None
        self.worker_count = None
        self.edits = 0  # scene copies written so far
        self.preview = None  # (view key, the preview, top row first)
        self.last = None  # the last corrected frame
        self.rebuilt = 0.0
        self.received = 0

    @property
    def streaming(self):
        """Whether samples may still come for the view at rest (redraw again)."""
        return self.corrector is not None and self.corrector.view_key is not None

    def start(self, bpy_scene, workers):
        """Workers (started again for another count) on a copy of `bpy_scene` as it is now;
        the corrections start empty."""
        if self.workers is None or self.worker_count != workers:
            self.stop()
            self.folder = tempfile.mkdtemp(prefix="lpv_viewport_corrections_")
            self.workers, self.worker_count = SampleWorkers(self._copy(bpy_scene), workers=workers), workers
        else:
            self.corrector.cancel()
            self.workers.blend_path = self._copy(bpy_scene)  # each worker opens it with its next request
        self.corrector = Corrector(self.workers)
        self.preview = None

    def _copy(self, bpy_scene):
        self.edits += 1
        path = os.path.join(self.folder, f"scene_{self.edits}.blend")
        write_scene(bpy_scene, path)
        return path

    def show(self, frame, scene, pipeline, camera, display):
        """Correct `frame` (a viewport Frame of `scene`, its combined image in `display`'s
        rows) with what has come: a new view or preview rests the corrector there, a still
        one is rebuilt when samples came and REBUILD_SECONDS passed. Returns the
        corrections' statistics."""
        key = scene.camera.key()
        rows = frame.display
        if self.preview is None or self.preview[0] != key or self.preview[1] is not frame:
            preview = np.ascontiguousarray(rows[::-1, :, :3])
            self.preview = (key, frame, preview)
            camera_matrix = tuple(map(tuple, np.linalg.inv(camera.view)))
            projection = tuple(map(tuple, camera.projection))
            self._write(self.corrector.rest(key, scene.camera, camera_matrix, preview, pipeline.read_guide(scene),
                                            projection), rows, display)
        else:
            self.corrector.receive(timeout=0)
            now = time.perf_counter()
            if self.corrector.samples_received > self.received and now - self.rebuilt >= REBUILD_SECONDS:
                self._write(self.corrector.frame(), rows, display)
        return self.corrector.stats(self.last)

    def _write(self, reconstruction, rows, display):
        rows[::-1, :, :3] = reconstruction.image
        display.fresh = True
        self.last, self.rebuilt, self.received = reconstruction, time.perf_counter(), self.corrector.samples_received

    def stop(self):
        """Close the workers and remove the scene copies."""
        if self.workers is not None:
            self.corrector.cancel()
            self.workers.close()
        if self.folder is not None:
            shutil.rmtree(self.folder, ignore_errors=True)
        self.workers = self.corrector = self.folder = self.preview = None
