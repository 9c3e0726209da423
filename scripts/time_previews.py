"""Times the preview frame the corrections start from, on exported scenes (.npz), without Blender.

    python scripts/time_previews.py NAME=FILE.npz:WIDTHxHEIGHT [...] [setting flags] > corrections_previews.json

reads each FILE.npz (made with `python -m lpv_preview export NAME`) and, as the
corrections' benchmark does (cli/correction_runs.py render_previews), renders a frame
with a pipeline released after (shaders compiled), then times five whole frames of fresh
pipelines at WIDTH × HEIGHT with the default settings (or those the setting flags give,
as `bench --corrections` takes them); prints the machine and each scene's median
milliseconds as JSON, which `bench --corrections --gpu-previews` reads. The benchmark on a
CPU-only machine counts its own (llvmpipe) preview time; this gives the GPU's for the same
frames.
"""
import argparse
import json
import statistics
import sys
import time

from lpv_preview.cli.flags import add_setting_flags, check_setting_flags, settings_from
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene

parser = argparse.ArgumentParser(description="the corrections' preview frames, timed")
parser.add_argument("scenes", nargs="+", help="NAME=FILE.npz:WIDTHxHEIGHT")
add_setting_flags(parser)
args = parser.parse_args()
check_setting_flags(args)
results = {}
for item in args.scenes:
    name, rest = item.split("=", 1)
    path, size = rest.rsplit(":", 1)
    width, height = map(int, size.split("x"))
    scene = load_scene(path)
    settings = settings_from(args, width, height)
    warm = Pipeline(settings)
    warm.render_converged(scene)
    warm.release()
    times = []
    for _ in range(5):
        pipeline = Pipeline(settings)
        start = time.perf_counter()
        pipeline.render_converged(scene)
        times.append((time.perf_counter() - start) * 1000)
        pipeline.release()
    results[name] = {"size": [settings.width, settings.height], "preview_ms": statistics.median(times)}
print(json.dumps({"machine": pipeline.glc.renderer, "command": "python scripts/time_previews.py " + " ".join(sys.argv[1:]),
                  "scenes": results}, indent=1))
