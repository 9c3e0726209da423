"""What bounces after the first cost: exported scenes rendered with one bounce and with as
many as their Light Paths say, without Blender.

    python scripts/time_bounces.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and times
one-set 1920×1080 frames with every stage redone, printing per scene and case the
bounces, the median frame's wall milliseconds with its least and most, and the median
stages of the indirect light (`bounce_ms`: the later generations; `gather_ms` or
`pixel_gather_ms`: the gather, which has their points to gather too), as JSON.
"""
import argparse
import json
import statistics
import time

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings

STAGES = ("bounce_ms", "gather_ms", "pixel_gather_ms", "inject_ms")


def timed(scene, settings, frames):
    pipeline = Pipeline(settings)
    try:
        pipeline.render(scene, passes=())  # warm-up
        times, stages, bounces = [], {stage: [] for stage in STAGES}, None
        for _ in range(frames):
            pipeline.invalidate()
            pipeline.glc.gl.finish()
            started = time.perf_counter()
            frame = pipeline.render(scene, passes=())
            pipeline.glc.gl.finish()
            times.append((time.perf_counter() - started) * 1000)
            for stage in STAGES:
                stages[stage].append(frame.stats.get(stage, 0.0))
            bounces = frame.stats["bounces"]
        return pipeline.glc.renderer, {"bounces": bounces, "frame_ms": round(statistics.median(times), 2),
                                       "least_ms": round(min(times), 2), "most_ms": round(max(times), 2),
                                       **{stage: round(statistics.median(values), 2) for stage, values in stages.items()}}
    finally:
        pipeline.release()


def main():
    parser = argparse.ArgumentParser(description="what bounces after the first cost")
    parser.add_argument("folder")
    parser.add_argument("names", nargs="+")
    parser.add_argument("--frames", type=int, default=15)
    args = parser.parse_args()
    report, renderer = {}, None
    for name in args.names:
        scene = load_scene(f"{args.folder}/{name}.npz")
        for case, bounces in (("one bounce", 1), ("Light Paths", 0)):
            renderer, report[f"{name}, {case}"] = timed(scene, Settings(width=1920, height=1080, bounces=bounces),
                                                        args.frames)
    print(json.dumps({"renderer": renderer, "frames": args.frames, "runs": report}, indent=1))


if __name__ == "__main__":
    main()
