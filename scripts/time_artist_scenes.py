"""Times our frames of the exported artist-scene suite on this machine's GPU, without Blender.

    python -m lpv_preview export hdri_product --out DIR/hdri_product.npz   # each scene, where Blender is
    python scripts/time_artist_scenes.py DIR [--width 1920 --height 1080] [--frames 20] > gpu_times.json

reads every DIR/NAME.npz of the suite (demo/artist/ ARTIST_SCENES) there is, renders
each once to warm up (shaders, Poisson cells), then times `--frames` full frames (every
stage redone) of one VPL set and of a converged frame (bench/artist.py CONVERGE_SETS
sets), and prints their medians, least and most as JSON. Where the Scene holds a world,
the world's cost is the median frame whose world only shows (world_samples 0)
subtracted from the median frame; otherwise it is null. `bench --artist --gpu-times FILE` judges the time
goals with this file.
"""
import argparse
import json
import os
import statistics
import time

from lpv_preview.bench.artist import CONVERGE_SETS
from lpv_preview.demo.artist import ARTIST_SCENES
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings


def timed_ms(pipeline, scene, settings, frames):
    """The median, least and most of `frames` full frames' milliseconds, every stage redone
    each time."""
    pipeline.render_converged(scene, settings, passes=())  # warm-up
    times = []
    for _ in range(frames):
        pipeline.invalidate()
        started = time.perf_counter()
        pipeline.render_converged(scene, settings, passes=())
        pipeline.glc.gl.finish()
        times.append((time.perf_counter() - started) * 1000)
    return {"median": statistics.median(times), "min": min(times), "max": max(times)}


def time_scene(path, width, height, frames):
    scene = load_scene(path)
    one = Settings(width=width, height=height)
    converged = one.with_changes(converge_sets=CONVERGE_SETS)
    pipeline = Pipeline(one)
    try:
        one_ms = timed_ms(pipeline, scene, one, frames)
        converged_ms = timed_ms(pipeline, scene, converged, frames)
        world_ms = None
        if scene.world is not None:  # the world's light: the frame against one whose world only shows
            unlit = timed_ms(pipeline, scene, one.with_changes(world_samples=0), frames)
            world_ms = one_ms["median"] - unlit["median"]
        return {"one_frame_ms": one_ms, "converged_ms": converged_ms, "converge_sets": CONVERGE_SETS,
                "world_ms": world_ms, "frames": frames, "triangles": scene.triangle_count}
    finally:
        pipeline.release()


def main():
    parser = argparse.ArgumentParser(description="our frame times of the exported artist scenes")
    parser.add_argument("folder", help="the folder of NAME.npz files (python -m lpv_preview export NAME)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--frames", type=int, default=20, help="timed frames per median")
    args = parser.parse_args()
    from lpv_preview.gpu.context import GLContext
    glc = GLContext.shared()
    scenes = {}
    for name in ARTIST_SCENES:
        path = os.path.join(args.folder, f"{name}.npz")
        if os.path.isfile(path):
            scenes[name] = time_scene(path, args.width, args.height, args.frames)
    if not scenes:
        parser.error(f"no artist scene file in '{args.folder}'; export them with python -m lpv_preview export NAME")
    print(json.dumps({"renderer": glc.renderer, "width": args.width, "height": args.height, "scenes": scenes},
                     indent=1))


if __name__ == "__main__":
    main()
