"""Per-stage GPU milliseconds of the light side on exported scenes, and GPU memory, as JSON lines.

    python scripts/time_lpv_stages.py DIR [--grid-phases 1 2] [--indirect-methods lpv light_grid]
        [--vpls 1024 2048] [--bounces 1 4]

reads DIR/cornell.npz (1024²), DIR/city130k_point.npz and, where it is there,
DIR/city1200k_point.npz (1920×1080), made with `python -m lpv_preview export` (the
last: `export city --triangles 1200000 --lights 1`), and times every stage redone
(warm-up excluded, no image read back) at each preset, one VPL set a frame, with each
indirect method, VPL count and number of bounces asked for in place of the preset's;
`set_ms` is the median frame of a still view adding another VPL set. It also runs on
an older copy of the package (one without bench/), so two versions compare on one driver.
"""
import argparse
import json
import os

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import PRESETS, Settings

try:
    from lpv_preview.bench.timing import timed_frames
    from lpv_preview.gpu.scene_file import load_scene
except ImportError:  # the version before bench/ and gpu/scene_file.py
    from lpv_preview.gpu.bench import timed_frames
    from lpv_preview.gpu.scene import Scene
    load_scene = Scene.load

CASES = tuple(PRESETS.items())
SCENES = (("cornell", (1024, 1024)), ("city130k_point", (1920, 1080)), ("city1200k_point", (1920, 1080)))
KEYS = ("gpu_rsm_ms", "gpu_warp_ms", "gpu_vpl_ms", "gpu_place_ms", "gpu_inject_ms", "gpu_bounce_ms", "gpu_propagate_ms",
        "gpu_gather_ms", "gpu_gbuffer_ms", "gpu_direct_ms", "gpu_pixel_gather_ms", "gpu_indirect_ms", "total_ms",
        "set_ms")

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("folder")
parser.add_argument("--grid-phases", type=int, nargs="*", default=[], help="time each of these grid_phases")
parser.add_argument("--indirect-methods", nargs="*", default=[], help="time each of these indirect methods")
parser.add_argument("--vpls", type=int, nargs="*", default=[], help="time each of these VPL counts")
parser.add_argument("--bounces", type=int, nargs="*", default=[], help="time each of these numbers of bounces")
args = parser.parse_args()
for scene_name, (width, height) in SCENES:
    if not os.path.exists(f"{args.folder}/{scene_name}.npz"):
        continue
    scene = load_scene(f"{args.folder}/{scene_name}.npz")
    for case, changes in CASES:
        for phases, indirect, vpls, bounces in [(p, m, v, b) for p in args.grid_phases or [None]
                                                for m in args.indirect_methods or [None] for v in args.vpls or [None]
                                                for b in args.bounces or [None]]:
            more = {key: value for key, value in (("grid_phases", phases), ("indirect_method", indirect),
                                                  ("vpls_per_light", vpls), ("bounces", bounces)) if value is not None}
            one_set = {"converge_sets": 1} if "converge_sets" in changes else {}
            settings = Settings(width=width, height=height, **{**changes, **one_set, **more})
            settle = Pipeline(settings)  # the first pipeline after a large one runs slow for its life (H100)
            settle.render(scene, passes=())
            settle.release()
            pipeline = Pipeline(settings)
            try:
                timings, _ = timed_frames(pipeline, scene, 7, passes=())
                held = pipeline.gpu_bytes()
                if hasattr(pipeline, "render_converged"):
                    added = [pipeline.render(scene, passes=(), vpl_set=k, accumulate=True).stats["total_ms"]
                             for k in range(1, 8)]
                    timings["set_ms"] = sorted(added)[len(added) // 2]
            finally:
                pipeline.release()
            print(json.dumps({"scene": scene_name, "triangles": scene.triangle_count, "case": case, **more,
                              **{key: round(timings.get(key, 0.0), 3) for key in KEYS}, "gpu_bytes": held}), flush=True)
