"""Many emitters (issue 17): frame time and error against the emitter count for the
emitter grid's three interpolations and the brute-force loop, the GPU memory the grid
holds, and the frame time of many point lights against one.

Every figure is measured on the machine that runs it (`python -m lpv_preview bench
--emitters`); the report names the renderer.
"""
import json
import time
from pathlib import Path

import numpy as np

from ..gpu.context import GLContext, resource_bytes
from ..gpu.metrics import psnr, relative_mse
from ..gpu.pipeline import Pipeline
from ..gpu.settings import EMITTER_INTERPOLATIONS, Settings
from .synthetic import lamps_over_floor, particle_room

COUNTS = tuple(4 ** k for k in range(11))  # 1 .. 1,048,576
SIZES = {"gpu": (1920, 1080), "llvmpipe": (320, 240)}
"""The frame of the emitter counts: the issue's 1920 × 1080 on a GPU; on llvmpipe, where
brute force at that size takes minutes an emitter set, a smaller one."""


def emitter_bench_size():
    """The frame size of the emitter counts on this machine (SIZES)."""
    return SIZES["llvmpipe" if GLContext.shared().is_software else "gpu"]


GRID_STAGES = ("emitter_upload_ms", "emitter_grid_ms", "emitter_light_ms", "total_ms")


def _median_stages(pipeline, scenes, settings):
    """Median ms of the emitters' upload, the grid's build and the shading over frames of
    `scenes` (the particles moving from frame to frame: each frame uploads and builds
    again, as an animation does), after a first frame that compiles the shaders; and the
    direct image of the first scene."""
    frame = pipeline.render(scenes[0], settings, passes=("direct",))
    direct = frame.passes["direct"]
    times = []
    for scene in scenes[1:]:
        frame = pipeline.render(scene, settings, passes=())
        times.append({key: frame.stats.get(key, 0.0) for key in GRID_STAGES})
    return {key: float(np.median([t[key] for t in times])) for key in GRID_STAGES}, direct


def measure_emitter_counts(counts=COUNTS, width=1920, height=1080, resolution=64, repeats=3, brute_limit=1 << 20,
                           log=print):
    """For each count: the particle room's frame with the grid (each interpolation) and
    by brute force (up to `brute_limit` emitters), the grid's PSNR against brute force,
    and the grid's GPU memory; times are medians over `repeats` frames of moving particles."""
    glc = GLContext.shared()
    rows = []
    base = Settings(width=width, height=height, emitter_grid_resolution=resolution, indirect_method="light_grid",
                    emitter_bounce_samples=256)
    for count in counts:
        scenes = [particle_room(count, seed=seed) for seed in range(repeats + 1)]
        pipeline = Pipeline(base, glc)
        try:
            row = {"emitters": count}
            reference = None
            if count <= brute_limit:
                timed, reference = _median_stages(pipeline, scenes[:2], base.with_changes(emitter_light="brute_force"))
                row["brute_force_ms"] = timed["emitter_light_ms"]
            for interpolation in EMITTER_INTERPOLATIONS:
                timed, direct = _median_stages(pipeline, scenes, base.with_changes(emitter_interpolation=interpolation))
                row[interpolation] = {"upload_ms": timed["emitter_upload_ms"], "build_ms": timed["emitter_grid_ms"],
                                      "shade_ms": timed["emitter_light_ms"], "frame_ms": timed["total_ms"],
                                      "grid_ms": timed["emitter_grid_ms"] + timed["emitter_light_ms"]}
                if reference is not None:
                    row[interpolation]["psnr_vs_brute_db"] = float(psnr(direct, reference))
            row["grid_bytes"] = resource_bytes(*pipeline.last_emitter_grid.resources())
        finally:
            pipeline.release()
        log(json.dumps(row))
        rows.append(row)
    return {"renderer": glc.renderer, "width": width, "height": height, "grid_resolution": resolution,
            "rows": rows}


def measure_many_lights(count=64, width=640, height=480, repeats=3, log=print):
    """A frame of `count` point lights over the room's floor against a frame of one, with
    the default light-map budget (the rest through the emitter grid) and with every
    light given maps."""
    glc = GLContext.shared()
    result = {"renderer": glc.renderer, "lights": count, "width": width, "height": height}
    for name, scene, changes in (("one_light", lamps_over_floor(1), {}),
                                 ("many_lights", lamps_over_floor(count), {}),
                                 ("many_lights_all_mapped", lamps_over_floor(count), {"light_map_budget": count})):
        settings = Settings(width=width, height=height, **changes)
        pipeline = Pipeline(settings, glc)
        try:
            times = []
            for _ in range(repeats):
                pipeline.invalidate()
                start = time.perf_counter()
                frame = pipeline.render(scene, settings, passes=("combined",))
                times.append((time.perf_counter() - start) * 1000.0)
            result[name] = {"frame_ms": float(np.median(times)), "mapped_lights": frame.stats["mapped_lights"],
                            "lights_as_emitters": frame.stats["lights_as_emitters"]}
        finally:
            pipeline.release()
        log(json.dumps({name: result[name]}))
    result["ratio"] = result["many_lights"]["frame_ms"] / result["one_light"]["frame_ms"]
    result["ratio_all_mapped"] = result["many_lights_all_mapped"]["frame_ms"] / result["one_light"]["frame_ms"]
    return result


