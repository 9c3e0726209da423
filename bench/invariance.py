"""Invariances: the same scene moved, scaled or sampled differently must give the same
picture. Each row renders the closed room (bench/synthetic.py) changed one way and
compares its direct and indirect images (PSNR) with the unchanged room's, per method:

- translation: the room moved by (d, d, 0) in float64 (a georeferenced model stands
  1e5-1e6 m out; the local origin of gpu/scene.py keeps its positions small);
- grid shift: the LPV's grid moved by a fraction of a cell against the room (Settings
  grid_shift): what an object or light crossing cell boundaries in an animation sees;
- light frame: the light's own frame turned 45° about its direction (its maps sample the
  room elsewhere; the picture should not care);
- scale: the room, its light and its camera scaled (the light's power with the square),
  which changes no radiance.
"""
import dataclasses
import json
import math
import os

from ..gpu.metrics import psnr
from ..gpu.pipeline import render_once
from ..gpu.scene_edits import turned_about_its_axis
from ..gpu.settings import Settings
from .synthetic import room_scene

METHODS = ("cm", "dpm", "wdpm", "tdpm", "twdpm")
TRANSLATIONS = (100.0, 1e3, 1234.567, 1e4, 1e5, 1e6)
GRID_SHIFTS = (0.25, 0.5, 0.75)
SCALES = (1e-3, 1e3)
SETTINGS = Settings(width=96, height=96, rsm_resolution=256, vpls_per_light=1024, converge_sets=1)
ROOM_QUADS = 8


def variants():
    """(invariance, what changed, scene, settings changes) for every row."""
    rows = [("translation", f"{d:g} m", room_scene(ROOM_QUADS, offset=(d, d, 0.0)), {}) for d in TRANSLATIONS]
    rows += [("grid shift", f"{f:g} cell", room_scene(ROOM_QUADS), {"grid_shift": f}) for f in GRID_SHIFTS]
    turned = room_scene(ROOM_QUADS)
    turned.lights = [turned_about_its_axis(light) for light in turned.lights]
    rows.append(("light frame", "turned 45°", turned, {}))
    rows += [("scale", f"× {s:g}", room_scene(ROOM_QUADS, scale=s), {}) for s in SCALES]
    return rows


def measure_invariances(methods=METHODS, settings=SETTINGS, log=print):
    """{"rows": [{invariance, change, method, direct_psnr, indirect_psnr}], ...}: each
    variant's images against the unchanged room's, per method (PSNR in dB; None where
    the images are identical)."""
    rows = []
    for method in methods:
        method_settings = settings.with_changes(method=method)
        reference = render_once(room_scene(ROOM_QUADS), method_settings).passes
        for invariance, change, scene, changes in variants():
            passes = render_once(scene, method_settings.with_changes(**changes)).passes
            figures = {name: psnr(passes[name], reference[name]) for name in ("direct", "indirect")}
            rows.append({"invariance": invariance, "change": change, "method": method,
                         **{f"{name}_psnr": None if math.isinf(value) else value for name, value in figures.items()}})
        log(f"invariance: {method} done")
    return {"settings": dataclasses.asdict(settings), "room_quads": ROOM_QUADS, "rows": rows}


def markdown_table(report):
    """One row per invariance and change, two columns (direct, indirect) per method."""
    methods = list(dict.fromkeys(row["method"] for row in report["rows"]))
    cells = {(row["invariance"], row["change"], row["method"]): row for row in report["rows"]}
    changes = list(dict.fromkeys((row["invariance"], row["change"]) for row in report["rows"]))
    head = ["invariance", "change"] + [f"{method.upper()} {image}" for method in methods
                                      for image in ("direct", "indirect")]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for invariance, change in changes:
        values = []
        for method in methods:
            row = cells[(invariance, change, method)]
            values += ["identical" if row[f"{image}_psnr"] is None else f"{row[f'{image}_psnr']:.1f}"
                       for image in ("direct", "indirect")]
        lines.append("| " + " | ".join([invariance, change, *values]) + " |")
    return "\n".join(lines) + "\n"


def write_invariances(report, out, command):
    """invariance.json and invariance.md (the command, then the table) in the folder `out`."""
    os.makedirs(out, exist_ok=True)
    report = {**report, "command": command}
    with open(os.path.join(out, "invariance.json"), "w") as handle:
        json.dump(report, handle, indent=1)
    with open(os.path.join(out, "invariance.md"), "w") as handle:
        handle.write(f"    {command}\n\n" + markdown_table(report))
    return {"out": out, "rows": len(report["rows"])}
