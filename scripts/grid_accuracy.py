"""Indirect light of exported scenes against the Cycles one bounce stored beside them, for
each indirect method, grid size and number of grid phases, as JSON lines.

    python scripts/grid_accuracy.py DIR

reads DIR/cornell.npz, DIR/atrium_point.npz and DIR/city130k_point.npz with their
.cycles.npz references (`python -m lpv_preview export ... --cycles-samples 512`), renders
each at its reference's size (the Cornell box also at half of it) and prints PSNR,
relative MSE and the ratio of our indirect mean to Cycles'.
"""
import json
import sys

import numpy as np

from lpv_preview.gpu.metrics import psnr, relative_mse
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings

CASES = [{"indirect_method": method, "lpv_resolution": size, "grid_phases": phases}
         for method in INDIRECT_METHODS for size in (16, 24, 32) for phases in (1, 2)]

folder = sys.argv[1]
for name in ("cornell", "atrium_point", "city130k_point"):
    reference = np.load(f"{folder}/{name}.cycles.npz")["indirect"]
    height, width = reference.shape[:2]
    scene = load_scene(f"{folder}/{name}.npz")
    sizes = [(width, height)] + ([(width // 2, height // 2)] if name == "cornell" else [])
    for case in CASES:
        for size in sizes:
            frame = render_once(scene, Settings(width=size[0], height=size[1], **case))
            image = frame.passes["indirect"]
            factor = width // size[0]
            target = reference.reshape(size[1], factor, size[0], factor, 3).mean(axis=(1, 3))
            print(json.dumps({"scene": name, "size": size, **case, "psnr": round(psnr(image, target), 2),
                              "relative_mse": round(relative_mse(image, target), 4),
                              "mean_ratio": round(float(image.mean() / target.mean()), 3),
                              "levels": frame.stats["grid_levels"], "cell": frame.stats["lpv_cell_size"]}),
                  flush=True)
