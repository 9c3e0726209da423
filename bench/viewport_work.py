"""The viewport's own work: the scenes of a run of redraws after one kind of edit, and the
wall-clock time of each redraw as a viewport makes it (one VPL set, the combined image
read into a float buffer). scripts/time_viewport_work.py tables it per scene and preset;
the sweeps time each point's light edits and camera moves with it, which
`choose_presets` picks the presets by (bench/sweep_report.py)."""
import dataclasses
import statistics
import time

import numpy as np

from ..gpu.scene_edits import camera_path
from ..gpu.shade import DISPLAY_CHANNELS
from .timing import THROUGHPUT_WARM_UP_SECONDS

TURN_DEGREES = 0.25
EDITS = ("camera move", "light edit", "material edit")


def edited_frames(scene, edit, frames):
    """The scenes of `frames` redraws after edits of kind `edit` (EDITS), the first one's
    before it. As the add-on's are, each is the last one with a part replaced: what it
    keeps keeps its content keys (gpu/scene.py), made once here.
    - camera move: the camera turned TURN_DEGREES a redraw (the grids stay);
    - light edit: the first lamp's power 1 % up and down in turn (its maps are redone);
    - material edit: every surface's albedo 1 % up and down in turn (the mesh is made again)."""
    scene.sanitize()
    scene.geometry_key(), scene.point_emitters_key(), scene.bounds()
    if edit == "camera move":
        return [dataclasses.replace(scene, camera=camera) for camera in
                camera_path(scene.camera, frames + 1, degrees=TURN_DEGREES * frames / 2)]
    if edit == "light edit":
        first = scene.lights[0]
        return [dataclasses.replace(scene, lights=[dataclasses.replace(first, power=first.power * (1.01 if i % 2 else 1.0)),
                                                   *scene.lights[1:]]) for i in range(frames + 1)]
    if edit == "material edit":
        return [dataclasses.replace(scene, albedo=np.ascontiguousarray(scene.albedo * np.float32(0.99 if i % 2 else 1.0)),
                                    _content_keys=None) for i in range(frames + 1)]
    raise ValueError(edit)


def display_buffer(settings):
    """A float buffer the size of the settings' image, as a viewport reads its frames into."""
    return np.empty(settings.width * settings.height * DISPLAY_CHANNELS, dtype=np.float32)


def timed_redraws(pipeline, scenes, display):
    """Wall-clock milliseconds of each redraw of `scenes` after the first (median, least,
    most) and the median of each stage over 0.05 ms. The first is drawn for
    THROUGHPUT_WARM_UP_SECONDS first: the GPU's clocks drop while the CPU builds the next
    case's scenes (bench/timing.py)."""
    warm_up_until = time.perf_counter() + THROUGHPUT_WARM_UP_SECONDS
    while True:
        pipeline.invalidate()
        pipeline.render(scenes[0], passes=(), display_into=display)
        if time.perf_counter() >= warm_up_until:
            break
    times, stages = [], []
    for scene in scenes[1:]:
        began = time.perf_counter()
        frame = pipeline.render(scene, passes=(), display_into=display)
        times.append((time.perf_counter() - began) * 1000.0)
        stages.append({key: value for key, value in frame.stats.items() if key.endswith("_ms") and key != "total_ms"})
    names = sorted({key for s in stages for key in s})
    medians = {key: statistics.median(s.get(key, 0.0) for s in stages) for key in names}
    return {"frame_ms": round(statistics.median(times), 2), "least_ms": round(min(times), 2),
            "most_ms": round(max(times), 2),
            "stages": {key: round(value, 2) for key, value in medians.items() if value >= 0.05}}


SWEEP_REDRAWS = 8
"""Redraws a sweep times of each edit at each point (after half a second of warm-up)."""


def redraw_times(pipeline, scene, settings, redraws=SWEEP_REDRAWS):
    """The median wall-clock milliseconds of a camera move's redraw and of a light edit's
    (where the scene has lamps) at the settings' image size: `camera_move_ms`,
    `light_edit_ms`."""
    display = display_buffer(settings)
    times = {}
    for edit in ("camera move", "light edit") if scene.lights else ("camera move",):
        frames = edited_frames(scene, edit, redraws)
        times[edit.replace(" ", "_") + "_ms"] = timed_redraws(pipeline, frames, display)["frame_ms"]
    return times
