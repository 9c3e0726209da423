"""Rendering a Blender scene outside the RenderEngine, for the command line: one frame to
a multi-layer EXR, tone-mapped PNGs and stats.json, or an animation to one EXR a frame.
"""
import json
import os
import sys
import time

import bpy

from ..gpu.errors import LPVError
from ..gpu.image_io import write_exr, write_png
from ..gpu.pipeline import Pipeline, render_once
from .render_scene import scene_to_render


def open_blend(path):
    """Open the .blend file `path` in place of the current one, or one clear error."""
    if not os.path.isfile(path):
        raise LPVError(f"There is no file '{path}'; give the path of a .blend file.")
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path))
    except RuntimeError as error:
        raise LPVError(f"Blender cannot open '{path}' ({str(error).strip()}); check that it is a .blend file.")
    return bpy.context.scene


def write_outputs(frame, out_dir, extra_stats):
    """passes.exr (every pass of the frame), PNGs of combined and indirect, stats.json."""
    write_exr(os.path.join(out_dir, "passes.exr"), frame.passes)
    write_png(os.path.join(out_dir, "combined.png"), frame.passes["combined"])
    write_png(os.path.join(out_dir, "indirect.png"), frame.passes["indirect"])
    stats = {**extra_stats, **frame.stats}
    with open(os.path.join(out_dir, "stats.json"), "w") as handle:
        json.dump(stats, handle, indent=2)
    return stats


def render_to_files(bpy_scene, settings, passes, out_dir, extra_stats):
    """Render `passes` of what F12 shows of `bpy_scene` with `settings` and write them to
    `out_dir`; returns the statistics written."""
    start = time.perf_counter()
    scene = scene_to_render(bpy_scene, (settings.width, settings.height))
    extract_ms = (time.perf_counter() - start) * 1000
    frame = render_once(scene, settings, passes=passes)
    return write_outputs(frame, out_dir, {**extra_stats, "extract_ms": extract_ms})


def frame_path(out_dir, frame):
    return os.path.join(out_dir, f"frame_{frame:04d}.exr")


def write_frame(path, passes):
    """The frame's EXR under a temporary name, renamed when complete, so an interrupted
    frame is never taken for a finished one; the temporary file is removed when the
    writing fails or Ctrl-C stops it."""
    partial = path + ".partial.exr"
    try:
        write_exr(partial, passes)
        os.replace(partial, path)
    finally:
        if os.path.exists(partial):
            os.remove(partial)


def render_animation(bpy_scene, frames, settings, passes, out_dir, overwrite=False):
    """One EXR per frame of `frames` (a range) in `out_dir`, with a progress bar.

    Frames whose EXR exists are skipped unless `overwrite`, so a rerun resumes where an
    interrupted one stopped (`write_frame` never leaves a half-written frame).
    """
    todo = [f for f in frames if overwrite or not os.path.exists(frame_path(out_dir, f))]
    pipeline = Pipeline(settings)
    timings = []
    try:
        for done, frame in enumerate(todo):
            started = time.perf_counter()
            bpy_scene.frame_set(frame)
            scene = scene_to_render(bpy_scene, (settings.width, settings.height))
            result = pipeline.render(scene, passes=passes)
            write_frame(frame_path(out_dir, frame), result.passes)
            timings.append(time.perf_counter() - started)
            print_progress(done + 1, len(todo), frame, timings)
    finally:
        pipeline.release()
    return {"out": os.path.abspath(out_dir), "frames": [frames.start, frames[-1]], "rendered": len(todo),
            "skipped": len(frames) - len(todo), "seconds_per_frame": sum(timings) / len(timings) if timings else 0.0}


def print_progress(done, total, frame, timings, width=30):
    filled = width * done // total
    left = (total - done) * sum(timings) / len(timings)
    print(f"\rframe {frame} [{'#' * filled}{'.' * (width - filled)}] {done}/{total}, {left:.0f} s left",
          end="\n" if done == total else "", file=sys.stderr, flush=True)
