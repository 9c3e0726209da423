"""Command line: `python -m lpv_preview demo | render FILE.blend | compare FILE.blend | export SCENE | bench`.

`demo` builds a built-in scene with bpy and renders it; `render` renders a user's .blend
from its active camera (`--frames 1-24`: an animation, one EXR a frame, resumable);
`compare` measures the methods and their peers (EEVEE, denoised Cycles) against Cycles
references; `export` saves a demo scene as .npz for machines without Blender; `bench`
measures every RSM method against CM (the thesis's Table 1), runs declared sweeps and
writes the benchmarks page.
Each render writes a multi-layer EXR (combined, direct, indirect), tone-mapped PNGs of
combined and indirect, and stats.json. Errors a user can fix print one line, no traceback,
and exit with status 2; Ctrl-C stops a command with one line and status 130.

This file is the command line only: the flags and one short function per command. The
work is in the packages (addon/batch.py, addon/comparison.py, demo/, bench/); bpy and
the GPU are imported by the commands that need them.
"""
import argparse
import json
import os
import sys
import tempfile
import time

from . import demo
from .gpu.errors import LPVError
from .gpu.passes import render_passes
from .gpu.scene_edits import LIGHT_KIND_NAMES
from .gpu.settings import (COMPARISON_PARAMETERS, CORRECTION_PARAMETERS, DISPLAY_PARAMETERS, INDIRECT_METHODS, METHODS,
                           PARAMETERS, PRESETS, ComparisonSettings, CorrectionSettings, describe_preset,
                           preset_settings)

# ---- flags shared by the commands ----


def positive_int(text):
    """An argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number of at least 1")
    return value


def method_list(text, known=METHODS):
    """An argparse type: comma-separated methods of gpu/settings.py, at least one."""
    methods = [method.strip() for method in text.split(",") if method.strip()]
    unknown = [method for method in methods if method not in known]
    if unknown or not methods:
        raise argparse.ArgumentTypeError(f"unknown or no method '{','.join(unknown)}'; choose from "
                                         f"{', '.join(known)}")
    return methods


def lower_first(text):
    """A sentence's first letter in lower case, its names (EEVEE) kept, to follow 'do not'."""
    return text[:1].lower() + text[1:]


def indirect_method_list(text):
    """An argparse type: comma-separated indirect methods of gpu/settings.py, at least one."""
    return method_list(text, INDIRECT_METHODS)


def add_setting_flags(parser):
    """One flag per parameter of gpu/settings.py, defaulting to None (= not given), and
    --preset, whose values the flags given override."""
    parser.add_argument("--preset", choices=tuple(PRESETS), help="start from this preset of gpu/settings.py: "
                        + "; ".join(f"{name}: {describe_preset(name)}" for name in PRESETS))
    for name, field in PARAMETERS.items():
        add_parameter_flag(parser, name, field)


def add_parameter_flag(parser, name, field, flag=None):
    """The flag of one parameter of gpu/settings.py (`flag`: its name, else the parameter's
    with dashes), defaulting to None (= not given), its range and default in its help."""
    meta = field.metadata
    flag = flag or "--" + name.replace("_", "-")
    if field.type in (bool, "bool"):
        parser.add_argument(flag, dest=name, action=argparse.BooleanOptionalAction, default=None,
                            help=meta["description"])
        return
    kind = {"int": int, "float": float, "str": str}.get(field.type, field.type)
    limits = f" ({meta['min']}..{meta['max']}, default {field.default})" if meta["min"] is not None else ""
    parser.add_argument(flag, dest=name, type=kind, default=None, choices=meta["choices"],
                        help=meta["description"] + limits)


def add_debug_passes_flag(parser):
    debug = ", ".join(p.name for p in render_passes(debug=True) if p.debug)
    parser.add_argument("--debug-passes", action="store_true",
                        help=f"{DISPLAY_PARAMETERS['debug_passes'].metadata['description']} (EXR layers {debug})")


def add_correction_flags(parser, scheduler=True):
    """--correct-seconds and --workers (gpu/settings.py CorrectionSettings), and --scheduler
    where the .blend can be shared."""
    for name, flag in (("correct_seconds", "--correct-seconds"), ("correction_workers", "--workers")):
        add_parameter_flag(parser, name, CORRECTION_PARAMETERS[name], flag)
    if scheduler:
        parser.add_argument("--scheduler", help="with --correct-seconds: the tls://HOST:PORT of a Dask scheduler "
                                                "whose workers render the Cycles samples, its certificates in Dask's "
                                                "configuration (README), instead of local workers")


