"""The thesis's Table 1 on our scenes: every RSM method's cost and quality against CM.

For each scene and method: RSM and warp milliseconds (throughput: many back to back,
the GPU finished before and after, so CPU submission gaps do not count), whole-frame
milliseconds (median of repeats, every stage redone, warm-up excluded), the DPM quality (PSNR of the method's map against
the reference DPM sampled from the cube map, over the reference's valid texels) and the
LPV quality (PSNR of the indirect-only image against the CM-based LPV with the same VPL
count and grid, over a camera path), and for warped methods the share of texels
converged / approximate / failed after 1, 4, 8 and 16 iterations (the thesis's fig. 10).

Beside them, the sampling reference: the LPV PSNR of CM against CM with the light's frame
turned 45° about its axis (the same map quality, the VPLs elsewhere). A method near it
differs from CM about as much as CM's own VPL pattern makes it differ from itself.
"""
import json
import math
import os

import numpy as np

from ..gpu.context import GLContext
from ..gpu.mesh_buffer import MeshBuffer
from ..gpu.metrics import psnr
from ..gpu.pipeline import Pipeline, map_recipe
from ..gpu.rsm import PROJECTION_PARABOLOID, render_rsm
from ..gpu.scene_edits import camera_path, turned_about_its_axis, with_point_light
from ..gpu.settings import METHODS
from ..gpu.warp import STATUS_NAMES, reference_paraboloid_map, warp_paraboloid_map
from .timing import THROUGHPUT_RUNS, throughput_ms, timed_frames

TABLE1_METHODS = tuple(method for method in METHODS if method != "auto")
"""The RSM methods Table 1 measures against CM (`auto` chooses among them per light)."""

STATUS_ITERATIONS = (1, 4, 8, 16)


def sampling_reference(settings, scene, cameras, reference_images):
    """LPV PSNR of CM against CM with every light's frame turned 45°: per frame."""
    lights = scene.lights
    scene.lights = [turned_about_its_axis(light) for light in lights]
    turned = Pipeline(settings.with_changes(method="cm"))
    try:
        images = indirect_images(turned, scene, cameras)
    finally:
        scene.lights = lights
        turned.release()
    return [psnr(image, reference) for image, reference in zip(images, reference_images)]


def map_measurements(glc, scene, settings, method):
    """RSM and warp milliseconds of one method for all the scene's lights and, for a
    warped method, fig. 10's status shares of its first paraboloid map (from the unwarped
    map, rendered once for both)."""
    recipe = map_recipe(settings, method)
    mesh = MeshBuffer(glc, scene)
    bounds = scene.bounds()
    timing = {"rsm_throughput_ms": 0.0, "warp_throughput_ms": 0.0}
    shares = None
    try:
        for light in scene.lights:
            def render():
                return render_rsm(glc, mesh, light, settings.rsm_resolution, bounds, recipe.projection,
                                  recipe.tessellation_unit)

            timing["rsm_throughput_ms"] += throughput_ms(glc, lambda: render().release())
            if recipe.warp_alpha is None:
                continue
            rsm = render()

            def warp():
                warped, status = warp_paraboloid_map(glc, rsm, recipe.warp_alpha, settings.warp_iterations,
                                                     settings.warp_significant_figures)
                warped.release()
                status.release()

            if rsm.projection_kind == PROJECTION_PARABOLOID:
                timing["warp_throughput_ms"] += throughput_ms(glc, warp)
                if shares is None:
                    shares = warp_status_shares(glc, rsm, recipe.warp_alpha, settings.warp_significant_figures)
            rsm.release()
    finally:
        mesh.release()
    return timing, shares


def indirect_images(pipeline, scene, cameras):
    images = []
    for camera in cameras:
        scene.camera = camera
        images.append(pipeline.render(scene).passes["indirect"])
    return images


def warp_status_shares(glc, source_rsm, alpha, significant_figures):
    """Share of valid-disk texels converged / approximate / failed after 1, 4, 8, 16 steps."""
    shares = {}
    for iterations in STATUS_ITERATIONS:
        warped, status = warp_paraboloid_map(glc, source_rsm, alpha, iterations, significant_figures)
        found = sum(status.counts[name] for name in STATUS_NAMES[1:])
        shares[iterations] = {name: status.counts[name] / max(found, 1) for name in STATUS_NAMES[1:]}
        warped.release()
        status.release()
    return shares


def benchmark_scene(name, scene, settings, methods, frames=5, repeats=3, budget="equal-resolution"):
    """One scene's rows: a dict per method."""
    scene = with_point_light(scene)
    scene.sanitize()
    base_camera = scene.camera
    cameras = camera_path(base_camera, frames)
    cube_settings = settings.with_changes(method="cm")
    cube = Pipeline(cube_settings)
    rows = {}
    try:
        timing, stats = timed_frames(cube, scene, repeats)
        reference_images = indirect_images(cube, scene, cameras)
        scene.camera = base_camera
        cube_maps, _ = cube.light_maps(scene)
        timing.update(map_measurements(cube.glc, scene, cube_settings, "cm")[0])
        rows["cm"] = {"timing": timing, "rsm_faces": stats["rsm_faces"], "rsm_resolution": settings.rsm_resolution}
        sampling = sampling_reference(settings, scene, cameras, reference_images)
        scene.camera = base_camera
        for method in methods:
            if method == "cm":
                continue
            resolution = settings.rsm_resolution
            if budget == "equal-texel-budget":  # 2 R_dpm^2 = 6 R_cm^2 for a point light
                resolution = min(2048, int(round(settings.rsm_resolution * math.sqrt(3))))
            pipeline = Pipeline(settings.with_changes(method=method, rsm_resolution=resolution))
            try:
                timing, stats = timed_frames(pipeline, scene, repeats)
                map_timing, shares = map_measurements(pipeline.glc, scene, pipeline.settings, method)
                timing.update(map_timing)
                images = indirect_images(pipeline, scene, cameras)
                scene.camera = base_camera
                quality = [psnr(image, reference) for image, reference in zip(images, reference_images)]
                maps, _ = pipeline.light_maps(scene)
                row = {"timing": timing, "rsm_faces": stats["rsm_faces"], "rsm_resolution": resolution,
                       "lpv_psnr_mean": float(np.mean(quality)), "lpv_psnr_min": float(np.min(quality)),
                       "lpv_psnr_frames": [float(q) for q in quality]}
                row.update(dpm_quality(pipeline, cube_maps, maps))
                if method in ("wdpm", "twdpm"):
                    row["warp_status"] = stats.get("warp_status")
                    row["warp_status_after"] = shares or {}
                rows[method] = row
            finally:
                pipeline.release()
    finally:
        cube.release()
    return {"scene": name, "triangles": scene.triangle_count, "lights": [light.kind for light in scene.lights],
            "budget": budget, "frames": frames, "repeats": repeats, "methods": rows,
            "sampling_reference": {"lpv_psnr_mean": float(np.mean(sampling)),
                                   "lpv_psnr_min": float(np.min(sampling)),
                                   "lpv_psnr_frames": [float(q) for q in sampling]}}


