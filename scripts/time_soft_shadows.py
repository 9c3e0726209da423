"""What soft shadows cost: exported scenes rendered with their lights' sizes and with every
size 0 (hard shadows), without Blender.

    python scripts/time_soft_shadows.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and times
one-set 1920×1080 frames with every stage redone, printing per scene and case the median
frame's wall milliseconds, its least and most, and the median direct stage (`direct_ms`,
where the shadows are filtered), as JSON.
"""
import argparse
import dataclasses
import json
import statistics
import time

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings

parser = argparse.ArgumentParser(description="soft shadows' cost against hard ones")
parser.add_argument("folder")
parser.add_argument("names", nargs="+")
parser.add_argument("--frames", type=int, default=15)
args = parser.parse_args()
report, renderer = {}, None
for name in args.names:
    scene = load_scene(f"{args.folder}/{name}.npz")
    hard = dataclasses.replace(scene, lights=[dataclasses.replace(light, radius=0.0, size=(0.0, 0.0), angle=0.0)
                                              for light in scene.lights])
    for case, shown in (("light sizes", scene), ("sizes 0", hard)):
        pipeline = Pipeline(Settings(width=1920, height=1080))
        try:
            renderer = pipeline.glc.renderer
            pipeline.render(shown, passes=())  # warm-up
            times, direct = [], []
            for _ in range(args.frames):
                pipeline.invalidate()
                pipeline.glc.gl.finish()
                started = time.perf_counter()
                frame = pipeline.render(shown, passes=())
                pipeline.glc.gl.finish()
                times.append((time.perf_counter() - started) * 1000)
                direct.append(frame.stats.get("direct_ms", 0.0))
            report[f"{name}, {case}"] = {"frame_ms": round(statistics.median(times), 2),
                                         "least_ms": round(min(times), 2), "most_ms": round(max(times), 2),
                                         "direct_ms": round(statistics.median(direct), 2)}
        finally:
            pipeline.release()
print(json.dumps({"renderer": renderer, "frames": args.frames, "runs": report}, indent=1))
