"""Rendering a Blender scene outside the RenderEngine, for the command line: one frame to
a multi-layer EXR, PNGs through the scene's colour management (as F12 saves them) and
stats.json, or an animation to one EXR a frame.
"""
import json
import os
import sys
import time
from contextlib import nullcontext
from dataclasses import asdict

import bpy

from ..corrections.corrector import correct, rendered_passes
from ..gpu.errors import LPVError
from ..gpu.image_io import read_exr_metadata, write_exr, write_png
from ..gpu.pipeline import Pipeline, render_once
from .corrected_render import corrected_frame, workers_for
from .extract import check_camera, output_layout
from .frame_stats import missing_images_warning, renderer_warning
from .render_scene import scene_to_render
from .view_transform import scene_view_transform


def open_blend(path):
    """Open the .blend file `path` in place of the current one, or one clear error."""
    if not os.path.isfile(path):
        raise LPVError(f"There is no file '{path}'; give the path of a .blend file.")
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path))
    except RuntimeError as error:
        raise LPVError(f"Blender cannot open '{path}' ({str(error).strip()}); check that it is a .blend file.")
    return bpy.context.scene


RENDERER_ATTRIBUTE = "lpv_preview_renderer"
RENDERER_WARNING_ATTRIBUTE = "lpv_preview_renderer_warning"
"""The EXR header attributes naming the OpenGL renderer that made the frame and, for a
software rasterizer, warning of it (frame_stats.py `renderer_warning`)."""


def renderer_metadata(stats):
    """The EXR header attributes that name the renderer of a frame with these statistics."""
    warning = renderer_warning(stats)
    return {RENDERER_ATTRIBUTE: stats["renderer"], **({RENDERER_WARNING_ATTRIBUTE: warning} if warning else {})}


def write_outputs(frame, layout, out_dir, extra_stats, view_transform):
    """passes.exr (every pass of the frame, its renderer in the header), PNGs of combined
    and indirect through `view_transform` (gpu/colour_management.py), stats.json; the
    images as `layout` (gpu/output_layout.py) writes them."""
    images = layout.written(frame.passes, frame.coverage)
    write_exr(os.path.join(out_dir, "passes.exr"), images, renderer_metadata(frame.stats))
    write_png(os.path.join(out_dir, "combined.png"), images["combined"], view_transform)
    write_png(os.path.join(out_dir, "indirect.png"), images["indirect"], view_transform)
    warning, missing = renderer_warning(frame.stats), missing_images_warning(frame.stats)
    stats = {**extra_stats, **frame.stats, **({"renderer_warning": warning} if warning else {}),
             **({"missing_images_warning": missing} if missing else {})}
    with open(os.path.join(out_dir, "stats.json"), "w") as handle:
        json.dump(stats, handle, indent=2)
    return stats


def render_to_files(bpy_scene, settings, passes, out_dir, extra_stats, correction=None, blend_path=None,
                    scheduler=None):
    """Render `passes` of what F12 shows of `bpy_scene` with `settings` and write them to
    `out_dir`, the PNGs through its colour management; returns the statistics written. With `correction` (CorrectionSettings)
    asking for seconds, the combined image is corrected toward Cycles by sample workers
    opening `blend_path` (None: a copy of the scene as it is) on this machine, or on the
    Dask cluster at `scheduler`."""
    start = time.perf_counter()
    layout = checked_layout(bpy_scene, settings)
    scene = scene_to_render(bpy_scene, (settings.width, settings.height))
    extract_ms = (time.perf_counter() - start) * 1000
    if correction is not None and correction.correct_seconds > 0:
        frame = corrected_frame(bpy_scene, scene, settings, passes, correction, blend_path, scheduler)
    else:
        frame = render_once(scene, settings, passes=passes)
    return write_outputs(frame, layout, out_dir, {**extra_stats, "extract_ms": extract_ms},
                         scene_view_transform(bpy_scene))


def checked_layout(bpy_scene, settings):
    """What the render writes of a frame of `settings`' size (addon/extract.py
    output_layout), refused in one sentence when its region holds no pixel or its camera
    is panoramic (before any frame is read or rendered)."""
    check_camera(bpy_scene)
    layout = output_layout(bpy_scene, (settings.width, settings.height))
    if layout.empty:
        raise LPVError("The render region is narrower than a pixel; draw a larger one (Ctrl-B) or clear it "
                       "(Ctrl-Alt-B).")
    return layout


def frame_path(out_dir, frame):
    return os.path.join(out_dir, f"frame_{frame:04d}.exr")


FRAME_RECORD = "lpv_preview_frame"
"""The EXR header attribute in which each frame of an animation records what it was made
with (`frame_record`), so that a rerun knows which frames it can keep."""


def frame_record(settings, passes, correct_seconds=0.0, layout=None):
    """What a frame is made with: every setting (the image size among them), the passes,
    the seconds it was corrected toward Cycles, and what of it is written (its render
    region, Film Transparent)."""
    return {"settings": asdict(settings), "passes": list(passes), "correct_seconds": correct_seconds,
            "layout": asdict(layout) if layout is not None else None}


