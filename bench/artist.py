"""The artist-scene suite (demo/artist/) against Cycles' Combined: per scene, the mean
luminance ratio, HDR-FLIP and relMSE of one frame of ours, our converged frame, EEVEE and
Cycles at 1 sample with OpenImageDenoise, and the goals of issue 30 judged from them,
written as artist.json and artist.md.

Nothing here imports bpy: cli/bench_blender.py `bench_artist` renders the images and
hands them over. Our frame times on a GPU come from scripts/time_artist_scenes.py run
there on the exported suite (`--gpu-times`); without them the time goals are "not
measured". The goals are printed beside the figures, never tuned to.
"""
import json
from pathlib import Path

import numpy as np

from ..gpu.metrics import flip, luminance, relative_mse

CONVERGE_SETS = 16
"""VPL sets our converged frame averages."""
MEAN_TOLERANCE = 0.10
"""One frame's mean luminance within this share of Cycles'."""
CONVERGED_SECONDS = 0.5
"""A converged frame counts only if it takes at most this long on the GPU (the H100)."""
CONVERGED_FLIP_SHARE = 0.5
"""The converged frame's HDR-FLIP at most this share of EEVEE's."""
WORLD_MS = 2.0
"""The world's cost per 1080p frame on the GPU at most this."""

RENDERS = {"ours_one_frame": "ours, one frame", "ours_converged": "ours, converged",
           "eevee": "EEVEE (F12)", "cycles_denoised": "Cycles 1 spp + OIDN"}
"""The renders each scene compares with Cycles' Combined, and their labels."""


def image_figures(test, reference):
    """Mean luminance ratio (test over reference), mean HDR-FLIP and relMSE of an image
    against Cycles' Combined; the ratio and HDR-FLIP are None for a black reference."""
    reference_mean = float(np.mean(luminance(reference)))
    lit = reference_mean > 0.0
    return {"mean_ratio": float(np.mean(luminance(test))) / reference_mean if lit else None,
            "flip": flip(test, reference)[0] if lit else None, "relative_mse": relative_mse(test, reference)}


def render_row(image, reference, seconds, settings):
    """A render's figures against the reference, its wall seconds here and how it was made."""
    return {"figures": image_figures(image, reference), "seconds": seconds, "settings": settings}


def missing_row(reason):
    """A render that could not be made: why, in the LPVError's sentence."""
    return {"figures": None, "missing": reason}


def _figure(scene, render, name):
    row = scene["renders"].get(render) or {}
    return (row.get("figures") or {}).get(name)


def scene_goals(scene, gpu_times=None):
    """Issue 30's goals for one scene: True (met), False (not met) or None (not measured:
    no GPU timings, or the figure is undefined). `gpu_times` is that scene's entry of
    scripts/time_artist_scenes.py's JSON."""
    ratio = _figure(scene, "ours_one_frame", "mean_ratio")
    one, converged, eevee = (_figure(scene, render, "flip") for render in ("ours_one_frame", "ours_converged", "eevee"))
    missing_ours = "missing" in scene["renders"]["ours_one_frame"]
    goals = {"one_frame_mean": False if missing_ours else (None if ratio is None else abs(ratio - 1) <= MEAN_TOLERANCE),
             "one_frame_flip_below_eevee": False if missing_ours else
             (None if one is None or eevee is None else one < eevee),
             "converged_flip_half_eevee": False if missing_ours else
             (None if converged is None or eevee is None else converged <= CONVERGED_FLIP_SHARE * eevee),
             "converged_seconds": None, "world_ms": None}
    if gpu_times:
        if gpu_times.get("converged_ms") is not None:
            goals["converged_seconds"] = gpu_times["converged_ms"]["median"] <= CONVERGED_SECONDS * 1000
        if gpu_times.get("world_ms") is not None:
            goals["world_ms"] = gpu_times["world_ms"] <= WORLD_MS
    return goals


GOAL_TEXT = {"one_frame_mean": f"one frame: mean within ±{MEAN_TOLERANCE:.0%} of Cycles'",
             "one_frame_flip_below_eevee": "one frame: HDR-FLIP below EEVEE's",
             "converged_flip_half_eevee": f"converged: HDR-FLIP at most {CONVERGED_FLIP_SHARE:g} × EEVEE's",
             "converged_seconds": f"converged frame at most {CONVERGED_SECONDS:g} s on the GPU",
             "world_ms": f"the world at most {WORLD_MS:g} ms a 1080p frame on the GPU"}


def goal_text(value):
    return {True: "met", False: "not met", None: "not measured"}[value]


def read_gpu_times(path):
    """scripts/time_artist_scenes.py's JSON: {"renderer", "width", "height", "scenes": {name: ...}}."""
    return json.loads(Path(path).read_text())


def write_artist_report(report, out):
    """artist.json and artist.md in the folder `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "artist.json").write_text(json.dumps(report, indent=1))
    (out / "artist.md").write_text(artist_markdown(report))
    return {"out": str(out), "scenes": [scene["name"] for scene in report["scenes"]],
            "goals_met": sum(v is True for scene in report["scenes"] for v in scene["goals"].values()),
            "goals": sum(len(scene["goals"]) for scene in report["scenes"])}


def _spread(timed):
    """A median with its least and most, in ms."""
    return f"{timed['median']:.2f} ms ({timed['min']:.2f}-{timed['max']:.2f})"


def _cell(value, spec):
    return "–" if value is None else format(value, spec)


def artist_markdown(report):
    """A table per scene (each render's figures against Cycles' Combined), its goals, and
    how the figures were made."""
    width, height = report["resolution"]
    lines = [f"Against Cycles' Combined at {report['cycles_samples']} samples (the scene's own settings otherwise), "
             f"{width}×{height}; ours on {report['renderer']}, {report['machine']}, converged over "
             f"{report['converge_sets']} VPL sets.", ""]
    gpu = report.get("gpu_times")
    for scene in report["scenes"]:
        lines += [f"### {scene['name']}", "",
                  "| render | mean ratio | HDR-FLIP | relMSE | seconds here |", "|---|---:|---:|---:|---:|"]
        for key, label in RENDERS.items():
            row = scene["renders"][key]
            if "missing" in row:
                lines.append(f"| {label} | – | – | – | not rendered: {row['missing']} |")
                continue
            figures = row["figures"]
            lines.append(f"| {label} | {_cell(figures['mean_ratio'], '.3f')} | {_cell(figures['flip'], '.4f')} | "
                         f"{_cell(figures['relative_mse'], '.4f')} | {row['seconds']:.2f} |")
        times = (gpu or {}).get("scenes", {}).get(scene["name"])
        if times:
            lines += ["", f"On {gpu['renderer']} at {gpu['width']}×{gpu['height']}: one frame "
                          f"{_spread(times['one_frame_ms'])}, converged ({times['converge_sets']} VPL sets) "
                          f"{_spread(times['converged_ms'])}, the world "
                          f"{_cell(times.get('world_ms'), '.2f')} ms (median of {times['frames']})."]
        lines += [""] + [f"- {GOAL_TEXT[goal]}: **{goal_text(value)}**" for goal, value in scene["goals"].items()]
        lines.append("")
    lines.append(f"Command: `{report['command']}`")
    return "\n".join(lines) + "\n"
