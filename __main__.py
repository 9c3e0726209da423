"""Command line: `python -m lpv_preview demo | render FILE.blend | compare FILE.blend | export SCENE | bench`.

`demo` builds a built-in scene with bpy and renders it; `render` renders a user's .blend
from its active camera (`--frames 1-24`: an animation, one EXR a frame, resumable);
`compare` measures the methods against Cycles references; `export` saves a demo scene as
.npz for machines without Blender; `bench` measures every RSM method against CM (the
thesis's Table 1).
Each writes a multi-layer EXR (combined, direct, indirect), tone-mapped PNGs of combined
and indirect, and stats.json. Errors a user can fix print one line, no traceback.
"""
import argparse
import json
import os
import sys
import time

from .gpu.errors import LPVError
from .gpu.scene import LIGHT_KINDS
from .gpu.settings import PARAMETERS, PRESETS, describe_preset, preset_settings

SCENE_SIZE_FLAGS = ("width", "height")  # taken from the .blend unless given


def positive_int(text):
    """An argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number of at least 1")
    return value


def add_setting_flags(parser):
    """One flag per parameter of gpu/settings.py, defaulting to None (= not given), and
    --preset, whose values the flags given override."""
    parser.add_argument("--preset", choices=tuple(PRESETS), help="start from this preset of gpu/settings.py: "
                        + "; ".join(f"{name}: {describe_preset(name)}" for name in PRESETS))
    for name, field in PARAMETERS.items():
        meta = field.metadata
        flag = "--" + name.replace("_", "-")
        if field.type in (bool, "bool"):
            parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=None, help=meta["description"])
            continue
        kind = {"int": int, "float": float, "str": str}.get(field.type, field.type)
        limits = f" ({meta['min']}..{meta['max']}, default {field.default})" if meta["min"] is not None else ""
        parser.add_argument(flag, type=kind, default=None, choices=meta["choices"],
                            help=meta["description"] + limits)


def settings_from(args, width, height):
    given = {name: getattr(args, name) for name in PARAMETERS if getattr(args, name) is not None}
    given.setdefault("width", width)
    given.setdefault("height", height)
    return preset_settings(args.preset, **given)


def settings_for_blend(bpy_scene, args):
    """The flags' settings, the image size from the .blend's render resolution unless given."""
    from .addon.extract import render_resolution
    return settings_from(args, *render_resolution(bpy_scene))


def passes_for(args):
    """The pipeline passes a command writes: ours, and the debug ones with --debug-passes."""
    from .gpu.debug_views import DEBUG_PASS_NAMES
    from .gpu.shade import PASS_NAMES
    return PASS_NAMES + (DEBUG_PASS_NAMES if args.debug_passes else ())


def add_debug_passes_flag(parser):
    from .gpu.settings import DISPLAY_PARAMETERS
    parser.add_argument("--debug-passes", action="store_true",
                        help=DISPLAY_PARAMETERS["debug_passes"].metadata["description"] + " (EXR layers vpl_splats, "
                        "warp_status)")


def write_outputs(frame, out_dir, extra_stats):
    """combined/direct/indirect EXR, PNGs of combined and indirect, stats.json."""
    from .gpu.image_io import write_exr, write_png
    write_exr(os.path.join(out_dir, "passes.exr"), frame.passes)
    write_png(os.path.join(out_dir, "combined.png"), frame.passes["combined"])
    write_png(os.path.join(out_dir, "indirect.png"), frame.passes["indirect"])
    stats = {**extra_stats, **frame.stats}
    with open(os.path.join(out_dir, "stats.json"), "w") as handle:
        json.dump(stats, handle, indent=2)
    return stats


def render_bpy_scene(bpy_scene, args, extra_stats):
    """Extract the evaluated scene, render it and write the outputs."""
    import bpy
    from .addon.extract import extract_scene
    from .gpu.pipeline import render_once
    start = time.perf_counter()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    settings = settings_for_blend(bpy_scene, args)
    scene = extract_scene(depsgraph, resolution=(settings.width, settings.height))
    extract_ms = (time.perf_counter() - start) * 1000
    frame = render_once(scene, settings, passes=passes_for(args))
    return write_outputs(frame, args.out, {**extra_stats, "extract_ms": extract_ms})


def command_demo(args):
    from .demo import build
    start = time.perf_counter()
    bpy_scene = build(args.scene, **({"triangles": args.triangles} if args.triangles else {}))
    build_ms = (time.perf_counter() - start) * 1000
    stats = render_bpy_scene(bpy_scene, args, {"scene": args.scene, "build_ms": build_ms})
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def command_render(args):
    import bpy
    if not os.path.isfile(args.file):
        raise LPVError(f"There is no file '{args.file}'; give the path of a .blend file.")
    frames = parse_frames(args.frames) if args.frames else None
    start = time.perf_counter()
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.file))
    except RuntimeError as error:
        raise LPVError(f"Blender cannot open '{args.file}' ({str(error).strip()}); check that it is a .blend file.")
    if frames is not None:
        stats = render_animation(bpy.context.scene, frames, args)
    else:
        stats = render_bpy_scene(bpy.context.scene, args, {"file": os.path.abspath(args.file)})
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def command_compare(args):
    """Cycles references and each method's errors against them, written to args.out."""
    import bpy
    from .addon.comparison import comparison_steps, run_to_end, write_report
    from .addon.cycles_reference import ReferenceCache
    from .demo import SCENES, build
    start = time.perf_counter()
    if args.file in SCENES:
        build(args.file)
    elif not os.path.isfile(args.file):
        raise LPVError(f"There is no file '{args.file}'; give the path of a .blend file or a demo scene name "
                       f"({', '.join(SCENES)}).")
    else:
        try:
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.file))
        except RuntimeError as error:
            raise LPVError(f"Blender cannot open '{args.file}' ({str(error).strip()}); check that it is a .blend file.")
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    cache = None if args.no_cache else ReferenceCache(args.cache)
    steps = comparison_steps(bpy.context.scene, methods, args.samples, settings_for_blend(bpy.context.scene, args),
                             cache, noise_floor=not args.no_noise_floor)
    rows = write_report(run_to_end(steps), args.out)
    return {"rows": rows, "out": os.path.abspath(args.out), "command_ms": (time.perf_counter() - start) * 1000}


