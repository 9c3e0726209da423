"""Times the cube-map pipeline on exported scenes (.npz), without Blender.

    python scripts/time_pipeline.py DIR NAME [NAME ...]

reads DIR/NAME.npz (made with `python -m lpv_preview export`), renders once to warm up
(shader compilation, Poisson cells), then five full frames (every stage redone) and five
camera-only frames (RSM, VPLs and LPV reused), and prints the medians and the last full
frame's per-stage milliseconds as JSON lines: the whole-frame cost with readback at the
default settings, the figures of docs/benchmarks.md's first table. `python -m
lpv_preview bench` measures the RSM methods against each other instead.
"""
import json
import statistics
import sys
import time

import numpy as np

from lpv_preview.gpu.scene import Scene
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings
results = {}
folder = sys.argv[1]
for name in sys.argv[2:]:
    scene = Scene.load(f"{folder}/{name}.npz")
    size = (1024, 1024) if name == "cornell" else (1920, 1080)
    p = Pipeline(Settings(width=size[0], height=size[1], rsm_resolution=1024))
    p.render(scene)  # warm-up: shader compilation, Poisson cells
    full, camera = [], []
    for i in range(5):
        p.invalidate()
        t = time.perf_counter(); f = p.render(scene); full.append((time.perf_counter() - t) * 1000)
        stats = f.stats
        t = time.perf_counter(); g = p.render(scene); camera.append((time.perf_counter() - t) * 1000)
    finite = all(np.isfinite(v).all() for v in f.passes.values())
    results[name] = {"renderer": p.glc.renderer, "triangles": scene.triangle_count, "full_frame_ms": statistics.median(full),
                     "camera_only_ms": statistics.median(camera), "finite": finite,
                     "stages_ms": {k: round(v, 3) for k, v in stats.items() if k.endswith("_ms")},
                     "indirect_mean": float(f.passes["indirect"].mean())}
    print(name, json.dumps(results[name]), flush=True)
    p.release()
