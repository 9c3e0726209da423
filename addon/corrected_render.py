"""Corrections toward Cycles on the Blender side: the .blend the sample workers open (the
user's file, or the scene as it is written to a temporary copy), the workers started for
a render, and a frame of ours corrected by them (corrections/corrector.py)."""
import os
from contextlib import contextmanager

import bpy

from ..corrections.corrector import check_corrections_fit, correct, rendered_passes
from ..corrections.sample_workers import SampleWorkers
from ..gpu.errors import LPVError, first_line
from ..gpu.pipeline import Pipeline
from ..gpu.temporary_folders import temporary_folder
from .sample_renderer import open_sample_renderer


def write_scene(bpy_scene, path):
    """Write `bpy_scene` and what it uses to the .blend `path` as it is now, unsaved edits
    included, without touching the open file (no operator: callable while drawing)."""
    try:
        bpy.data.libraries.write(path, {bpy_scene}, path_remap="ABSOLUTE", fake_user=True)
    except (OSError, RuntimeError) as error:
        raise LPVError(f"Cannot write the scene's copy for the Cycles sample workers to '{path}' "
                       f"({first_line(error)}); free some disk space or set TMPDIR.") from None


@contextmanager
def blend_for_workers(bpy_scene, path=None, remote=False):
    """The .blend the workers open: `path`, the file `bpy_scene` was opened from and not
    edited since (the command line's `render`), else `bpy_scene` written to a temporary
    folder for the while (for local workers only: a `remote` cluster's cannot read it).
    Blender as a module counts every file as edited (`bpy.data.is_dirty`), so the caller
    vouches for it."""
    if path is not None and os.path.abspath(bpy.data.filepath) == os.path.abspath(path):
        yield path
        return
    if remote:
        raise LPVError("A remote Dask cluster's workers open the .blend file itself; render a saved .blend file "
                       "that they can read at the same path.")
    with temporary_folder("lpv_corrections_") as folder:
        copy = os.path.join(folder, "corrections.blend")
        write_scene(bpy_scene, copy)
        yield copy


@contextmanager
def workers_for(bpy_scene, correction, resolution, blend_path=None, scheduler=None):
    """The SampleWorkers of `correction` (CorrectionSettings): `correction_workers` local
    ones, or the Dask cluster at `scheduler` (its TLS certificates from Dask's
    configuration), every one with the .blend of `bpy_scene` open (`blend_for_workers`).
    They start first: a cluster that cannot be reached, or corrections of a `resolution`
    (width, height) that would not fit in memory, stop a render before its work."""
    check_corrections_fit(*resolution)
    with blend_for_workers(bpy_scene, blend_path, remote=scheduler is not None) as path:
        workers = None if scheduler else correction.correction_workers
        with SampleWorkers(path, open_sample_renderer, workers=workers, scheduler=scheduler) as workers:
            workers.open_everywhere()
            yield workers


def corrected_frame(bpy_scene, scene, settings, passes, correction, blend_path=None, scheduler=None):
    """A frame of the gpu Scene `scene` (extracted from `bpy_scene` at its current frame)
    corrected toward Cycles for `correction.correct_seconds` by the workers of
    `workers_for`."""
    with workers_for(bpy_scene, correction, (settings.width, settings.height), blend_path, scheduler) as workers:
        pipeline = Pipeline(settings)
        try:
            frame = pipeline.render_converged(scene, passes=rendered_passes(passes)[0])
            correct(workers, pipeline, scene, frame, correction.correct_seconds, bpy_scene.frame_current)
            return frame
        finally:
            pipeline.release()