def parse_frames(text):
    """'7' or '1-24' as a range of frame numbers."""
    first, _, last = text.partition("-")
    try:
        first, last = int(first), int(last or first)
    except ValueError:
        raise LPVError(f"--frames '{text}' is not a frame or a range; write it like 7 or 1-24.") from None
    if last < first:
        raise LPVError(f"--frames '{text}' ends before it starts; write the first frame first, like 1-24.")
    return range(first, last + 1)


def frame_path(out_dir, frame):
    return os.path.join(out_dir, f"frame_{frame:04d}.exr")


def render_animation(bpy_scene, frames, args):
    """One EXR per frame (combined, direct, indirect) in args.out, with a progress bar.

    Frames whose EXR exists are skipped unless args.overwrite, so a rerun resumes where
    an interrupted one stopped; each EXR is written under a temporary name and renamed
    when complete, so an interrupted frame is never taken for a finished one.
    """
    import bpy
    from .addon.extract import extract_scene
    from .gpu.image_io import write_exr
    from .gpu.pipeline import Pipeline
    settings = settings_for_blend(bpy_scene, args)
    todo = [f for f in frames if args.overwrite or not os.path.exists(frame_path(args.out, f))]
    skipped = len(frames) - len(todo)
    pipeline = Pipeline(settings)
    timings = []
    try:
        for done, frame in enumerate(todo):
            started = time.perf_counter()
            bpy_scene.frame_set(frame)
            scene = extract_scene(bpy.context.evaluated_depsgraph_get(), resolution=(settings.width, settings.height))
            result = pipeline.render(scene, passes=passes_for(args))
            partial = frame_path(args.out, frame) + ".partial.exr"
            write_exr(partial, result.passes)
            os.replace(partial, frame_path(args.out, frame))
            timings.append(time.perf_counter() - started)
            print_progress(done + 1, len(todo), frame, timings)
    finally:
        pipeline.release()
    return {"file": os.path.abspath(args.file), "out": os.path.abspath(args.out), "frames": [frames.start, frames[-1]],
            "rendered": len(todo), "skipped": skipped,
            "seconds_per_frame": sum(timings) / len(timings) if timings else 0.0}