def correction_from(args):
    """The CorrectionSettings the flags give, refused before any work when bad."""
    from .addon.sample_workers import check_scheduler
    scheduler = getattr(args, "scheduler", None)
    given = {name: getattr(args, name) for name in ("correct_seconds", "correction_workers")
             if getattr(args, name) is not None}
    correction = CorrectionSettings(**given)
    if scheduler is not None:
        if correction.correct_seconds <= 0:
            raise LPVError("--scheduler is for the corrections; give --correct-seconds too.")
        if "correction_workers" in given:
            raise LPVError("--workers starts local workers and --scheduler uses a cluster's; give one of them.")
        check_scheduler(scheduler)
    return correction


def settings_from(args, width, height):
    """The settings the flags give (over the preset, if any), `width` x `height` unless given."""
    given = {name: getattr(args, name) for name in PARAMETERS if getattr(args, name) is not None}
    given.setdefault("width", width)
    given.setdefault("height", height)
    return preset_settings(args.preset, **given)


def check_setting_flags(args):
    """Refuse bad setting flags before any work, though the image size may yet come from
    the scene."""
    settings_from(args, PARAMETERS["width"].default, PARAMETERS["height"].default)


def check_writable(folder):
    """Refuse an output folder that cannot be made or written into, before any work: make
    what is missing of it, write a probe file, and remove both again."""
    folder = os.path.abspath(folder)
    made = []  # the folders missing now, the outermost first
    missing = folder
    while not os.path.exists(missing):
        made.insert(0, missing)
        missing = os.path.dirname(missing)
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as error:
        raise LPVError(f"Cannot write into the output folder '{folder}' ({error.strerror}); "
                       f"choose a writable folder.") from None
    finally:
        for path in reversed(made):
            if os.path.isdir(path):
                os.rmdir(path)


def settings_for_blend(bpy_scene, args):
    """The flags' settings, the image size from the .blend's render resolution unless given."""
    from .addon.extract import render_resolution
    return settings_from(args, *render_resolution(bpy_scene))


def pass_names(args):
    """The pipeline passes a command writes: ours, and the debug ones with --debug-passes."""
    return tuple(p.name for p in render_passes(args.debug_passes))


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


def command_line(args):
    return "python -m lpv_preview " + " ".join(args.argv)


# ---- the commands ----


def command_demo(args):
    from .addon.batch import render_to_files
    check_writable(args.out)
    check_setting_flags(args)
    correction = correction_from(args)
    start = time.perf_counter()
    bpy_scene = demo.build(args.scene, **({"triangles": args.triangles} if args.triangles is not None else {}))
    build_ms = (time.perf_counter() - start) * 1000
    stats = render_to_files(bpy_scene, settings_for_blend(bpy_scene, args), pass_names(args), args.out,
                            {"scene": args.scene, "build_ms": build_ms}, correction)
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def command_render(args):
    from .addon.batch import open_blend, render_animation, render_to_files
    frames = parse_frames(args.frames) if args.frames else None
    check_writable(args.out)
    check_setting_flags(args)
    correction = correction_from(args)
    start = time.perf_counter()
    bpy_scene = open_blend(args.file)
    settings, file = settings_for_blend(bpy_scene, args), os.path.abspath(args.file)
    if frames is None:
        stats = render_to_files(bpy_scene, settings, pass_names(args), args.out, {"file": file}, correction, file,
                                args.scheduler)
    else:
        stats = {"file": file, **render_animation(bpy_scene, frames, settings, pass_names(args), args.out,
                                                  args.overwrite, correction, file, args.scheduler)}
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def check_methods_fit(bpy_scene, settings, methods, indirect_methods):
    """Refuse, before any Cycles reference is rendered, a comparison whose frames our
    renderer cannot make here (no OpenGL 4.5, too large for the driver or the memory)."""
    from .addon.render_scene import scene_to_render
    from .gpu.capacity import check_frame_fits
    from .gpu.context import GLContext
    glc = GLContext.shared()
    scene = scene_to_render(bpy_scene, (settings.width, settings.height))
    for method in methods:
        for indirect in indirect_methods:
            check_frame_fits(glc, settings.with_changes(method=method, indirect_method=indirect), scene)


