"""What the corrections' benchmark (bench/corrections.py) measures, rendered with bpy: a
demo scene's views along a camera path with their Cycles references and previews, and
the timelines of Cycles progressive, Cycles denoised and the corrected preview, each a
list of (wall seconds, image shown from then on)."""
import math
import time
from contextlib import contextmanager
from dataclasses import dataclass, field

import bpy
import numpy as np
from mathutils import Matrix

from ..addon.cycles_reference import ReferenceCache, cycles_reference
from ..addon.cycles_samples import SampleRenderer
from ..addon.render_scene import scene_and_signature_to_render
from ..addon.sample_renderer import open_sample_renderer
from ..corrections.corrector import Corrector
from ..corrections.sample_request import SampleRequest
from ..corrections.sample_workers import SampleWorkers
from ..gpu.pipeline import Pipeline

TIMELINE_SEED = 100
"""The Cycles timelines' seeds count up from here, apart from the references' and the corrections'."""


@dataclass
class View:
    """One camera of the path: its turn, world matrix, gpu Scene, reference and preview."""

    degrees: float
    camera: tuple
    scene: object
    reference: np.ndarray
    preview: np.ndarray = None
    gbuffer: object = None
    preview_seconds: float = 0.0
    key: str = field(default="")


def turned(matrix_world, degrees):
    """A camera world matrix turned by `degrees` about the world's vertical axis through the camera."""
    location = matrix_world.to_translation()
    turn = Matrix.Translation(location) @ Matrix.Rotation(math.radians(degrees), 4, "Z") @ Matrix.Translation(-location)
    return turn @ matrix_world


@contextmanager
def camera_at(bpy_scene, matrix):
    """The scene's camera at `matrix` for the while."""
    camera = bpy_scene.camera
    saved = camera.matrix_world.copy()
    camera.matrix_world = matrix
    try:
        yield
    finally:
        camera.matrix_world = saved


def path_views(name, build, resolution, degrees, reference_samples, blend_path, log=print):
    """Build the scene `name` (`build()` makes it in the open file and returns it), save it
    at `blend_path` and return its View for every turn in `degrees`, their references
    rendered (or cached)."""
    bpy_scene = build()
    bpy.ops.wm.save_as_mainfile(filepath=blend_path)
    start = bpy_scene.camera.matrix_world.copy()
    views = []
    for turn in degrees:
        matrix = turned(start, turn)
        with camera_at(bpy_scene, matrix):
            scene, signature = scene_and_signature_to_render(bpy_scene, resolution)
            began = time.perf_counter()
            reference = cycles_reference(bpy_scene, "full_gi", reference_samples, 0, resolution, ReferenceCache(),
                                         signature)
            log(f"{name} {turn:g}°: reference in {time.perf_counter() - began:.1f} s")
        views.append(View(turn, tuple(map(tuple, matrix)), scene, reference.combined_pass, key=scene.camera.key()))
    return views


def render_previews(views, settings):
    """Each view's preview and Guide, and its render time: the first a whole frame of a
    fresh pipeline (its shaders compiled before), the others a camera move of it."""
    Pipeline(settings).release()  # nothing cached but the process's compiled shaders
    warm = Pipeline(settings)
    warm.render_converged(views[0].scene)
    warm.release()
    pipeline = Pipeline(settings)
    try:
        for view in views:
            began = time.perf_counter()
            frame = pipeline.render_converged(view.scene)
            view.preview_seconds = time.perf_counter() - began
            view.preview, view.gbuffer = frame.passes["combined"], pipeline.read_gbuffer(view.scene)
    finally:
        pipeline.release()


