"""The corrections toward Cycles (issue 18) against Cycles itself, over wall time: error
against a high-sample full-GI reference for Cycles progressive (undenoised, and denoised
by OpenImageDenoise at each step as its viewport shows it) and for the preview corrected
by Cycles sample workers, all on the same CPU cores; for a still camera and along a short
camera path.

bpy lives with the caller, who hands in each method's timeline: (seconds, image) pairs,
an image being what the user sees from then on (`python -m lpv_preview bench
--corrections`, cli/correction_runs.py).
"""
import json
import math
from pathlib import Path

from ..gpu.errors import LPVError, first_line
from ..gpu.metrics import psnr, relative_mse
from .plots import pyplot, save

SCENES = {"cornell": (128, 128), "atrium": (160, 90), "city": (160, 90)}
"""The demo scenes lit by lamps and their image sizes (small: Cycles' reference and its
samples are the cost)."""
REFERENCE_SAMPLES = 4096
STILL_SECONDS = 60.0
DENOISED_SECONDS = 8.0
"""Denoised Cycles is rendered anew for each sample count (1, 2, 4, ...) while the next fits here."""
DENOISED_GOAL_SECONDS = 5.0
FRAMES_AT = (0.1, 0.2, 0.3, 0.4, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0)
"""When the corrected frame is rebuilt and measured: seconds after its preview is shown
(the same moments whether the preview took llvmpipe's second or the GPU's milliseconds)."""
PATH_DEGREES = (0.0, 2.5, 5.0)
"""The camera path: turns about the vertical axis through the camera, one frame each."""
FRAME_SECONDS = 2.0
"""Wall time every method gets for each frame of the path."""
TABLE_MOMENTS = (0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0, 60.0)
"""The report's columns: the error shown at these seconds."""
TIMING = {"path_degrees": PATH_DEGREES, "still_seconds": STILL_SECONDS, "denoised_seconds": DENOISED_SECONDS,
          "frame_seconds": FRAME_SECONDS, "frames_at": FRAMES_AT}
"""What the timelines' runs are given (cli/correction_runs.py measure_scene)."""
METHODS = ("cycles", "cycles_denoised", "corrected")
LABELS = {"cycles": "Cycles progressive", "cycles_denoised": "Cycles + OpenImageDenoise",
          "corrected": "preview + corrections"}


def read_gpu_previews(path):
    """{scene: seconds} of the previews timed on a GPU (scripts/time_previews.py's JSON), or
    one sentence."""
    try:
        scenes = json.loads(Path(path).read_text())["scenes"]
        times = {name: (float(scene["preview_ms"]) / 1e3, tuple(scene["size"])) for name, scene in scenes.items()}
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise LPVError(f"Cannot read the GPU's preview times from '{path}' ({first_line(error)}); give the JSON "
                       f"that scripts/time_previews.py printed.") from None
    for name, (_, size) in times.items():
        if name in SCENES and size != SCENES[name]:
            raise LPVError(f"The GPU's preview of {name} in '{path}' was timed at {size[0]} x {size[1]}, not at the "
                           f"benchmark's {SCENES[name][0]} x {SCENES[name][1]}; time it again with "
                           f"scripts/time_previews.py.")
    return {name: seconds for name, (seconds, _) in times.items()}


def error_curve(timeline, reference):
    """[{seconds, relative_mse, psnr}] of a timeline of (seconds, image)."""
    return [{"seconds": float(seconds), "relative_mse": relative_mse(image, reference), "psnr": psnr(image, reference)}
            for seconds, image in timeline]


def error_at(curve, seconds, figure="relative_mse"):
    """The error the user sees at `seconds`: the last image shown by then (inf before the first)."""
    shown = [point[figure] for point in curve if point["seconds"] <= seconds]
    return shown[-1] if shown else math.inf


def still_goals(curves, earlier=0.0):
    """The issue's goals for a still camera: the corrected frame below undenoised Cycles at
    every moment of the first STILL_SECONDS (checked at every time either changes) and
    below denoised Cycles at equal time for the first DENOISED_GOAL_SECONDS; with the
    corrected frames shown `earlier` seconds sooner (a preview rendered faster elsewhere)."""
    corrected = _earlier(curves["corrected"], earlier)

    def below(other, until):
        moments = sorted({point["seconds"] for curve in (corrected, curves[other]) for point in curve
                          if 0 <= point["seconds"] <= until})
        losing = [round(t, 2) for t in moments if error_at(corrected, t) >= error_at(curves[other], t)]
        return {"met": not losing, "moments": len(moments), "losing_moments": losing[:8],
                "losing": len(losing), "last_losing": losing[-1] if losing else None}
    return {"below_cycles": below("cycles", STILL_SECONDS),
            "below_denoised": below("cycles_denoised", DENOISED_GOAL_SECONDS)}