def command_compare(args):
    """Cycles references and each method's errors against them, written to args.out;
    every step, part of a Cycles render and the references' estimated time on stderr."""
    from .addon.batch import open_blend
    from .addon.comparison import comparison_steps, write_report
    from .addon.cycles_reference import run_to_end
    from .addon.cycles_reference import ReferenceCache
    check_writable(args.out)
    check_setting_flags(args)
    start = time.perf_counter()
    if args.file in demo.SCENES:
        bpy_scene = demo.build(args.file)
    elif not os.path.isfile(args.file):
        raise LPVError(f"There is no file '{args.file}'; give the path of a .blend file or a demo scene name "
                       f"({', '.join(demo.SCENES)}).")
    else:
        bpy_scene = open_blend(args.file)
    settings = settings_for_blend(bpy_scene, args)
    # --indirect-method alone compares that one; else the list (default every one).
    indirect_methods = args.indirect_methods or ([args.indirect_method] if args.indirect_method
                                                 else ComparisonSettings().indirect_methods)
    check_methods_fit(bpy_scene, settings, args.methods, indirect_methods)
    cache = None if args.no_cache else ReferenceCache(args.cache)
    steps = comparison_steps(bpy_scene, args.methods, args.samples, settings, cache,
                             noise_floor=not args.no_noise_floor, indirect_methods=indirect_methods,
                             peers=not args.no_peers)
    progress = lambda step: print(f"[{time.perf_counter() - start:5.0f} s {step[0]:4.0%}] {step[1]}", file=sys.stderr,
                                  flush=True)
    rows = write_report(run_to_end(steps, progress), args.out)
    return {"rows": rows, "out": os.path.abspath(args.out), "command_ms": (time.perf_counter() - start) * 1000}


def command_export(args):
    from .gpu.scene_file import cycles_reference_path
    if args.cycles_width and not args.cycles_samples:
        raise LPVError("--cycles-width needs --cycles-samples: the Cycles reference is rendered only when asked.")
    check_writable(os.path.dirname(args.out))
    options = {key: value for key, value in (("triangles", args.triangles), ("lights", args.lights),
                                             ("light_kind", args.light_kind), ("cycles_samples", args.cycles_samples),
                                             ("cycles_width", args.cycles_width)) if value is not None}
    scene = demo.export_npz(args.scene, args.out, **options)
    return {"scene": args.scene, "file": args.out, "triangles": scene.triangle_count, "lights": len(scene.lights),
            **({"cycles_reference": str(cycles_reference_path(args.out))} if args.cycles_samples else {})}


def bench_scene(item):
    """A bench scene: an .npz scene file (no Blender needed) or a demo scene built with bpy."""
    from .gpu.scene_file import load_scene
    return load_scene(item) if item.endswith(".npz") else demo.extracted(item)


def check_bench_scenes(items):
    """Refuse a bench scene that is neither a demo scene nor an .npz scene file there is."""
    for item in items:
        if item not in demo.SCENES and not (item.endswith(".npz") and os.path.isfile(item)):
            raise LPVError(f"The bench scene '{item}' is neither a demo scene ({', '.join(demo.SCENES)}) nor an "
                           f".npz scene file that exists; check --scenes.")


def bench_cycles_indirect(item, samples, width, height):
    """A sweep scene's Cycles one-bounce indirect image and its samples: an .npz file's
    stored beside it (None if not), a demo scene's rendered (cached) `width` pixels
    across at the scene's own aspect (its camera was extracted at that aspect)."""
    if item.endswith(".npz"):
        from .gpu.scene_file import stored_cycles_indirect
        return stored_cycles_indirect(item)
    return demo.cycles_indirect(demo.build(item), samples, width), samples


def blender_available():
    """Whether bpy can be imported here (not on the GPU machine)."""
    import importlib.util
    return importlib.util.find_spec("bpy") is not None


EMITTER_CYCLES_COUNTS = (1024, 16384)
EMITTER_CYCLES_SIZE = (160, 120)
EMITTER_CYCLES_SAMPLES = 256


def particle_cases(counts, width, height, samples):
    """(count, Scene, Cycles' direct image) of the particles demo scene for each count."""
    from .addon.cycles_reference import ReferenceCache, cycles_reference
    from .addon.render_scene import scene_to_render
    for count in counts:
        bpy_scene = demo.build("particles", particles=count, resolution=(width, height))
        reference = cycles_reference(bpy_scene, "one_bounce", samples, 0, (width, height), ReferenceCache())
        yield count, scene_to_render(bpy_scene, (width, height)), reference.direct


SAMPLE_BENCH_SIZE = (128, 128)


