"""What the benchmarks need of Blender: demo scenes built and extracted with bpy, their
Cycles references, the Cycles sample workers and the corrections' timelines. bench/
never imports bpy; the command hands it these."""
import json
import os
import tempfile

from .. import demo
from ..gpu.errors import LPVError
from .flags import command_line, settings_from


def bench_scene(item):
    """A bench scene: an .npz scene file (no Blender needed) or a demo scene built with bpy."""
    from ..gpu.scene_file import load_scene
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
        from ..gpu.scene_file import stored_cycles_indirect
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
    from ..addon.cycles_reference import ReferenceCache, cycles_reference
    from ..addon.render_scene import scene_to_render
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

    from ..addon.cycles_samples import SampleRenderer
    from ..addon.sample_renderer import open_sample_renderer
    from ..bench.sample_rates import request_costs, worker_scaling, write_sample_report
    from ..corrections.sample_request import SampleRequest
    from ..corrections.sample_workers import SampleWorkers
    with tempfile.TemporaryDirectory(prefix="lpv_samples_") as folder:
        blend = os.path.join(folder, "cornell.blend")
        demo.build("cornell", resolution=SAMPLE_BENCH_SIZE)
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        renderer = SampleRenderer(blend)
        try:
            costs = request_costs(renderer.render, SampleRequest, SAMPLE_BENCH_SIZE, log=log)
        finally:
            renderer.close()
        scaling = worker_scaling(lambda count: SampleWorkers(blend, open_sample_renderer, workers=count), SampleRequest,
                                 SAMPLE_BENCH_SIZE, log=log)
    report = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPU cores",
              "scene": "Cornell box", "resolution": list(SAMPLE_BENCH_SIZE), "costs": costs, "scaling": scaling,
              "command": command_line(args)}
    return write_sample_report(report, args.out)


def bench_corrections(args, log):
    """The corrected preview against Cycles progressive and denoised over time, on the demo
    scenes lit by lamps (bench/corrections.py), into corrections.json, .md and plots."""
    import platform

    from ..bench import corrections
    from .correction_runs import measure_scene
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


ARTIST_SIZE = (160, 90)
ARTIST_SAMPLES = 1024
"""The artist suite's image size and Cycles samples unless --width and --samples say otherwise."""


def artist_scene_names(text):
    """The artist scenes --scenes names (None: the whole suite), refused when unknown."""
    names = demo.ARTIST_SCENES if text is None else tuple(text.split(","))
    unknown = [name for name in names if name not in demo.ARTIST_SCENES]
    if unknown:
        raise LPVError(f"'{unknown[0]}' is not an artist scene; bench --artist takes "
                       f"{', '.join(demo.ARTIST_SCENES)}.")
    return names


def bench_artist(args, log):
    """The artist-scene suite against Cycles' Combined: one frame of ours, our converged
    frame, EEVEE and Cycles at 1 sample with OpenImageDenoise per scene (bench/artist.py),
    into artist.json and artist.md."""
    import platform
    import time
    from dataclasses import asdict

    from ..addon.combined_renders import cycles_combined, cycles_denoised_combined, eevee_combined
    from ..addon.render_scene import scene_to_render
    from ..bench import artist
    from ..gpu.context import GLContext
    from ..gpu.pipeline import render_once
    names = artist_scene_names(args.scenes)
    width = args.width or ARTIST_SIZE[0]
    size = (width, args.height or max(1, round(width * ARTIST_SIZE[1] / ARTIST_SIZE[0])))
    samples = args.samples or ARTIST_SAMPLES
    settings = settings_from(args, *size)
    sets = args.converge_sets or artist.CONVERGE_SETS  # the converged frame's; one frame is one set
    gpu = artist.read_gpu_times(args.gpu_times) if args.gpu_times else None
    scenes = []
    for name in names:
        bpy_scene = demo.build(name, resolution=size)
        log(f"{name}: Cycles at {samples} samples, {size[0]}×{size[1]}")
        reference, reference_settings = cycles_combined(bpy_scene, samples, size)
        renders = {}
        try:
            content = scene_to_render(bpy_scene, size)
            for key, changes in (("ours_one_frame", {"converge_sets": 1}), ("ours_converged", {"converge_sets": sets})):
                started = time.perf_counter()
                frame = render_once(content, settings.with_changes(**changes), passes=("combined",))
                renders[key] = artist.render_row(frame.passes["combined"][..., :3], reference,
                                                 time.perf_counter() - started, changes)
        except LPVError as error:
            renders = dict.fromkeys(("ours_one_frame", "ours_converged"), artist.missing_row(str(error)))
        log(f"{name}: EEVEE")
        image, eevee_settings = eevee_combined(bpy_scene, size, args.eevee_samples)
        renders["eevee"] = artist.render_row(image, reference, eevee_settings["render_seconds"], eevee_settings)
        log(f"{name}: Cycles 1 sample + OpenImageDenoise")
        try:
            image, denoised_settings = cycles_denoised_combined(bpy_scene, 1, size)
            renders["cycles_denoised"] = artist.render_row(image, reference, denoised_settings["render_seconds"],
                                                           denoised_settings)
        except LPVError as error:
            renders["cycles_denoised"] = artist.missing_row(str(error))
        scene = {"name": name, "cycles": reference_settings, "renders": renders}
        scene["goals"] = artist.scene_goals(scene, (gpu or {}).get("scenes", {}).get(name))
        log(json.dumps({"name": name, **{key: row["figures"] for key, row in renders.items()}}))
        scenes.append(scene)
    glc = GLContext.last_made or GLContext.shared()
    report = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPU cores",
              "renderer": glc.renderer, "resolution": list(size), "cycles_samples": samples,
              "converge_sets": sets, "settings": asdict(settings), "scenes": scenes,
              "gpu_times": gpu, "command": command_line(args)}
    return artist.write_artist_report(report, args.out)