def print_progress(done, total, frame, timings, width=30):
    filled = width * done // total
    left = (total - done) * sum(timings) / len(timings)
    print(f"\rframe {frame} [{'#' * filled}{'.' * (width - filled)}] {done}/{total}, {left:.0f} s left",
          end="\n" if done == total else "", file=sys.stderr, flush=True)


def command_export(args):
    from .demo import export_npz
    from .gpu.sweep import cycles_reference_path
    if args.cycles_width and not args.cycles_samples:
        raise LPVError("--cycles-width needs --cycles-samples: the Cycles reference is rendered only when asked.")
    options = {key: value for key, value in (("triangles", args.triangles), ("lights", args.lights),
                                             ("light_kind", args.light_kind), ("cycles_samples", args.cycles_samples),
                                             ("cycles_width", args.cycles_width)) if value}
    scene = export_npz(args.scene, args.out, **options)
    return {"scene": args.scene, "file": args.out, "triangles": scene.triangle_count, "lights": len(scene.lights),
            **({"cycles_reference": str(cycles_reference_path(args.out))} if args.cycles_samples else {})}


def load_bench_scene(item):
    """A .npz export (no Blender needed) or a demo scene built with bpy."""
    from .gpu.scene import Scene
    if item.endswith(".npz"):
        if not os.path.isfile(item):
            raise LPVError(f"There is no scene file '{item}'; make it with `python -m lpv_preview export`.")
        return Scene.load(item)
    return built_scene(item)


def sweep_cycles_indirect(name, samples, width, height):
    """A sweep scene's Cycles one-bounce indirect image and its samples: a demo scene's
    rendered (cached) `width` pixels across with the scene's own aspect (its camera was
    extracted at that aspect; the sweep measures errors at the image's size), an .npz
    export's stored beside it (None if not)."""
    if name.endswith(".npz"):
        from .gpu.sweep import stored_cycles_indirect
        return stored_cycles_indirect(name)
    from .addon.cycles_reference import ReferenceCache, cycles_reference
    from .addon.extract import render_resolution
    from .demo import build
    bpy_scene = build(name)
    size = render_resolution(bpy_scene, width)
    return cycles_reference(bpy_scene, "one_bounce", samples, 0, size, ReferenceCache()).indirect, samples


def write_sweep_outputs(report, out, command=None, write_json=True):
    """sweep_NAME.json (unless `write_json` is false: the report was read from it), .md
    and the plots, from a sweep report."""
    import importlib.util
    from .gpu.sweep_report import markdown_report, pareto_plots, scaling_plots
    os.makedirs(out, exist_ok=True)
    name = report["sweep"]
    json_path = os.path.join(out, f"sweep_{name}.json")
    if write_json:
        with open(json_path, "w") as handle:
            json.dump(report, handle, indent=1, default=float)
    if importlib.util.find_spec("matplotlib") is None:  # the GPU machine: plot here with --report
        print("bench: no matplotlib here, so no plots; run `bench --report` on the JSON where it is installed",
              file=sys.stderr)
        plots, fits = [], {}
    else:
        plots, fits = pareto_plots(report, out), scaling_plots(report, out)
    with open(os.path.join(out, f"sweep_{name}.md"), "w") as handle:
        handle.write(markdown_report(report, command or report.get("command")))
    return {"json": json_path, "plots": plots + list(fits), "scaling": fits}


