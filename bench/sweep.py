"""Benchmark sweeps: run time against error for every point of a declared sweep.

A sweep (bench/sweeps.toml) names scenes, methods and axes of settings. For each point the
pipeline renders the scene's camera view; `timed_frames` gives the median per-stage and
frame milliseconds with every stage redone (warm-up excluded, no image read back: what
the GPU does for a frame) and their spread, and the
indirect image is compared (PSNR, relative MSE, FLIP) with the CM-LPV reference: the
same LPV grid and steps fed by a cube map of 2048² and 65,536 VPLs (a sweep's `reference`
may set others), so the error is what the method's light side costs. With `cycles_samples`, points that keep the scene's own
lights are also compared with its Cycles one-bounce reference, which `cycles_indirect`
(a callback: bpy lives above this module) supplies; those errors compare grids and steps
too. An .npz export may carry its Cycles reference beside it (gpu/scene_file.py
`stored_cycles_indirect`, written by `python -m lpv_preview export --cycles-samples`): the GPU machine has no
Cycles, and a reference of a 1920x1080 image would take the CPU machine an hour, so the
points of such a scene are timed at their own size and compared, with both references,
in a render at the stored reference's smaller size. The GPU memory is what the pipeline
holds. No bpy: this runs on the GPU machine from .npz scene exports.
"""
import itertools
import os
import platform
import time
import tomllib
from pathlib import Path

from ..gpu.context import GLContext
from ..gpu.errors import LPVError
from ..gpu.metrics import flip, psnr, relative_mse
from ..gpu.pipeline import Pipeline, render_once
from ..gpu.scene_edits import LIGHT_KIND_NAMES, with_lights
from ..gpu.settings import PARAMETERS, PRESETS, preset_settings
from .sweep_report import REFERENCE_CHANGES, SCALING_AXES
from .timing import timed_frames
from .viewport_work import redraw_times

SWEEPS_FILE = Path(__file__).parent / "sweeps.toml"
SWEEP_KEYS = {"description", "mode", "scenes", "methods", "preset", "lights", "light_kind", "repeats", "cycles_samples",
              "scaling", "choose_presets", "reference", "viewport_redraws"}
SWEEP_CHOICES = {"preset": PRESETS, "scaling": SCALING_AXES, "light_kind": LIGHT_KIND_NAMES}
"""The sweep keys whose values come from a fixed set."""
SCHEMA_VERSION = 1


def load_sweep(name, path=SWEEPS_FILE):
    """The sweep `name` of the sweeps file, checked: known keys, settings and values."""
    try:
        with open(path, "rb") as handle:
            sweeps = tomllib.load(handle)
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise LPVError(f"Cannot read the sweeps file '{path}' ({error}); give a TOML file of sweeps.") from None
    if name not in sweeps:
        raise LPVError(f"There is no sweep '{name}' in {path}; choose one of {', '.join(sweeps)}.")
    sweep = sweeps[name]
    unknown = set(sweep) - SWEEP_KEYS - set(PARAMETERS)
    if unknown:
        raise LPVError(f"Sweep '{name}' has unknown key '{sorted(unknown)[0]}'; use settings of gpu/settings.py "
                       f"or {', '.join(sorted(SWEEP_KEYS))}.")
    if ("methods" in sweep) == ("preset" in sweep):
        raise LPVError(f"Sweep '{name}' needs either 'methods' or 'preset' (a preset sets the method).")
    unknown = set(sweep.get("reference", {})) - set(REFERENCE_CHANGES)
    if unknown:
        raise LPVError(f"Sweep '{name}' has reference setting '{sorted(unknown)[0]}'; a reference sets "
                       f"{', '.join(REFERENCE_CHANGES)}.")
    for key, choices in SWEEP_CHOICES.items():
        for value in _as_list(sweep.get(key, [])):
            if value not in choices:
                raise LPVError(f"Sweep '{name}' has {key.replace('_', ' ')} '{value}'; choose from "
                               f"{', '.join(choices)}.")
    return sweep


def _as_list(value):
    return list(value) if isinstance(value, list) else [value]


def sweep_points(sweep):
    """Every point of the sweep: dicts of scene, method (or preset), light count and kind,
    settings."""
    axes = {key: _as_list(value) for key, value in sweep.items()
            if key in PARAMETERS or key in ("preset", "lights", "light_kind")}
    base = {key: values[0] for key, values in axes.items()}
    if sweep.get("mode", "product") == "one-at-a-time":
        variations = [dict(base)]
        for key, values in axes.items():
            variations += [{**base, key: value} for value in values[1:]]
    else:
        variations = [dict(zip(axes, combination)) for combination in itertools.product(*axes.values())]
    return [{"scene": scene, "method": method or preset_settings(variation["preset"]).method, **variation}
            for scene in _as_list(sweep["scenes"]) for method in _as_list(sweep.get("methods", [None]))
            for variation in variations]


def machine_description(glc):
    """What a report was measured on: the GL renderer, its version (the driver's on
    NVIDIA and Mesa), the CPU and its cores."""
    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo") as handle:
            cpu = next(line.split(":", 1)[1].strip() for line in handle if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"renderer": glc.renderer, "version": glc.version, "cpu": f"{cpu}, {os.cpu_count()} cores",
            "system": platform.platform()}


