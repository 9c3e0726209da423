"""What the world's light costs against its World Samples, on exported scenes, without Blender.

    python scripts/time_world_samples.py DIR NAME [NAME ...] [--samples 0 64 256 1024] [--frames 12]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and renders
one-set 1920×1080 frames with every stage redone at each World Samples count, printing per
count the median frame's wall milliseconds (least and most) and the median of each stage
that took more than half a millisecond (`world_ms`: the pixels' gather of the world's
light; `emitter_bounce_ms`: its bounce), as JSON. 0 samples is the frame whose world only
shows.
"""
import argparse
import json
import statistics
import time

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings

parser = argparse.ArgumentParser(description="the world's cost against World Samples")
parser.add_argument("folder")
parser.add_argument("names", nargs="+")
parser.add_argument("--samples", type=int, nargs="+", default=[0, 64, 256, 1024])
parser.add_argument("--frames", type=int, default=12)
args = parser.parse_args()
report = {}
for name in args.names:
    scene = load_scene(f"{args.folder}/{name}.npz")
    pipeline = Pipeline(Settings(width=1920, height=1080))
    try:
        for samples in args.samples:
            settings = Settings(width=1920, height=1080, world_samples=samples)
            pipeline.render(scene, settings, passes=())  # warm-up
            times, stages = [], []
            for _ in range(args.frames):
                pipeline.invalidate()
                pipeline.glc.gl.finish()
                started = time.perf_counter()
                frame = pipeline.render(scene, settings, passes=())
                pipeline.glc.gl.finish()
                times.append((time.perf_counter() - started) * 1000)
                stages.append({key: value for key, value in frame.stats.items() if key.endswith("_ms")})
            medians = {key: statistics.median(stage.get(key, 0.0) for stage in stages) for key in stages[0]}
            report[f"{name}, {samples} samples"] = {
                "frame_ms": round(statistics.median(times), 2), "least_ms": round(min(times), 2),
                "most_ms": round(max(times), 2),
                **{key: round(value, 2) for key, value in medians.items() if value > 0.5 and key != "total_ms"}}
    finally:
        pipeline.release()
print(json.dumps({"renderer": pipeline.glc.renderer, "frames": args.frames, "runs": report}, indent=1))
