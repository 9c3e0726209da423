"""What a sweep's JSON report shows: a Markdown table, Pareto plots of time against error
per scene, and scaling plots of frame time against triangles and lights with the fitted
line. Made from the JSON alone, so a sweep run on the GPU machine is reported here."""
import json
import os
import sys
from collections import defaultdict

import numpy as np

from ..gpu.errors import LPVError
from ..gpu.metrics import figure_text
from ..gpu.pipeline import STAGES
from ..gpu.settings import INDIRECT_METHOD_ONLY, PRESET_PARAMETERS
from .plots import pyplot, save
from .viewport_work import SWEEP_REDRAWS

ERROR_METRIC = "relative_mse"  # the Pareto plots' error axis (lower is better)
ERROR_SOURCES = {"errors_vs_cycles": "Cycles one bounce", "errors_vs_cm": "CM-LPV"}


REFERENCE_CHANGES = {"method": "cm", "rsm_resolution": 2048, "vpls_per_light": 65536, "converge_sets": 1}
"""The CM-LPV reference's settings over a point's (a sweep's `reference` may change them)."""

SCALING_AXES = {"triangles": lambda point: point["triangles"], "lights": lambda point: point.get("lights", 1)}
"""What a sweep's `scaling` may name: the plots of frame time against each, and its x value."""


def read_report(path):
    """A sweep's (or Table 1's) JSON report, or one clear error."""
    try:
        with open(path) as handle:
            return json.load(handle)
    except (OSError, ValueError) as error:
        raise LPVError(f"Cannot read the sweep report '{path}' ({error}); give a sweep_NAME.json file.")


SWEEP_REPORT_KEYS = ("sweep", "description", "machine", "repeats", "points")
"""What `bench --sweep` writes and its Markdown and plots read."""


def read_sweep_report(path):
    """A sweep's JSON report, or one clear error when the file is none (Table 1's, say)."""
    report = read_report(path)
    missing = [key for key in SWEEP_REPORT_KEYS if not isinstance(report, dict) or key not in report]
    if missing:
        raise LPVError(f"'{path}' is not a sweep report (it lacks {', '.join(missing)}); give a sweep_NAME.json file "
                       f"that `bench --sweep NAME` wrote.")
    return report


def scene_label(scene):
    return os.path.splitext(os.path.basename(scene))[0]


def points_by_scene(points):
    """The points grouped by scene, in their order."""
    groups = defaultdict(list)
    for point in points:
        groups[point["scene"]].append(point)
    return groups


def error_cell(errors, key, spec):
    """One error figure of a table ("—" where there is none)."""
    return figure_text(errors.get(key), spec)


def varied_axes(points):
    """The settings and light keys whose value differs between points (besides method)."""
    keys = [k for k in points[0]["settings"] if k != "method"]
    varied = [k for k in keys if len({p["settings"][k] for p in points}) > 1]
    varied += [k for k in ("preset", "lights", "light_kind") if len({p.get(k) for p in points}) > 1]
    return varied


def error_source(points):
    """The errors the Pareto front of `points` is drawn on: against Cycles where every
    point has them (they compare grids and steps too), else against the CM-LPV."""
    return "errors_vs_cycles" if all("errors_vs_cycles" in p for p in points) else "errors_vs_cm"


def lowest_error_front(items, time, error):
    """The items no other beats in both `time` and `error` (functions of an item), fastest
    first."""
    front, best = [], float("inf")
    for item in sorted(items, key=lambda item: (time(item), error(item))):
        if error(item) < best:
            front.append(item)
            best = error(item)
    return front


def pareto_front(points):
    """The points no other point beats in both frame time and error, fastest first."""
    source = error_source(points)
    return lowest_error_front([p for p in points if p[source][ERROR_METRIC] is not None],
                              lambda p: p["timings_ms"]["total_ms"], lambda p: p[source][ERROR_METRIC])


ACCURATE_TIME_FACTOR = 4.0
"""`accurate` is the most accurate point of the front whose time is at most this factor of
balanced's: a quarter of its rate or more, where the front's last points took 30 to 50
times as long for a third less error (docs/benchmarks.md, the `fronts` sweep)."""