def cycles_progressive(renderer, view, seconds, threads, denoise=False):
    """Cycles on `threads` threads over the whole view for `seconds`. Undenoised: steps of
    1, 1, 2, 4, ... samples whose running mean is shown after each (as its viewport
    refines), the last cut to what its pace fits in the time left; denoised: 1, 2, 4, ...
    samples each rendered anew and denoised, while the next is expected to fit. Returns
    the timeline and the samples of its last image."""
    height, width = view.reference.shape[:2]
    timeline, total, samples, spent, seed = [], 0.0, 0, 0.0, TIMELINE_SEED
    step = 1
    while spent < seconds:
        result = renderer.render(SampleRequest((0, 0, width, height), (width, height), step, seed, view.camera,
                                               denoise=denoise), threads)
        seed += 1
        image = result.passes["Combined"]
        if denoise:
            if timeline and result.seconds > seconds:
                break
            timeline.append((result.seconds, image))
            samples, step = step, 2 * step
            if 2 * result.seconds > seconds:
                break
            continue
        spent += result.seconds
        total, samples = total + image.astype(np.float64) * step, samples + step
        timeline.append((spent, (total / samples).astype(np.float32)))
        step = max(1, min(samples, int((seconds - spent) * step / result.seconds)))
    return timeline, samples


def corrected(workers, view, seconds, frames_at=(), corrector=None):
    """The preview of the View `view` corrected for `seconds` of wall time counted from
    the start of its preview's render (`frames_at`: when frames are rebuilt and shown, in
    seconds after the preview is shown, as a viewport redraws from then on whatever the
    preview took); with `corrector`, one that holds earlier views' corrections. Returns
    the timeline and the Corrector."""
    corrector = corrector or Corrector(workers)
    began = time.perf_counter()
    first = corrector.rest(view.key, view.scene.camera, view.camera, view.preview, view.gbuffer)
    offset = view.preview_seconds + time.perf_counter() - began
    timeline = [(view.preview_seconds, view.preview), (offset, first.image)]
    frames = [view.preview_seconds + t - offset for t in frames_at if view.preview_seconds + t > offset]
    for at, reconstruction in corrector.run(seconds - offset, frames):
        timeline.append((offset + at, reconstruction.image))
    return timeline, corrector


def measure_scene(name, build, settings, reference_samples, blend_path, cores, timing, log=print):
    """Every timeline of the benchmark on the scene `name` that `build()` makes, its
    previews rendered with `settings` (their size the benchmark's), `timing` giving the
    camera path's turns and the seconds of each run (bench/corrections.py TIMING):
    {"views", "still" {method: timeline}, "cycles_samples", "turn" (the first corrected
    image after turning to the path's last view), "path" [{method: timeline} per view]},
    Cycles and the workers on `cores` cores."""
    resolution = (settings.width, settings.height)
    views = path_views(name, build, resolution, timing["path_degrees"], reference_samples, blend_path, log)
    render_previews(views, settings)
    renderer = SampleRenderer(blend_path)
    try:
        renderer.render(SampleRequest((0, 0, 1, 1), resolution, 1, 1), cores)  # Cycles' scene loaded, as the workers'
        still, samples = cycles_progressive(renderer, views[0], timing["still_seconds"], cores)
        denoised, _ = cycles_progressive(renderer, views[0], timing["denoised_seconds"], cores, denoise=True)
        path = [{"cycles": cycles_progressive(renderer, view, timing["frame_seconds"], cores)[0],
                 "cycles_denoised": cycles_progressive(renderer, view, timing["frame_seconds"], cores, denoise=True)[0]}
                for view in views]
    finally:
        renderer.close()
    log(f"{name}: Cycles timelines done ({samples} samples in {still[-1][0]:.1f} s)")
    with SampleWorkers(blend_path, open_sample_renderer, workers=cores) as workers:
        workers.open_everywhere()
        workers.settle(resolution)  # every worker's scene loaded
        ours, corrector = corrected(workers, views[0], timing["still_seconds"], timing["frames_at"])
        corrector.cancel()
        turn = corrector.rest(views[-1].key, views[-1].scene.camera, views[-1].camera, views[-1].preview,
                              views[-1].gbuffer).image
        corrector.cancel()  # the turned view's requests: not the path's
        log(f"{name}: corrected still done ({corrector.samples_received} samples)")
        corrector = None
        for view, frame in zip(views, path):
            workers.settle(resolution)  # the last run's cancelled requests, rendered to their end
            frame["corrected"], corrector = corrected(workers, view, timing["frame_seconds"], (), corrector)
            corrector.cancel()
    return {"views": views, "still": {"cycles": still, "cycles_denoised": denoised, "corrected": ours},
            "cycles_samples": samples, "turn": turn, "path": path}
