"""How the indirect light converges toward Cycles as a still frame averages VPL sets, as
JSON lines on stdout: per scene, method, bounces and singularity bound, the PSNR, relative
MSE and mean ratio of our indirect image against Cycles' after 1, 2, 4, ... sets, with the
time all the sets took from a frame with every stage redone (wall clock, GPU work
finished) and the last set's frame time (a still view's: VPLs, indirect stage, gather).

    python scripts/convergence.py DIR [--sets 64] [--scale 1] [--methods vpl_gather,light_grid]
        [--scenes cornell,...] [--vpls 2048] [--bounds 1,0] [--bounces 4]

DIR holds NAME.npz scenes with NAME.cycles.npz references (`python -m lpv_preview export
... --cycles-samples N`, scripts/leak_figures.py --export): one bounce against `indirect`,
--bounces bounces against `full_gi_indirect`. With --scale K our image is K times the
reference's size, compared at the reference's pixel centres (the Cornell box at 1024²
against 256²). With
bounds 0 and 1 (the default) the difference of their converged means is the bias of
bounding the VPLs' 1/r² (settings.py singularity_bound).
"""
import argparse
import json
import os
import time

import numpy as np

from lpv_preview.gpu.metrics import psnr, relative_mse
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import cycles_reference_path, load_scene
from lpv_preview.gpu.settings import Settings


BLACK = 1e-6  # a reference mean below this is Cycles' zero


def at_reference_pixels(image, factor):
    """Our image, `factor` times the reference's size, at the reference's pixel centres
    (the reference is sampled there: a 0.01 px filter): the middle pixel of each block,
    or the mean of the middle four for an even factor."""
    height, width = image.shape[0] // factor, image.shape[1] // factor
    blocks = image.reshape(height, factor, width, factor, 3)
    middle = slice(factor // 2 - 1, factor // 2 + 1) if factor % 2 == 0 else slice(factor // 2, factor // 2 + 1)
    return blocks[:, middle, :, middle].mean(axis=(1, 3))


def converge(pipeline, scene, settings, sets, target, factor):
    """Figures after 1, 2, 4, ... VPL sets (and the last) of one still frame."""
    rows, spent = [], 0.0
    for k in range(sets):
        start = time.perf_counter()
        frame = pipeline.render(scene, settings, vpl_set=k, accumulate=k > 0, passes=())
        spent += time.perf_counter() - start
        if k & (k + 1) == 0 or k == sets - 1:
            image = at_reference_pixels(pipeline.targets.read("indirect"), factor)
            rows.append({"sets": k + 1, "seconds": round(spent, 4), "frame_ms": round(frame.stats["total_ms"], 2),
                         "psnr": round(psnr(image, target), 2), "relative_mse": round(relative_mse(image, target), 4),
                         "mean_ratio": round(float(image.mean() / target.mean()), 4)})
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("--sets", type=int, default=64)
    parser.add_argument("--scale", type=int, default=1)
    parser.add_argument("--methods", default="vpl_gather,light_grid")
    parser.add_argument("--scenes", default=None, help="names in the folder (default: every one with references)")
    parser.add_argument("--vpls", type=int, default=2048)
    parser.add_argument("--bounds", default="1,0")
    parser.add_argument("--bounces", type=int, default=4, help="bounces against the full-GI reference")
    args = parser.parse_args()
    names = args.scenes.split(",") if args.scenes else sorted(
        entry[:-len(".cycles.npz")] for entry in os.listdir(args.folder) if entry.endswith(".cycles.npz"))
    pipeline = Pipeline()
    try:
        for name in names:
            scene = load_scene(os.path.join(args.folder, f"{name}.npz"))
            with np.load(cycles_reference_path(os.path.join(args.folder, f"{name}.npz"))) as stored:
                references = {1: stored["indirect"]}
                if "full_gi_indirect" in stored and args.bounces > 1:
                    references[args.bounces] = stored["full_gi_indirect"]
            if references[1].mean() < BLACK:
                continue  # no indirect light to converge to (scripts/leak_figures.py measures the leak)
            height, width = references[1].shape[:2]
            for method in args.methods.split(","):
                for bounces, target in references.items():
                    for bound in (float(b) for b in args.bounds.split(",")):
                        if bound != 1.0 and bounces > 1:
                            continue
                        settings = Settings(width=width * args.scale, height=height * args.scale, method="auto",
                                            rsm_resolution=256, vpls_per_light=args.vpls, indirect_method=method,
                                            bounces=bounces, singularity_bound=bound)
                        pipeline.render(scene, settings, passes=())  # shaders compiled, Poisson sets made
                        pipeline.invalidate()
                        rows = converge(pipeline, scene, settings, args.sets, target, args.scale)
                        print(json.dumps({"scene": name, "size": [width * args.scale, height * args.scale],
                                          "method": method, "bounces": bounces, "singularity_bound": bound,
                                          "vpls": args.vpls, "gpu_mb": round(pipeline.gpu_bytes() / 2 ** 20, 1),
                                          "renderer": pipeline.glc.renderer, "rows": rows}), flush=True)
    finally:
        pipeline.release()


if __name__ == "__main__":
    main()