def geometric_mean(values):
    return float(np.exp(np.mean(np.log(values))))


REDRAW_KEYS = ("camera_move_ms", "light_edit_ms")
REDRAW_NAMES = {"camera_move_ms": "camera move redraw ms", "light_edit_ms": "light edit redraw ms"}
"""The viewport redraws a sweep with `viewport_redraws` times at each point (bench/
viewport_work.py redraw_times)."""


def redraw_ms(point):
    """The mean of a point's viewport redraws: what an artist waits for after moving the
    view or a light."""
    return float(np.mean([point["timings_ms"][key] for key in REDRAW_KEYS if key in point["timings_ms"]]))


def choose_presets(report):
    """Fast, balanced and accurate settings from a sweep that crosses the indirect method,
    the grid and the light side on several scenes, every point compared with Cycles.

    Each set of preset parameters measured on every scene is a candidate, with its mean
    time over the scenes (of the viewport's redraws where the sweep timed them, else of a
    frame with every stage redone) and its geometric-mean relMSE against Cycles' one bounce
    (a parameter the point's indirect method does not read is left out, its points
    merged). On their Pareto front balanced is the point with the least product of time
    and error, each over the front's best; fast the most accurate point faster than
    balanced (balanced where none is), and accurate the most accurate within
    ACCURATE_TIME_FACTOR of balanced's time: from fast to accurate each takes longer and
    comes closer to Cycles."""
    points = [p for p in report["points"] if p.get("errors_vs_cycles", {}).get("relative_mse")]
    scenes = sorted({p["scene"] for p in points})
    timed = redraw_ms if all(REDRAW_KEYS[0] in p["timings_ms"] for p in points) else \
        lambda p: p["timings_ms"]["total_ms"]
    combos = defaultdict(lambda: defaultdict(list))
    for p in points:
        method = p["settings"]["indirect_method"]
        used = tuple((k, p["settings"][k]) for k in PRESET_PARAMETERS
                     if INDIRECT_METHOD_ONLY.get(k, method) == method)
        combos[used][p["scene"]].append(p)
    candidates = []
    for used, by_scene in combos.items():
        if set(by_scene) != set(scenes):
            continue
        group = [p for s in scenes for p in by_scene[s]]
        candidates.append({
            "settings": dict(used),
            "frame_ms": float(np.mean([timed(p) for p in group])),
            "timed": "viewport redraw" if timed is redraw_ms else "frame",
            "relative_mse_vs_cm": geometric_mean([p["errors_vs_cm"]["relative_mse"] for p in group]),
            "relative_mse_vs_cycles": geometric_mean([p["errors_vs_cycles"]["relative_mse"] for p in group])})
    front = lowest_error_front(candidates, lambda c: c["frame_ms"], lambda c: c["relative_mse_vs_cycles"])
    least_error = front[-1]["relative_mse_vs_cycles"]
    balanced = min(front, key=lambda c: c["frame_ms"] / front[0]["frame_ms"] * c["relative_mse_vs_cycles"] / least_error)
    fast = ([c for c in front if c["frame_ms"] < balanced["frame_ms"]] or [balanced])[-1]
    accurate = [c for c in front if c["frame_ms"] <= ACCURATE_TIME_FACTOR * balanced["frame_ms"]][-1]
    return {"fast": fast, "balanced": balanced, "accurate": accurate}