def dpm_quality(pipeline, cube_maps, method_maps):
    flux, position = [], []
    for cube, maps in zip(cube_maps, method_maps):
        if maps.rsm.projection_kind != PROJECTION_PARABOLOID:
            continue
        reference = reference_paraboloid_map(pipeline.glc, cube.rsm, maps.rsm)
        valid = reference.read(reference.position)[..., 3] > 0
        flux.append(psnr(maps.rsm.read(maps.rsm.flux)[..., :3], reference.read(reference.flux)[..., :3], mask=valid))
        position.append(psnr(maps.rsm.read(maps.rsm.position)[..., :3],
                             reference.read(reference.position)[..., :3], mask=valid))
        reference.release()
    if not flux:
        return {}
    return {"dpm_flux_psnr": float(np.mean(flux)), "dpm_position_psnr": float(np.mean(position))}


def markdown_table(results, machine):
    """Table 1 as markdown: one row per scene and method."""
    lines = [f"Machine: {machine}", "",
             f"RSM and warp ms: throughput ({THROUGHPUT_RUNS} back to back, wall clock, GPU finished before and "
             "after); RSM+warp over CM: the method's RSM and warp time over CM's RSM time; frame ms: median wall "
             "clock of a whole frame with readback.", "",
             "| scene | triangles | budget | method | RSM res | RSM ms | warp ms | RSM+warp over CM | frame ms | "
             "DPM flux PSNR | DPM position PSNR | LPV PSNR mean | LPV PSNR min |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for result in results:
        cube_ms = result["methods"]["cm"]["timing"]["rsm_throughput_ms"]
        for method, row in result["methods"].items():
            t = row["timing"]
            cell = lambda key: f"{row[key]:.2f}" if key in row else "-"
            rsm_ms, warp_ms = t["rsm_throughput_ms"], t["warp_throughput_ms"]
            lines.append(f"| {result['scene']} | {result['triangles']:,} | {result['budget']} | {method.upper()} | "
                         f"{row['rsm_resolution']} | {rsm_ms:.2f} | {warp_ms:.2f} | {(rsm_ms + warp_ms) / cube_ms:.0%} | "
                         f"{t['total_ms']:.1f} | {cell('dpm_flux_psnr')} | {cell('dpm_position_psnr')} | "
                         f"{cell('lpv_psnr_mean')} | {cell('lpv_psnr_min')} |")
        sampling = result["sampling_reference"]
        lines.append(f"| {result['scene']} | {result['triangles']:,} | {result['budget']} | CM turned 45° (sampling "
                     f"reference) | {result['methods']['cm']['rsm_resolution']} | - | - | - | - | - | - | "
                     f"{sampling['lpv_psnr_mean']:.2f} | {sampling['lpv_psnr_min']:.2f} |")
    lines += ["", "Warp status (share of texels that found geometry) after 1, 4, 8, 16 iterations:", "",
              "| scene | method | iterations | converged | approximate | failed |", "|---|---|---|---|---|---|"]
    for result in results:
        for method, row in result["methods"].items():
            for iterations, shares in row.get("warp_status_after", {}).items():
                lines.append(f"| {result['scene']} | {method.upper()} | {iterations} | {shares['converged']:.3f} | "
                             f"{shares['approximate']:.3f} | {shares['failed']:.3f} |")
    return "\n".join(lines) + "\n"


BUDGETS = ("equal-resolution", "equal-texel-budget")
"""Table 1 at the same RSM resolution for every method, or at the same texel count."""


def run_table1(scenes, settings, methods, frames, repeats, budgets, command, log=print):
    """Table 1's report over `scenes`, (name, load) pairs whose `load()` gives the Scene."""
    results = []
    for name, load in scenes:
        for budget in budgets:
            results.append(benchmark_scene(name, load(), settings, methods, frames, repeats, budget))
            log(f"bench: {name} ({budget}) done")
    glc = GLContext.shared()
    return {"machine": f"{glc.renderer}, OpenGL {glc.version}", "command": command, "settings": vars(settings),
            "results": results}


def write_table1(report, out):
    """table1.json and table1.md in the folder `out`."""
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "table1.json"), "w") as handle:
        json.dump(report, handle, indent=1, default=float)
    with open(os.path.join(out, "table1.md"), "w") as handle:
        handle.write(f"Command: `{report['command']}`\n\n" + markdown_table(report["results"], report["machine"]))