def measure_against_cycles(cases, width, height, log=print):
    """The direct light of brute force and of the grid (each interpolation) against
    Cycles': `cases` are (emitter count, Scene, Cycles' direct image at width × height),
    made where Blender is (the caller's). PSNR, relMSE and the ratio of the means."""
    rows = []
    base = Settings(width=width, height=height, emitter_bounce_samples=256)
    for count, scene, reference in cases:
        pipeline = Pipeline(base)
        try:
            row = {"emitters": count}
            variants = [("brute_force", {"emitter_light": "brute_force"})]
            variants += [(interpolation, {"emitter_interpolation": interpolation})
                         for interpolation in EMITTER_INTERPOLATIONS]
            for name, changes in variants:
                direct = pipeline.render(scene, base.with_changes(**changes), passes=("direct",)).passes["direct"]
                row[name] = {"psnr_db": float(psnr(direct, reference)),
                             "rel_mse": float(relative_mse(direct, reference)),
                             "mean_ratio": float(direct.mean() / reference.mean())}
        finally:
            pipeline.release()
        log(json.dumps(row))
        rows.append(row)
    return {"renderer": GLContext.shared().renderer, "width": width, "height": height, "rows": rows}


def write_emitter_report(report, out):
    """emitters.json and emitters.md in the folder `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "emitters.json").write_text(json.dumps(report, indent=1))
    (out / "emitters.md").write_text(emitter_report_markdown(report))
    return {"out": str(out), "rows": sum(len(counts["rows"]) for counts in report["counts"])}


def emitter_report_markdown(report):
    """The report's tables: per grid resolution, per emitter count; against Cycles; many lights."""
    lights = report["lights"]
    lines = []
    for counts in report["counts"]:
        lines += [f"### Emitter grid {counts['grid_resolution']}³ ({counts['renderer']})", "",
                  f"Particle room at {counts['width']}×{counts['height']}: grid build + shading (ms) and the grid "
                  f"against brute force (PSNR, dB) per interpolation, brute force (ms), the upload of the emitters and "
                  f"the whole frame, CPU included (ms, with the trilinear grid), grid memory.", "",
                  "| emitters | " + " | ".join(f"{i} ms | {i} dB" for i in EMITTER_INTERPOLATIONS) +
                  " | brute force ms | upload ms | frame ms | grid MiB |",
                  "|---:|" + "---:|" * (2 * len(EMITTER_INTERPOLATIONS) + 4)]
        for row in counts["rows"]:
            cells = []
            for interpolation in EMITTER_INTERPOLATIONS:
                entry = row[interpolation]
                cells += [f"{entry['grid_ms']:.2f}",
                          f"{entry['psnr_vs_brute_db']:.1f}" if "psnr_vs_brute_db" in entry else "–"]
            brute = f"{row['brute_force_ms']:.1f}" if "brute_force_ms" in row else "–"
            lines.append(f"| {row['emitters']:,} | " + " | ".join(cells) + f" | {brute} | "
                         f"{row['trilinear']['upload_ms']:.2f} | {row['trilinear']['frame_ms']:.1f} | "
                         f"{row['grid_bytes'] / 2**20:.1f} |")
        lines.append("")
    cycles = report.get("cycles")
    if cycles:
        names = ("brute_force", *EMITTER_INTERPOLATIONS)
        lines += [f"### Against Cycles (the particles demo scene, {cycles['width']}×{cycles['height']}, "
                  f"{cycles['samples']} samples, light tree; ours on {cycles['renderer']})", "",
                  "Direct light: PSNR (dB) / relMSE / our mean over Cycles'.", "",
                  "| emitters | " + " | ".join(names) + " |", "|---:|" + "---|" * len(names)]
        for row in cycles["rows"]:
            lines.append(f"| {row['emitters']:,} | " + " | ".join(
                f"{row[n]['psnr_db']:.1f} / {row[n]['rel_mse']:.4f} / {row[n]['mean_ratio']:.3f}"
                for n in names) + " |")
        lines.append("")
    lines += [f"{lights['lights']} point lights at {lights['width']}×{lights['height']}: a frame "
              f"{lights['many_lights']['frame_ms']:.1f} ms ({lights['many_lights']['mapped_lights']} with maps, "
              f"{lights['many_lights']['lights_as_emitters']} through the grid) against one light's "
              f"{lights['one_light']['frame_ms']:.1f} ms: {lights['ratio']:.2f}×; every light with maps "
              f"{lights['many_lights_all_mapped']['frame_ms']:.1f} ms ({lights['ratio_all_mapped']:.2f}×).", "",
              f"Command: `{report['command']}`"]
    return "\n".join(lines) + "\n"