def presets_table(chosen):
    """Markdown rows of choose_presets' result."""
    timed = next(iter(chosen.values()))["timed"]
    lines = [f"| preset | method | RSM | VPLs | indirect | grid | steps | VPL sets | mean {timed} ms | relMSE vs CM-LPV | "
             "relMSE vs Cycles |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, c in chosen.items():
        s = c["settings"]
        lines.append(f"| {name} | {s['method'].upper()} | {s['rsm_resolution']}² | {s['vpls_per_light']} | "
                     f"{s['indirect_method']} | {s['lpv_resolution']}³ | {s.get('propagation_iterations', '—')} | "
                     f"{s.get('converge_sets', 1)} | {c['frame_ms']:.2f} | "
                     f"{c['relative_mse_vs_cm']:.3g} | {c['relative_mse_vs_cycles']:.3g} |")
    return lines


def markdown_report(report, command=None):
    """The whole report as Markdown: machine, command, then one table per scene."""
    points = report["points"]
    varied = varied_axes(points)
    lines = [f"Sweep `{report['sweep']}`: {report['description']}", "",
             f"Machine: {machine_line(report['machine'])}; "
             f"median of {report['repeats']} frames with every stage redone (warm-up excluded), "
             f"spread min-max, no image read back; "
             + ("the viewport's redraws after a camera move and a light edit (one VPL set, the image read back as "
                "a viewport reads it; bench/viewport_work.py), medians of "
                f"{SWEEP_REDRAWS}, which choose the presets; " if any(REDRAW_KEYS[0] in p["timings_ms"] for p in points)
                else "")
             + "errors of the indirect image against the CM-LPV reference "
             f"({reference_words(report.get('reference', REFERENCE_CHANGES))}, the same grid and steps)"
             + (f" and against Cycles' one bounce at {report['cycles_samples']} samples (points with the scene's own "
                f"lights); the Pareto front is drawn on the Cycles errors where every point has them."
                if report.get("cycles_samples") else ".")]
    if command:
        lines += ["", f"    {command}"]
    for scene, group in points_by_scene(points).items():
        front = {id(p) for p in pareto_front(group)}
        sources = [source for source in ERROR_SOURCES if any(source in p for p in group)][::-1]
        stages = [stage for stage in STAGES if any(stage in p["timings_ms"] for p in group)]  # what ran
        redraws = [key for key in REDRAW_KEYS if any(key in p["timings_ms"] for p in group)]
        head = ["method", *varied, "frame ms (spread)", *(REDRAW_NAMES[key] for key in redraws),
                *(STAGES[stage] for stage in stages), "GPU MB",
                *(f"{metric} vs {ERROR_SOURCES[source]}" for source in sources for metric in ("PSNR dB", "relMSE", "FLIP")),
                "Pareto"]
        sizes = {tuple(p.get("error_size", (p["settings"]["width"], p["settings"]["height"]))) for p in group}
        timed = {(p["settings"]["width"], p["settings"]["height"]) for p in group}
        measured = (f", errors measured at {' / '.join(f'{w}×{h}' for w, h in sorted(sizes))}, times at "
                    f"{' / '.join(f'{w}×{h}' for w, h in sorted(timed))}" if sizes != timed else "")
        lines += ["", f"### {scene_label(scene)} ({group[0]['triangles']:,} triangles{measured})", "",
                  "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for p in group:
            t = p["timings_ms"]
            values = [str(p["settings"].get(k, p.get(k))) for k in varied]
            cells = [p["method"].upper(), *values]
            low, high = t["total_ms_spread"]
            errors = [error_cell(p.get(source, {}), k, f)
                      for source in sources for k, f in (("psnr", ".2f"), (ERROR_METRIC, ".3g"), ("flip", ".3f"))]
            cells += [f"{t['total_ms']:.2f} ({low:.2f}-{high:.2f})",
                      *(f"{t[key]:.2f}" if key in t else "—" for key in redraws), *(f"{t.get(s, 0.0):.2f}" for s in stages),
                      f"{p['gpu_bytes'] / 2**20:.0f}", *errors, "yes" if id(p) in front else ""]
            lines.append("| " + " | ".join(cells) + " |")
    if report.get("choose_presets"):
        lines += ["", "### Presets from this sweep (bench/sweep_report.py choose_presets)", "",
                  *presets_table(choose_presets(report))]
    return "\n".join(lines) + "\n"


def reference_words(reference):
    """The CM-LPV reference's settings in words, like 'cube map 2048², 65,536 VPLs'."""
    return f"cube map {reference['rsm_resolution']}², {reference['vpls_per_light']:,} VPLs"


def machine_line(machine):
    """The machine of a report in words: GPU (renderer), OpenGL and driver version, CPU."""
    line = f"{machine['renderer']}, OpenGL {machine['version']}"
    return line + (f"; CPU {machine['cpu']}" if machine.get("cpu") else "")


def pareto_plots(report, folder):
    """One PNG per scene: frame time against the error, one series per method, the
    Pareto front drawn through its points. Returns the files written."""
    plt = pyplot()
    written = []
    for scene, group in points_by_scene(report["points"]).items():
        source = error_source(group)
        figure, axes = plt.subplots(figsize=(6.4, 4.4), dpi=100)
        for method in sorted({p["method"] for p in group}):
            series = [p for p in group if p["method"] == method and p[source][ERROR_METRIC] is not None]
            axes.scatter([p["timings_ms"]["total_ms"] for p in series],
                         [p[source][ERROR_METRIC] for p in series], label=method.upper(), s=18)
        front = pareto_front(group)
        xs, ys = [p["timings_ms"]["total_ms"] for p in front], [p[source][ERROR_METRIC] for p in front]
        axes.plot(xs, ys, color="black", linewidth=1, marker="o", markersize=9, markerfacecolor="none",
                  label="Pareto front")
        if all(p[source][ERROR_METRIC] for p in front):
            axes.set_yscale("log")
        written.append(save(plt, figure, axes, ("frame ms (every stage redone)",
                                                 f"relative MSE of the indirect image vs {ERROR_SOURCES[source]}"),
                             f"{scene_label(scene)}: {report['machine']['renderer']}",
                             os.path.join(folder, f"pareto_{report['sweep']}_{scene_label(scene)}.png")))
    return written


def scaling_fit(xs, ys):
    """Least-squares line ys = intercept + slope · xs, and the exponent of ys ∝ xs^k
    (1 is linear growth)."""
    slope, intercept = np.polyfit(xs, ys, 1)
    exponent = np.polyfit(np.log(xs), np.log(ys), 1)[0] if min(xs) > 0 and min(ys) > 0 else float("nan")
    return float(intercept), float(slope), float(exponent)


def scaling_plots(report, folder):
    """Frame time against triangles, and against light count, per method (and light
    kind), with the fitted line, for the axes the sweep names in `scaling`. Returns
    {plot: fits}."""
    plt = pyplot()
    results = {}
    for axis in report.get("scaling", ()):
        key = SCALING_AXES[axis]
        series = defaultdict(list)
        for point in report["points"]:
            series[(point["method"], point.get("light_kind", ""))].append((key(point), point["timings_ms"]["total_ms"]))
        if not any(len({x for x, _ in values}) > 1 for values in series.values()):
            continue
        figure, axes = plt.subplots(figsize=(6.4, 4.4), dpi=100)
        fits = {}
        for (method, kind), values in sorted(series.items()):
            values.sort()
            xs, ys = np.array([v[0] for v in values], float), np.array([v[1] for v in values], float)
            intercept, slope, exponent = scaling_fit(xs, ys)
            name = f"{method.upper()} {kind}".strip()
            fits[name] = {"intercept_ms": intercept, "slope_ms": slope, "exponent": exponent}
            axes.scatter(xs, ys, s=18, label=f"{name}: {slope:.3g} ms per {axis[:-1]}, exponent {exponent:.2f}")
            axes.plot(xs, intercept + slope * xs, linewidth=1)
        path = save(plt, figure, axes, (axis, "frame ms"), f"{report['sweep']}: {report['machine']['renderer']}",
                     os.path.join(folder, f"scaling_{report['sweep']}_{axis}.png"), legend_size=7)
        results[path] = fits
    return results


def write_sweep_outputs(report, out, command=None, write_json=True):
    """sweep_NAME.json (unless `write_json` is false: the report was read from it), .md
    and the plots, from a sweep report, in the folder `out`."""
    os.makedirs(out, exist_ok=True)
    name = report["sweep"]
    json_path = os.path.join(out, f"sweep_{name}.json")
    if write_json:
        with open(json_path, "w") as handle:
            json.dump(report, handle, indent=1, default=float)
    if pyplot() is None:  # the GPU machine: plot here with --report
        print("bench: no matplotlib here, so no plots; run `bench --report` on the JSON where it is installed",
              file=sys.stderr)
        plots, fits = [], {}
    else:
        plots, fits = pareto_plots(report, out), scaling_plots(report, out)
    with open(os.path.join(out, f"sweep_{name}.md"), "w") as handle:
        handle.write(markdown_report(report, command or report.get("command")))
    return {"json": json_path, "plots": plots + list(fits), "scaling": fits}