def bench_sample_workers(args, log):
    """Cycles sample requests' fixed and per-sample cost, and the workers' scaling, on the
    Cornell box (bench/sample_rates.py), into sample_workers.json and .md."""
    import platform

    import bpy

    from .addon.cycles_samples import SampleRenderer
    from .addon.sample_workers import SampleRequest, SampleWorkers
    from .bench.sample_rates import request_costs, worker_scaling, write_sample_report
    with tempfile.TemporaryDirectory(prefix="lpv_samples_") as folder:
        blend = os.path.join(folder, "cornell.blend")
        demo.build("cornell", resolution=SAMPLE_BENCH_SIZE)
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        renderer = SampleRenderer(blend)
        try:
            costs = request_costs(renderer.render, SampleRequest, SAMPLE_BENCH_SIZE, log=log)
        finally:
            renderer.close()
        scaling = worker_scaling(lambda count: SampleWorkers(blend, workers=count), SampleRequest, SAMPLE_BENCH_SIZE,
                                 log=log)
    report = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPU cores",
              "scene": "Cornell box", "resolution": list(SAMPLE_BENCH_SIZE), "costs": costs, "scaling": scaling,
              "command": command_line(args)}
    return write_sample_report(report, args.out)


def bench_corrections(args, log):
    """The corrected preview against Cycles progressive and denoised over time, on the demo
    scenes lit by lamps (bench/corrections.py), into corrections.json, .md and plots."""
    import platform

    from .addon.correction_runs import measure_scene
    from .bench import corrections
    gpu = corrections.read_gpu_previews(args.gpu_previews) if args.gpu_previews else {}
    cores = os.cpu_count()
    scenes = []
    with tempfile.TemporaryDirectory(prefix="lpv_corrections_") as folder:
        for name, size in corrections.SCENES.items():
            runs = measure_scene(name, lambda: demo.build(name, resolution=size), settings_from(args, *size),
                                 corrections.REFERENCE_SAMPLES, os.path.join(folder, f"{name}.blend"), cores,
                                 corrections.TIMING, log)
            scenes.append(corrections.scene_report(name, runs, corrections.REFERENCE_SAMPLES, gpu.get(name)))
            log(json.dumps({key: scenes[-1][key] for key in ("name", "preview_error", "goals", "turn")}))
    report = {"machine": f"{platform.processor() or platform.machine()}, {cores} CPU cores", "cores": cores,
              "workers": cores, "reference_samples": corrections.REFERENCE_SAMPLES, "scenes": scenes,
              "command": command_line(args)}
    return corrections.write_correction_report(report, args.out)


def command_bench(args):
    """Table 1 on demo scenes (built with bpy) or .npz scene files (no Blender needed),
    a declared sweep (--sweep), the outputs of a sweep report again (--report), or the
    benchmarks page from every report (--page)."""
    log = lambda line: print(line, file=sys.stderr, flush=True)
    if args.report:
        from .bench.sweep_report import read_report, write_sweep_outputs
        check_writable(args.out)
        same_folder = os.path.abspath(args.out) == os.path.abspath(os.path.dirname(args.report))
        return write_sweep_outputs(read_report(args.report), args.out, write_json=not same_folder)
    if args.page:
        from .bench.page import write_benchmarks_page
        check_writable(os.path.dirname(args.page))
        return write_benchmarks_page(args.page)
    if args.invariance:
        from .bench.invariance import measure_invariances, write_invariances
        check_writable(args.out)
        return write_invariances(measure_invariances(log=log), args.out, command_line(args))
    if args.sample_workers:
        check_writable(args.out)
        return bench_sample_workers(args, log)
    if args.corrections:
        check_setting_flags(args)
        if args.width is not None or args.height is not None:
            raise LPVError("bench --corrections renders each demo scene at its own size (bench/corrections.py "
                           "SCENES); leave out --width and --height.")
        check_writable(args.out)
        return bench_corrections(args, log)
    if args.emitters:
        from .bench.emitters import (emitter_bench_size, measure_against_cycles, measure_emitter_counts,
                                     measure_many_lights, write_emitter_report)
        check_writable(args.out)
        counts = tuple(4 ** k for k in range(args.emitters_up_to + 1))
        width, height = emitter_bench_size()
        report = {"counts": [measure_emitter_counts(counts, width, height, resolution, log=log)
                             for resolution in (32, 64)],
                  "lights": measure_many_lights(log=log), "command": command_line(args)}
        if blender_available():
            report["cycles"] = {**measure_against_cycles(particle_cases(EMITTER_CYCLES_COUNTS, *EMITTER_CYCLES_SIZE,
                                                                        EMITTER_CYCLES_SAMPLES),
                                                         *EMITTER_CYCLES_SIZE, log=log),
                                "samples": EMITTER_CYCLES_SAMPLES}
        return write_emitter_report(report, args.out)
    if args.fuzz:
        from .bench.fuzz import fuzz
        report = fuzz(range(args.fuzz), log=log)
        if report["failures"]:
            raise LPVError(f"{len(report['failures'])} of {args.fuzz} fuzzed scenes failed, the first with seed "
                           f"{report['failures'][0]['seed']}: {report['failures'][0]['detail'].splitlines()[-1]}")
        return report
    if args.sweep:
        from .bench.sweep import SWEEPS_FILE, load_sweep, run_sweep
        from .bench.sweep_report import write_sweep_outputs
        check_writable(args.out)
        sweep = load_sweep(args.sweep, args.sweeps or SWEEPS_FILE)
        report = run_sweep(args.sweep, sweep, bench_scene, log=log, cycles_indirect=bench_cycles_indirect)
        report["command"] = command_line(args)
        return {**write_sweep_outputs(report, args.out), "points": len(report["points"]),
                "seconds": report["seconds"]}
    from .bench.sweep_report import scene_label
    from .bench.table1 import BUDGETS, run_table1, write_table1
    check_writable(args.out)
    check_bench_scenes(args.scenes.split(","))
    scenes = [(scene_label(item), lambda item=item: bench_scene(item)) for item in args.scenes.split(",")]
    budgets = BUDGETS if args.budget == "both" else (args.budget,)
    report = run_table1(scenes, settings_from(args, 960, 540), args.methods, args.frames, args.repeats, budgets,
                        command_line(args), log)
    write_table1(report, args.out)
    return {"out": args.out, "scenes": len(scenes), "methods": list(args.methods), "machine": report["machine"]}


