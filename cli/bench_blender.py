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