def _indirect_errors(image, reference):
    if float(reference.max()) <= 0.0:
        return {"psnr": None, "relative_mse": None, "flip": None}
    return {"psnr": psnr(image, reference), "relative_mse": relative_mse(image, reference),
            "flip": flip(image, reference)[0]}


def settle_allocations(glc, scene, settings):
    """Build, render once and release a pipeline of `settings` before the timed one.

    On the H100 (driver 580.159.04) the first pipeline built after a large one was
    released (the CM-LPV reference: 2048² cube atlases, 65,536 VPLs) ran three times
    slower for its whole life (the Cornell box's G-buffer 12.5 ms by the timer query
    instead of 2.2, after 0.5 s of warm-up as after 2 s); a second one built with the
    same settings did not. This one takes that hit."""
    render_once(scene, settings, glc, passes=())


def run_sweep(name, sweep, load_scene, log=print, cycles_indirect=None):
    """Measure every point; returns the JSON-ready report (SCHEMA_VERSION).

    `cycles_indirect(scene, samples, width, height)` returns the scene's Cycles one-bounce
    indirect image (top row first) and its samples, or None where there is none. Where
    the image is smaller than the point's (a reference stored beside an .npz export),
    both errors are measured in a render at the image's size."""
    glc = GLContext.shared()
    repeats = int(sweep.get("repeats", 3))
    reference_changes = {**REFERENCE_CHANGES, **sweep.get("reference", {})}
    points = sweep_points(sweep)
    scenes, references, cycles, results = {}, {}, {}, []
    cycles_samples = sweep.get("cycles_samples")
    started = time.perf_counter()
    for index, point in enumerate(points):
        if point["scene"] not in scenes:
            scenes = {point["scene"]: load_scene(point["scene"])}  # one scene in memory at a time
        scene = scenes[point["scene"]]
        own_lights = "lights" not in point and "light_kind" not in point
        if not own_lights:
            scene = with_lights(scene, int(point.get("lights", 1)), point.get("light_kind", "point"))
        settings = preset_settings(point.get("preset"), **{k: v for k, v in point.items() if k in PARAMETERS})
        if "converged_lpv_resolution" not in point:  # a row's sets gather at the grid it names
            settings = settings.with_changes(converged_lpv_resolution=settings.lpv_resolution)
        cycles_reference = None
        if cycles_samples and cycles_indirect is not None and own_lights:
            cycles_key = (point["scene"], settings.width, settings.height)
            if cycles_key not in cycles:
                cycles[cycles_key] = cycles_indirect(point["scene"], int(cycles_samples), *cycles_key[1:])
                if cycles[cycles_key] is None:
                    log(f"sweep {name}: {point['scene']} has no Cycles reference, so no errors against Cycles; "
                        f"export it with --cycles-samples")
            cycles_reference = cycles[cycles_key]
        error_settings = settings
        if cycles_reference is not None:
            height, width = cycles_reference[0].shape[:2]
            error_settings = settings.with_changes(width=width, height=height)
        reference_key = (point["scene"], point.get("lights"), point.get("light_kind"), settings.lpv_resolution,
                         settings.propagation_iterations, error_settings.width, error_settings.height)
        if reference_key not in references:
            references[reference_key] = render_once(scene, error_settings.with_changes(**reference_changes), glc,
                                                    passes=("indirect",)).passes["indirect"]
        settle_allocations(glc, scene, settings)
        pipeline = Pipeline(settings, glc)
        try:
            timings, stats = timed_frames(pipeline, scene, repeats, passes=())
            if sweep.get("viewport_redraws"):
                timings.update(redraw_times(pipeline, scene, settings))
            memory = pipeline.gpu_bytes()
            if error_settings != settings:
                pipeline.release()
                pipeline = Pipeline(error_settings, glc)
            indirect = pipeline.render_converged(scene, passes=("indirect",)).passes["indirect"]
        finally:
            pipeline.release()
        result = {**point, "settings": {key: getattr(settings, key) for key in PARAMETERS},
                  "triangles": scene.triangle_count, "timings_ms": timings, "gpu_bytes": memory,
                  "vpl_count": stats["vpl_count"], "error_size": [error_settings.width, error_settings.height],
                  "errors_vs_cm": _indirect_errors(indirect, references[reference_key])}
        if cycles_reference is not None:
            result["errors_vs_cycles"] = _indirect_errors(indirect, cycles_reference[0])
            result["cycles_samples"] = cycles_reference[1]
        results.append(result)
        log(f"sweep {name}: {index + 1}/{len(points)} {point['scene']} {point['method']} "
            f"{timings['total_ms']:.1f} ms")
    return {"schema": SCHEMA_VERSION, "sweep": name, "description": sweep.get("description", ""),
            "cycles_samples": cycles_samples, "scaling": _as_list(sweep.get("scaling", [])),
            "choose_presets": bool(sweep.get("choose_presets", False)),
            "reference": reference_changes, "machine": machine_description(glc), "date": time.strftime("%Y-%m-%d"),
            "repeats": repeats,
            "seconds": time.perf_counter() - started, "points": results}
