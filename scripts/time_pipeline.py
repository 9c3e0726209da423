"""Times the cube-map pipeline on exported scenes (.npz), without Blender.

    python scripts/time_pipeline.py DIR NAME [NAME ...] [--method cm] [--point-light]

reads DIR/NAME.npz (made with `python -m lpv_preview export`), renders once to warm up
(shader compilation, Poisson cells), then five full frames (every stage redone) and five
camera-only frames (the camera turned a little; RSM, VPLs and LPV reused), each reading
the combined image alone straight into one float buffer, bottom row first, as the
viewport does (`display_into`), and prints the medians and the last
full and camera-only frames' per-stage milliseconds as JSON lines. `python -m
lpv_preview bench` measures the RSM methods against each other instead.
"""
import argparse
import json
import statistics
import time

import numpy as np

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_edits import camera_path, with_lights
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.shade import DISPLAY_CHANNELS

parser = argparse.ArgumentParser(description="whole-frame and camera-only timings of exported scenes")
parser.add_argument("folder")
parser.add_argument("names", nargs="+")
parser.add_argument("--method", default="cm")
parser.add_argument("--point-light", action="store_true", help="replace the lights by one point light (gpu/scene_edits.py)")
args = parser.parse_args()
results = {}
for name in args.names:
    scene = load_scene(f"{args.folder}/{name}.npz")
    if args.point_light:
        scene = with_lights(scene, 1, "point")
    size = (1024, 1024) if name == "cornell" else (1920, 1080)
    p = Pipeline(Settings(width=size[0], height=size[1], rsm_resolution=1024, method=args.method))
    p.render(scene)  # warm-up: shader compilation, Poisson cells
    display = np.empty(size[0] * size[1] * DISPLAY_CHANNELS, dtype=np.float32)
    full, camera = [], []
    cameras = camera_path(scene.camera, 5, degrees=2.0)
    for turned in cameras:
        p.invalidate()
        t = time.perf_counter(); f = p.render(scene, passes=(), display_into=display); full.append((time.perf_counter() - t) * 1000)
        stats = f.stats
        scene.camera = turned
        t = time.perf_counter(); g = p.render(scene, passes=(), display_into=display); camera.append((time.perf_counter() - t) * 1000)
        assert not any(k in g.stats for k in ("rsm_ms", "vpl_ms", "inject_ms", "propagate_ms"))
    finite = bool(np.isfinite(display).all())
    results[name] = {"renderer": p.glc.renderer, "triangles": scene.triangle_count, "full_frame_ms": statistics.median(full),
                     "camera_only_ms": statistics.median(camera),
                     "camera_share": statistics.median(camera) / statistics.median(full), "finite": finite,
                     "stages_ms": {k: round(v, 3) for k, v in stats.items() if k.endswith("_ms")},
                     "camera_stages_ms": {k: round(v, 3) for k, v in g.stats.items() if k.endswith("_ms")},
                     "combined_mean": float(display.mean()),
                     "gbuffer_triangles_per_second": scene.triangle_count / (g.stats["gbuffer_ms"] / 1000)}
    print(name, json.dumps(results[name]), flush=True)
    p.release()