def write_benchmarks_page(page):
    """Every sweep report's table and plots beside it again, then the page from them all."""
    from .gpu.benchmarks_page import benchmarks_page, read_reports
    reports = read_reports(page)
    sweeps = [(path, report) for path, report in reports if "sweep" in report]
    if not sweeps:
        raise LPVError(f"There are no sweep reports under {os.path.join(os.path.dirname(page), 'bench')}; run "
                       f"`bench --sweep` first.")
    for path, report in sweeps:
        write_sweep_outputs(report, str(path.parent), write_json=False)
    text = benchmarks_page(page, reports)
    try:
        with open(page, "w") as handle:
            handle.write(text)
    except OSError as error:
        raise LPVError(f"Cannot write the benchmarks page '{page}' ({error.strerror}); choose a writable path.")
    return {"page": page, "reports": [str(path) for path, _ in sweeps]}


def command_bench(args):
    """Table 1 on demo scenes (built with bpy) or exported .npz scenes (no Blender needed),
    a declared sweep (--sweep), the outputs of a sweep report again (--report), or the
    benchmarks page from every report (--page)."""
    if args.report:
        from .gpu.sweep_report import read_report
        report = read_report(args.report)
        return write_sweep_outputs(report, args.out, write_json=os.path.abspath(args.out) != os.path.abspath(
            os.path.dirname(args.report)))
    if args.page:
        return write_benchmarks_page(args.page)
    if args.sweep:
        from .gpu.sweep import SWEEPS_FILE, load_sweep, run_sweep
        sweep = load_sweep(args.sweep, args.sweeps or SWEEPS_FILE)
        report = run_sweep(args.sweep, sweep, load_bench_scene, log=lambda line: print(line, file=sys.stderr),
                           cycles_indirect=sweep_cycles_indirect)
        report["command"] = "python -m lpv_preview " + " ".join(args.argv)
        return {**write_sweep_outputs(report, args.out), "points": len(report["points"]),
                "seconds": report["seconds"]}
    from .gpu.bench import benchmark_scene, markdown_table
    from .gpu.context import GLContext
    from .gpu.scene import Scene
    scenes = []
    for item in args.scenes.split(","):
        if item.endswith(".npz"):
            scenes.append((os.path.splitext(os.path.basename(item))[0], lambda item=item: Scene.load(item)))
        else:
            scenes.append((item, lambda item=item: built_scene(item)))
    methods = tuple(args.methods.split(","))
    budgets = ("equal-resolution", "equal-texel-budget") if args.budget == "both" else (args.budget,)
    settings = settings_from(args, 960, 540)
    results = []
    for name, load in scenes:
        for budget in budgets:
            result = benchmark_scene(name, load(), settings, methods, args.frames, args.repeats, budget)
            results.append(result)
            print(f"bench: {name} ({budget}) done", file=sys.stderr, flush=True)
    glc = GLContext.shared()
    machine = f"{glc.renderer}, OpenGL {glc.version}"
    command = "python -m lpv_preview " + " ".join(args.argv)
    report = {"machine": machine, "command": command, "settings": vars(settings), "results": results}
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "table1.json"), "w") as handle:
        json.dump(report, handle, indent=1, default=float)
    with open(os.path.join(args.out, "table1.md"), "w") as handle:
        handle.write(f"Command: `{report['command']}`\n\n" + markdown_table(results, machine))
    return {"out": args.out, "scenes": len(scenes), "methods": list(methods), "machine": machine}


def built_scene(name):
    """A demo scene built with bpy and extracted (on a machine with Blender)."""
    import bpy
    from .addon.extract import extract_scene
    from .demo import build
    build(name)
    return extract_scene(bpy.context.evaluated_depsgraph_get())


