"""What the light of surfaces' own features costs (soft shadows, highlights and
reflections, cut-outs and glass): exported scenes rendered as they are and with each
feature taken out, without Blender.

    python scripts/time_surface_light.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and times
one-set 1920×1080 frames with every stage redone, for the scene as it is ("all"), with
every light's size 0 (hard shadows), with no glossy surface (no highlights, no
reflections), and with none of these nor cut-outs or glass ("none"). It prints per scene
and case the median frame's wall milliseconds, its least and most, and the median
direct stage (`direct_ms`: shadows and highlights) and composite (`indirect_ms`: the
reflections), as JSON; "all" less "none" is what the features cost.
"""
import argparse
import dataclasses
import json
import statistics
import time

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings


def cases(scene):
    """The scene and its variants, by name."""
    hard = [dataclasses.replace(light, radius=0.0, size=(0.0, 0.0), angle=0.0) for light in scene.lights]
    return {"all": scene, "sizes 0": dataclasses.replace(scene, lights=hard),
            "no gloss": dataclasses.replace(scene, specular=None),
            "none": dataclasses.replace(scene, lights=hard, specular=None, alpha=None, alpha_layers=None,
                                        transmission=None)}


def timed(shown, frames):
    pipeline = Pipeline(Settings(width=1920, height=1080))
    try:
        pipeline.render(shown, passes=())  # warm-up
        times, direct, composite = [], [], []
        for _ in range(frames):
            pipeline.invalidate()
            pipeline.glc.gl.finish()
            started = time.perf_counter()
            frame = pipeline.render(shown, passes=())
            pipeline.glc.gl.finish()
            times.append((time.perf_counter() - started) * 1000)
            direct.append(frame.stats.get("direct_ms", 0.0))
            composite.append(frame.stats.get("indirect_ms", 0.0))
        return pipeline.glc.renderer, {"frame_ms": round(statistics.median(times), 2),
                                       "least_ms": round(min(times), 2), "most_ms": round(max(times), 2),
                                       "direct_ms": round(statistics.median(direct), 2),
                                       "indirect_ms": round(statistics.median(composite), 2)}
    finally:
        pipeline.release()


def main():
    parser = argparse.ArgumentParser(description="what surfaces' own light costs")
    parser.add_argument("folder")
    parser.add_argument("names", nargs="+")
    parser.add_argument("--frames", type=int, default=15)
    args = parser.parse_args()
    report, renderer = {}, None
    for name in args.names:
        scene = load_scene(f"{args.folder}/{name}.npz")
        for case, shown in cases(scene).items():
            renderer, report[f"{name}, {case}"] = timed(shown, args.frames)
    print(json.dumps({"renderer": renderer, "frames": args.frames, "runs": report}, indent=1))


if __name__ == "__main__":
    main()