def turn_kept(gained_before, gained_after):
    """The share of the dB gained at the first view that the first corrected frame after
    the turn keeps (the goal: at least half)."""
    return gained_after / gained_before if gained_before > 0 else math.nan


def write_correction_report(report, out):
    """corrections.json, corrections.md and a plot of error against time per scene in `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "corrections.json").write_text(json.dumps(report, indent=1))
    plots = _plots(report, out)
    lines = [f"### Corrections toward Cycles against Cycles ({report['machine']})", "",
             f"Still camera: error (relative MSE) against a {report['reference_samples']}-sample Cycles full-GI "
             f"reference at each moment; {report['cores']} CPU cores for every method (Cycles on {report['cores']} "
             f"threads; {report['workers']} sample workers of one thread each, the preview's render time counted on "
             f"the same machine).", ""]
    for scene in report["scenes"]:
        lines += _scene_lines(scene, plots)
    lines += ["", f"Command: `{report['command']}`"]
    (out / "corrections.md").write_text("\n".join(lines) + "\n")
    return {"out": str(out), "plots": [str(p) for p in plots.values()]}


def _scene_lines(scene, plots):
    curves, labels = _curves(scene), _labels(scene)
    moments = TABLE_MOMENTS
    lines = [f"#### {scene['name']} ({scene['resolution'][0]}×{scene['resolution'][1]})", "",
             f"Preview alone: relative MSE {scene['preview_error']:.4f} ({scene['preview_psnr']:.1f} dB), rendered "
             f"in {scene['preview_seconds'] * 1e3:.0f} ms. The reference's own noise is about "
             f"{scene['reference_noise']:.4f} (Cycles' undenoised error scaled by its samples). Denoised "
             f"Cycles is rendered anew for 1, 2, 4, ... samples up to {DENOISED_SECONDS:g} s; '—': nothing shown "
             f"yet.", "",
             "| method | " + " | ".join(f"{t:g} s" for t in moments) + " |",
             "|---|" + "---:|" * len(moments)]
    for method in curves:
        until = DENOISED_SECONDS if method == "cycles_denoised" else STILL_SECONDS
        cells = [error_at(curves[method], t) if t <= until else None for t in moments]
        cells = ("not run" if cell is None else "—" if math.isinf(cell) else f"{cell:.4f}" for cell in cells)
        lines.append(f"| {labels[method]} | " + " | ".join(cells) + " |")
    lines += ["", f"Preview counted as rendered here ({scene['preview_seconds']:.2f} s): "
              + _goal_words(scene["goals"]) + "."]
    if scene.get("goals_gpu_preview") is not None:
        lines += [f"Preview counted as rendered on the GPU ({scene['gpu_preview_seconds'] * 1e3:.0f} ms, "
                  f"scripts/time_previews.py), the samples as measured here: " + _goal_words(scene["goals_gpu_preview"])
                  + "."]
    lines.append("")
    turn = scene["turn"]
    lines += [f"A {turn['degrees']:g}° turn after {turn['seconds_before']:g} s still: the first corrected frame "
              f"gains {turn['gained_after']:.1f} dB over its preview where the view before had gained "
              f"{turn['gained_before']:.1f} dB: **{turn['kept']:.0%} kept** (goal: at least half).", ""]
    lines += [f"Camera path ({', '.join(f'{d:g}°' for d in PATH_DEGREES)}), {FRAME_SECONDS:g} s a frame: "
              "relative MSE at the end of each frame's time (and of the corrected frame at its start).", "",
              "| frame | " + " | ".join(LABELS[m] for m in METHODS) + " | corrected at its start |",
              "|---|" + "---:|" * (len(METHODS) + 1)]
    for frame in scene["path"]:
        lines.append(f"| {frame['degrees']:g}° | " + " | ".join(f"{frame['end'][m]:.4f}" for m in METHODS)
                     + f" | {frame['corrected_start']:.4f} |")
    if scene["name"] in plots:
        lines += ["", f"![{scene['name']}]({plots[scene['name']].name})"]
    return lines + [""]


def _goal_words(goals):
    below, denoised = goals["below_cycles"], goals["below_denoised"]
    return (f"below undenoised Cycles at every moment of {STILL_SECONDS:g} s **{'met' if below['met'] else 'not met'}**"
            + ("" if below["met"] else f" (behind at {_losing(below)})")
            + f"; below denoised Cycles for the first {DENOISED_GOAL_SECONDS:g} s "
            f"**{'met' if denoised['met'] else 'not met'}**"
            + ("" if denoised["met"] else f" (behind at {_losing(denoised)})"))


def _plots(report, out):
    plt = pyplot()
    if plt is None:
        return {}
    plots = {}
    for scene in report["scenes"]:
        figure, axes = plt.subplots(figsize=(6.4, 4.4), dpi=100)
        for method, curve in _curves(scene).items():
            axes.step([p["seconds"] for p in curve], [p["relative_mse"] for p in curve], where="post",
                      linestyle="--" if method == "corrected_gpu" else "-", label=_labels(scene)[method])
        axes.axhline(scene["preview_error"], color="grey", linewidth=0.8, linestyle=":", label="preview alone")
        axes.set_xscale("log")
        axes.set_yscale("log")
        plots[scene["name"]] = save(plt, figure, axes, ("wall seconds", "relative MSE against the reference"),
                                    f"{scene['name']}: still camera, {report['cores']} CPU cores",
                                    out / f"corrections_{scene['name']}.png")
    return plots


def _curves(scene):
    """The still camera's error curves, with the corrected one as if the preview had been
    rendered on the GPU when its time there is known."""
    curves = dict(scene["still"])
    if scene.get("gpu_preview_seconds") is not None:
        curves["corrected_gpu"] = _earlier(curves["corrected"], scene["preview_seconds"] - scene["gpu_preview_seconds"])
    return curves


def _labels(scene):
    return {**LABELS, "corrected_gpu": f"preview on the GPU ({(scene.get('gpu_preview_seconds') or 0) * 1e3:.0f} ms) "
                                       f"+ corrections"}


def _losing(goal):
    """The moments a goal loses: the first 8 and, past them, how many more and the last."""
    shown = f"{goal['losing_moments']} s"
    more = goal.get("losing", 0) - len(goal["losing_moments"])
    return shown + (f" and {more} more moment{'s' * (more > 1)}, the last at {goal['last_losing']} s" if more > 0
                     else "")


def _earlier(curve, seconds):
    return [{**point, "seconds": point["seconds"] - seconds} for point in curve]


def scene_report(name, runs, reference_samples, gpu_preview_seconds=None):
    """A scene's entry of the report from the timelines of cli/correction_runs.py
    measure_scene (`runs`); with `gpu_preview_seconds` (the same preview timed on a GPU),
    the goals also as if the preview had been rendered there."""
    views = runs["views"]
    first, last = views[0], views[-1]
    still = {method: error_curve(timeline, first.reference) for method, timeline in runs["still"].items()}
    gained_before = psnr(runs["still"]["corrected"][-1][1], first.reference) - psnr(first.preview, first.reference)
    gained_after = psnr(runs["turn"], last.reference) - psnr(last.preview, last.reference)
    path = [{"degrees": view.degrees,
             "end": {method: relative_mse(frame[method][-1][1], view.reference) for method in METHODS},
             "corrected_start": relative_mse(frame["corrected"][1][1], view.reference)}
            for view, frame in zip(views, runs["path"])]
    return {"name": name, "resolution": list(first.reference.shape[1::-1]),
            "preview_error": relative_mse(first.preview, first.reference),
            "preview_psnr": psnr(first.preview, first.reference), "preview_seconds": first.preview_seconds,
            "reference_noise": float(still["cycles"][-1]["relative_mse"] * runs["cycles_samples"] / reference_samples),
            "cycles_samples": runs["cycles_samples"], "still": still, "goals": still_goals(still),
            "gpu_preview_seconds": gpu_preview_seconds,
            "goals_gpu_preview": None if gpu_preview_seconds is None else
            still_goals(still, first.preview_seconds - gpu_preview_seconds),
            "turn": {"degrees": last.degrees - first.degrees, "seconds_before": runs["still"]["corrected"][-1][0],
                     "gained_before": gained_before, "gained_after": gained_after,
                     "kept": turn_kept(gained_before, gained_after)},
            "path": path}