def build_parser():
    parser = argparse.ArgumentParser(prog="python -m lpv_preview", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    demo = commands.add_parser("demo", help="build a built-in scene with bpy and render it")
    demo.add_argument("--scene", default="cornell", choices=("cornell", "atrium", "city"))
    demo.add_argument("--triangles", type=int, help="triangle count of the atrium or the city")
    demo.add_argument("--out", default="out", help="output folder (default: out)")
    add_setting_flags(demo)
    add_debug_passes_flag(demo)
    demo.set_defaults(run=command_demo)
    render = commands.add_parser("render", help="render a .blend file from its active camera")
    render.add_argument("file")
    render.add_argument("--out", default="out", help="output folder (default: out)")
    render.add_argument("--frames", help="render these frames, like 1-24, one EXR each (frame_0001.exr ...)")
    render.add_argument("--overwrite", action="store_true", help="with --frames: render frames already written too")
    add_setting_flags(render)
    add_debug_passes_flag(render)
    render.set_defaults(run=command_render)
    compare = commands.add_parser("compare", help="measure the methods against Cycles references")
    compare.add_argument("file", help="a .blend file, or a demo scene name (cornell, atrium, city)")
    compare.add_argument("--methods", default="cm,wdpm", help="comma-separated methods (default: cm,wdpm)")
    compare.add_argument("--samples", type=positive_int, default=256, help="Cycles samples per pixel (default: 256)")
    compare.add_argument("--out", default="out/compare", help="output folder (default: out/compare)")
    compare.add_argument("--cache", help="folder of cached Cycles references (default: ~/.cache/lpv_preview/cycles)")
    compare.add_argument("--no-cache", action="store_true", help="render the references even when cached")
    compare.add_argument("--no-noise-floor", action="store_true",
                         help="skip the second Cycles render per reference that measures its noise")
    add_setting_flags(compare)
    compare.set_defaults(run=command_compare)
    export = commands.add_parser("export", help="save a demo scene as .npz for machines without Blender")
    export.add_argument("scene", choices=("cornell", "atrium", "city"))
    export.add_argument("--triangles", type=int, help="triangle count of the atrium or the city")
    export.add_argument("--out", required=True, help="the .npz file to write")
    export.add_argument("--lights", type=positive_int, help="replace the lights by this many of --light-kind")
    export.add_argument("--light-kind", choices=[kind.lower() for kind in LIGHT_KINDS], default="point")
    export.add_argument("--cycles-samples", type=positive_int,
                        help="also store the Cycles one-bounce indirect image beside it (NAME.cycles.npz) for sweeps")
    export.add_argument("--cycles-width", type=positive_int, help="its width in pixels (default: the scene's)")
    export.set_defaults(run=command_export)
    bench = commands.add_parser("bench", help="every RSM method against CM: time, DPM and LPV quality")
    bench.add_argument("--scenes", default="cornell,atrium,city",
                       help="comma-separated demo scene names and/or .npz files (default: cornell,atrium,city)")
    bench.add_argument("--methods", default="cm,dpm,wdpm,tdpm,twdpm")
    bench.add_argument("--budget", default="equal-resolution",
                       choices=("equal-resolution", "equal-texel-budget", "both"))
    bench.add_argument("--frames", type=int, default=5, help="camera-path frames for the LPV quality")
    bench.add_argument("--repeats", type=int, default=3, help="timed full frames per method (median)")
    bench.add_argument("--out", default="out/bench", help="folder for table1.json and table1.md, or the sweep's files")
    bench.add_argument("--sweep", help="run this sweep of gpu/sweeps.toml (or --sweeps FILE) instead of Table 1")
    bench.add_argument("--sweeps", help="the file of declared sweeps (default: gpu/sweeps.toml)")
    bench.add_argument("--report", help="write the Markdown and plots of this sweep_NAME.json again")
    bench.add_argument("--page", help="write this benchmarks page (docs/benchmarks.md) from the reports in the "
                       "folder bench beside it, their tables and plots again too")
    add_setting_flags(bench)
    bench.set_defaults(run=command_bench)
    return parser


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(argv)
    args.argv = argv
    try:
        result = args.run(args)
    except LPVError as error:
        print(f"lpv_preview: {error}", file=sys.stderr)
        return 2
    print(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
