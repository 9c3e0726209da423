"""Benchmark sweeps: run time against error for every point of a declared sweep.

A sweep (gpu/sweeps.toml) names scenes, methods and axes of settings. For each point the
pipeline renders the scene's camera view; `timed_frames` gives the median per-stage and
frame milliseconds with every stage redone (warm-up excluded, no image read back: what
the GPU does for a frame) and their spread, and the
indirect image is compared (PSNR, relative MSE, FLIP) with the CM-LPV reference: the
same LPV grid and steps fed by a cube map of 2048² and 65,536 VPLs, so the error is what
the method's light side costs. With `cycles_samples`, points that keep the scene's own
lights are also compared with its Cycles one-bounce reference, which `cycles_indirect`
(a callback: bpy lives above this module) supplies; those errors compare grids and steps
too. The GPU memory is what the pipeline holds. No bpy: this runs on the GPU machine from
.npz scene exports.
"""
import itertools
import math
import time
import tomllib
from pathlib import Path

import numpy as np

from .bench import timed_frames
from .errors import LPVError
from .metrics import flip, psnr, relative_mse
from .pipeline import Pipeline
from .scene import Light
from .settings import PARAMETERS, Settings

SWEEPS_FILE = Path(__file__).parent / "sweeps.toml"
SWEEP_KEYS = {"description", "mode", "scenes", "methods", "lights", "light_kind", "repeats", "cycles_samples"}
REFERENCE_CHANGES = {"method": "cm", "rsm_resolution": 2048, "vpls_per_light": 65536}
LIGHT_KINDS = {"point": "POINT", "spot": "SPOT", "area": "AREA", "sun": "SUN"}
SCHEMA_VERSION = 1


def load_sweep(name, path=SWEEPS_FILE):
    """The sweep `name` of the sweeps file, checked: known keys, settings and values."""
    with open(path, "rb") as handle:
        sweeps = tomllib.load(handle)
    if name not in sweeps:
        raise LPVError(f"There is no sweep '{name}' in {path}; choose one of {', '.join(sweeps)}.")
    sweep = sweeps[name]
    unknown = set(sweep) - SWEEP_KEYS - set(PARAMETERS)
    if unknown:
        raise LPVError(f"Sweep '{name}' has unknown key '{sorted(unknown)[0]}'; use settings of gpu/settings.py "
                       f"or {', '.join(sorted(SWEEP_KEYS))}.")
    for kind in _as_list(sweep.get("light_kind", [])):
        if kind not in LIGHT_KINDS:
            raise LPVError(f"Sweep '{name}' has light kind '{kind}'; choose from {', '.join(LIGHT_KINDS)}.")
    return sweep


def _as_list(value):
    return list(value) if isinstance(value, list) else [value]


def sweep_points(sweep):
    """Every point of the sweep: dicts of scene, method, light count and kind, settings."""
    axes = {key: _as_list(value) for key, value in sweep.items()
            if key in PARAMETERS or key in ("lights", "light_kind")}
    base = {key: values[0] for key, values in axes.items()}
    if sweep.get("mode", "product") == "one-at-a-time":
        variations = [dict(base)]
        for key, values in axes.items():
            variations += [{**base, key: value} for value in values[1:]]
    else:
        variations = [dict(zip(axes, combination)) for combination in itertools.product(*axes.values())]
    return [{"scene": scene, "method": method, **variation} for scene in _as_list(sweep["scenes"])
            for method in _as_list(sweep["methods"]) for variation in variations]