def build_parser():
    from .bench.table1 import BUDGETS, TABLE1_METHODS
    comparison = ComparisonSettings()
    parser = argparse.ArgumentParser(prog="python -m lpv_preview", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    scene_list = ", ".join(demo.SCENES)
    triangles_help = "triangle count of " + " or ".join(f"the {name} ({low:,}..{high:,})"
                                                        for name, (low, high) in demo.TRIANGLE_RANGES.items())

    command = commands.add_parser("demo", help="build a built-in scene with bpy and render it")
    command.add_argument("--scene", default=demo.SCENES[0], choices=demo.SCENES)
    command.add_argument("--triangles", type=int, help=triangles_help)
    command.add_argument("--out", default="out", help="output folder (default: out)")
    add_setting_flags(command)
    add_debug_passes_flag(command)
    add_correction_flags(command, scheduler=False)  # a demo scene is never saved where a cluster could read it
    command.set_defaults(run=command_demo)

    command = commands.add_parser("render", help="render a .blend file from its active camera")
    command.add_argument("file")
    command.add_argument("--out", default="out", help="output folder (default: out)")
    command.add_argument("--frames", help="render these frames, like 1-24, one EXR each (frame_0001.exr ...)")
    command.add_argument("--overwrite", action="store_true", help="with --frames: render frames already written too")
    add_setting_flags(command)
    add_debug_passes_flag(command)
    add_correction_flags(command)
    command.set_defaults(run=command_render)

    command = commands.add_parser("compare", help="measure the methods and their peers (EEVEE, denoised Cycles) "
                                                  "against Cycles references")
    command.add_argument("file", help=f"a .blend file, or a demo scene name ({scene_list})")
    command.add_argument("--methods", type=method_list, default=comparison.methods,
                         help=f"comma-separated methods (default: {','.join(comparison.methods)})")
    command.add_argument("--samples", type=positive_int, default=comparison.compare_samples,
                         help=f"{COMPARISON_PARAMETERS['compare_samples'].metadata['description']} "
                              f"(default: {comparison.compare_samples})")
    command.add_argument("--out", default="out/compare", help="output folder (default: out/compare)")
    command.add_argument("--cache", help="folder of cached Cycles references (default: ~/.cache/lpv_preview/cycles)")
    command.add_argument("--no-cache", action="store_true", help="render the references even when cached")
    command.add_argument("--no-noise-floor", action="store_true",
                         help=f"do not {COMPARISON_PARAMETERS['compare_noise_floor'].metadata['description'].lower()}")
    command.add_argument("--indirect-methods", type=indirect_method_list,
                         help=f"comma-separated indirect methods, a row each per method (default: "
                              f"{','.join(comparison.indirect_methods)}; only --indirect-method's when that is given)")
    command.add_argument("--no-peers", action="store_true",
                         help="do not " + lower_first(COMPARISON_PARAMETERS["compare_peers"].metadata["description"]))
    add_setting_flags(command)
    command.set_defaults(run=command_compare)

    command = commands.add_parser("export", help="save a demo scene as .npz for machines without Blender")
    command.add_argument("scene", choices=demo.SCENES)
    command.add_argument("--triangles", type=int, help=triangles_help)
    command.add_argument("--out", required=True, help="the .npz file to write")
    command.add_argument("--lights", type=positive_int, help="replace the lights by this many of --light-kind")
    command.add_argument("--light-kind", choices=tuple(LIGHT_KIND_NAMES), default="point")
    command.add_argument("--cycles-samples", type=positive_int,
                         help="also store the Cycles one-bounce indirect image beside it (NAME.cycles.npz) for sweeps")
    command.add_argument("--cycles-width", type=positive_int, help="its width in pixels (default: the scene's)")
    command.set_defaults(run=command_export)

    command = commands.add_parser("bench", help="every RSM method against CM: time, DPM and LPV quality")
    command.add_argument("--scenes", default=",".join(demo.LAMP_SCENES),
                         help=f"comma-separated demo scene names and/or .npz files (default: "
                              f"{','.join(demo.LAMP_SCENES)})")
    command.add_argument("--methods", type=method_list, default=list(TABLE1_METHODS),
                         help=f"comma-separated methods (default: {','.join(TABLE1_METHODS)})")
    command.add_argument("--budget", default=BUDGETS[0], choices=(*BUDGETS, "both"))
    command.add_argument("--frames", type=positive_int, default=5, help="camera-path frames for the LPV quality")
    command.add_argument("--repeats", type=positive_int, default=3, help="timed full frames per method (median)")
    command.add_argument("--out", default="out/bench", help="folder for table1.json and table1.md, or the sweep's files")
    command.add_argument("--sweep", help="run this sweep of bench/sweeps.toml (or --sweeps FILE) instead of Table 1")
    command.add_argument("--sweeps", help="the file of declared sweeps (default: bench/sweeps.toml)")
    command.add_argument("--report", help="write the Markdown and plots of this sweep_NAME.json again")
    command.add_argument("--invariance", action="store_true",
                         help="measure the invariances (translation, grid shift, light frame, scale) per method "
                              "on the closed room (invariance.json and invariance.md in --out)")
    command.add_argument("--sample-workers", action="store_true",
                         help="measure Cycles sample requests (fixed cost, cost a sample) and samples a second with "
                              "1, 2 and 4 Dask workers (sample_workers.json, sample_workers.md)")
    command.add_argument("--corrections", action="store_true",
                         help="the preview corrected toward Cycles by sample workers against Cycles progressive and "
                              "denoised, error over wall time, on the demo scenes lit by lamps (corrections.json, "
                              ".md, plots; minutes, and the references the first time); the setting flags are the "
                              "previews'")
    command.add_argument("--gpu-previews", help="with --corrections: the JSON of scripts/time_previews.py on a GPU "
                                               "(docs/bench/corrections_previews.json), to judge the goals also with "
                                               "the preview rendered there")
    command.add_argument("--emitters", action="store_true",
                         help="measure the emitter grid against the emitter count (1 to 4^N, --emitters-up-to) and "
                              "64 point lights against one (emitters.json, emitters.md)")
    command.add_argument("--emitters-up-to", type=int, default=10, choices=range(11), metavar="N",
                         help="largest emitter count's power of 4 for --emitters (default 10: 1,048,576)")
    command.add_argument("--fuzz", type=positive_int, metavar="N",
                         help="render N seeded random scenes; any that neither renders finite bounded light nor "
                              "stops with one sentence is a failure (exit 2)")
    command.add_argument("--page", help="write this benchmarks page (docs/benchmarks.md) from the reports in the "
                         "folder bench beside it, their tables and plots again too")
    add_setting_flags(command)
    command.set_defaults(run=command_bench)
    return parser


STOPPED = "Stopped by Ctrl-C; temporary files were removed, finished frames and Cycles references are kept."


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(argv)
    args.argv = argv
    try:
        result = args.run(args)
    except LPVError as error:
        print(f"lpv_preview: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"\nlpv_preview: {STOPPED}", file=sys.stderr)
        return 130
    print(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