def recorded_frame(path):
    """The record in the frame `path`, or None when it has none or cannot be read."""
    try:
        return json.loads(read_exr_metadata(path, FRAME_RECORD) or "null")
    except ValueError:
        return None


def why_render_again(recorded, wanted):
    """Why a frame made with the record `recorded` is not the one `wanted` asks for, in a
    few words ("at another size (64×64)"), or None when it is."""
    if not isinstance(recorded, dict) or not isinstance(recorded.get("settings"), dict):
        return "with no record of its settings"
    old, new = recorded["settings"], wanted["settings"]
    if (old.get("width"), old.get("height")) != (new["width"], new["height"]):
        return f"at another size ({old.get('width')}×{old.get('height')})"
    changed = [name for name in new if old.get(name) != new[name]]
    if changed:
        return f"with other settings ({', '.join(changed)})"
    seconds = recorded.get("correct_seconds", 0.0)
    if seconds != wanted["correct_seconds"]:
        return f"corrected for another time ({seconds:g} s)" if seconds else "uncorrected"
    if json.loads(json.dumps(wanted["layout"])) != recorded.get("layout"):
        return "with another render region or transparency"
    return None if recorded.get("passes") == wanted["passes"] else "with other passes"


def write_frame(path, passes, record, metadata=None):
    """The frame's EXR, `record` (and `metadata`) in its header, under a temporary name and
    renamed when complete, so an interrupted frame is never taken for a finished one; the
    temporary file is removed when the writing fails or Ctrl-C stops it."""
    partial = path + ".partial.exr"
    try:
        write_exr(partial, passes, {**(metadata or {}), FRAME_RECORD: json.dumps(record, sort_keys=True)})
        os.replace(partial, path)
    finally:
        if os.path.exists(partial):
            os.remove(partial)


def render_animation(bpy_scene, frames, settings, passes, out_dir, overwrite=False, correction=None,
                     blend_path=None, scheduler=None):
    """One EXR per frame of `frames` (a range) in `out_dir`, with a progress bar; with
    `correction` (CorrectionSettings) asking for seconds, each frame's combined image is
    corrected toward Cycles for that long, as `render_to_files` corrects one, by workers
    started once for the whole animation.

    A frame whose EXR exists and was made with these settings, size, passes and
    correction is kept unless `overwrite`, so a rerun resumes where an interrupted one
    stopped (`write_frame` never leaves a half-written frame); one made otherwise is
    rendered again, and the statistics and a line on stderr say how many and why.
    """
    seconds = correction.correct_seconds if correction is not None else 0.0
    rendered, written = rendered_passes(passes) if seconds > 0 else (passes, passes)
    layout = checked_layout(bpy_scene, settings)
    record = frame_record(settings, written, seconds, layout)
    todo, again = [], {}
    for frame in frames:
        path = frame_path(out_dir, frame)
        if overwrite or not os.path.exists(path):
            todo.append(frame)
            continue
        reason = why_render_again(recorded_frame(path), record)
        if reason:
            todo.append(frame)
            again[reason] = again.get(reason, 0) + 1
    if again:
        made = ", ".join(f"{count} {reason}" for reason, count in again.items())
        print(f"lpv_preview: rendering again {sum(again.values())} frames already in '{out_dir}', made {made}.",
              file=sys.stderr, flush=True)
    timings, corrected, rebuild, missing = [], {}, None, None
    correcting = (workers_for(bpy_scene, correction, (settings.width, settings.height), blend_path, scheduler)
                  if seconds > 0 and todo else nullcontext())
    with correcting as workers:
        pipeline = Pipeline(settings)
        renderer = {"renderer": pipeline.glc.renderer, "software_renderer": pipeline.glc.is_software}
        try:
            for done, frame in enumerate(todo):
                started = time.perf_counter()
                bpy_scene.frame_set(frame)
                scene = scene_to_render(bpy_scene, (settings.width, settings.height))
                result = pipeline.render_converged(scene, passes=rendered)
                missing = missing or missing_images_warning(result.stats)
                if workers is not None:
                    corrected[frame] = correct(workers, pipeline, scene, result, seconds, frame, rebuild)
                    rebuild = corrected[frame]["correction_rebuild_seconds"]
                write_frame(frame_path(out_dir, frame), layout.written(result.passes, result.coverage), record,
                            renderer_metadata(result.stats))
                timings.append(time.perf_counter() - started)
                print_progress(done + 1, len(todo), frame, timings)
        finally:
            pipeline.release()
    return {"out": os.path.abspath(out_dir), "frames": [frames.start, frames[-1]], "rendered": len(todo),
            "skipped": len(frames) - len(todo), "rendered_again": again,
            "seconds_per_frame": sum(timings) / len(timings) if timings else 0.0, "corrections": corrected,
            **renderer, **({"missing_images_warning": missing} if missing else {})}



def print_progress(done, total, frame, timings, width=30):
    filled = width * done // total
    left = (total - done) * sum(timings) / len(timings)
    print(f"\rframe {frame} [{'#' * filled}{'.' * (width - filled)}] {done}/{total}, {left:.0f} s left",
          end="\n" if done == total else "", file=sys.stderr, flush=True)