def with_lights(scene, count, kind):
    """The scene with its lights replaced by `count` lights of `kind` ("point", "spot",
    "area", "sun") on a square grid a quarter of the height under the top of its bounds,
    pointing down; their powers add up to the power that gives the floor about 1 W/m²
    from one light (a sun: 1 W/m² in all)."""
    low, high = scene.bounds()
    side = math.ceil(math.sqrt(count))
    height = 0.75 * (high[2] - low[2])
    lights = []
    for i in range(count):
        u, v = (i % side + 0.5) / side, (i // side + 0.5) / side
        position = np.array([low[0] + (0.25 + 0.5 * u) * (high[0] - low[0]),
                             low[1] + (0.25 + 0.5 * v) * (high[1] - low[1]), low[2] + height])
        blender_kind = LIGHT_KINDS[kind]
        power = 1.0 / count if blender_kind == "SUN" else 4 * math.pi * max(height, 1e-3) ** 2 / count
        direction = (0.3 * (u - 0.5), 0.3 * (v - 0.5), -1.0) if blender_kind == "SUN" else (0.0, 0.0, -1.0)
        lights.append(Light(blender_kind, position, direction, (0, 1, 0), (1, 1, 1), power, spot_size=math.radians(90),
                            size=(0.5, 0.5), name=f"sweep {kind} {i}"))
    scene.lights = lights
    return scene


def _indirect_errors(image, reference):
    if float(reference.max()) <= 0.0:
        return {"psnr": None, "relative_mse": None, "flip": None}
    return {"psnr": psnr(image, reference), "relative_mse": relative_mse(image, reference),
            "flip": flip(image, reference)[0]}


def run_sweep(name, sweep, load_scene, log=print, cycles_indirect=None):
    """Measure every point; returns the JSON-ready report (SCHEMA_VERSION).

    `cycles_indirect(scene, samples, width, height)` returns the scene's Cycles one-bounce
    indirect image (top row first) or None where there is none (an .npz scene)."""
    from .context import GLContext
    glc = GLContext.shared()
    repeats = int(sweep.get("repeats", 3))
    points = sweep_points(sweep)
    scenes, references, cycles, results = {}, {}, {}, []
    cycles_samples = sweep.get("cycles_samples")
    started = time.perf_counter()
    for index, point in enumerate(points):
        if point["scene"] not in scenes:
            scenes = {point["scene"]: load_scene(point["scene"])}  # one scene in memory at a time
        scene = scenes[point["scene"]]
        if "lights" in point or "light_kind" in point:
            scene = with_lights(scene, int(point.get("lights", 1)), point.get("light_kind", "point"))
        settings = Settings(**{key: value for key, value in point.items() if key in PARAMETERS})
        reference_key = (point["scene"], point.get("lights"), point.get("light_kind"), settings.lpv_resolution,
                         settings.propagation_iterations, settings.width, settings.height)
        if reference_key not in references:
            reference_pipeline = Pipeline(settings.with_changes(**REFERENCE_CHANGES), glc)
            try:
                references[reference_key] = reference_pipeline.render(scene, passes=("indirect",)).passes["indirect"]
            finally:
                reference_pipeline.release()
        pipeline = Pipeline(settings, glc)
        try:
            timings, stats = timed_frames(pipeline, scene, repeats, passes=())
            frame = pipeline.render(scene, passes=("indirect",))
            memory = pipeline.gpu_bytes()
        finally:
            pipeline.release()
        result = {**point, "settings": {key: getattr(settings, key) for key in PARAMETERS},
                  "triangles": scene.triangle_count, "timings_ms": timings, "gpu_bytes": memory,
                  "vpl_count": stats["vpl_count"],
                  "errors_vs_cm": _indirect_errors(frame.passes["indirect"], references[reference_key])}
        own_lights = "lights" not in point and "light_kind" not in point
        if cycles_samples and cycles_indirect is not None and own_lights:
            cycles_key = (point["scene"], settings.width, settings.height)
            if cycles_key not in cycles:
                cycles[cycles_key] = cycles_indirect(point["scene"], int(cycles_samples), *cycles_key[1:])
            if cycles[cycles_key] is not None:
                result["errors_vs_cycles"] = _indirect_errors(frame.passes["indirect"], cycles[cycles_key])
        results.append(result)
        log(f"sweep {name}: {index + 1}/{len(points)} {point['scene']} {point['method']} "
            f"{timings['total_ms']:.1f} ms")
    return {"schema": SCHEMA_VERSION, "sweep": name, "description": sweep.get("description", ""),
            "cycles_samples": cycles_samples,
            "machine": {"renderer": glc.renderer, "version": glc.version}, "repeats": repeats,
            "seconds": time.perf_counter() - started, "points": results}
