"""What a viewport redraw costs Blender's thread, now that frames render on the GL thread.

    python scripts/time_redraw.py [--scene cornell] [--width 960 --height 540] [--redraws 60]

builds a demo scene, opens a viewport session on it and redraws as Blender would while a
still view converges (`--sets` VPL sets, then `--redraws` with nothing new): each redraw's
wall time on the calling thread is sorted into the redraws that start a frame, those
that find one still rendering, those that take a finished one, and those with nothing to
do; beside them, the time the GL thread spent on each frame, which Blender's thread used
to wait for. Prints medians and ranges as JSON. Drawing the texture needs Blender's GPU
module, which background mode lacks: the upload of the finished rows (width × height ×
RGBA16F) is not in these figures.
"""
import argparse
import json
import statistics
import time

import bpy

from lpv_preview import demo
from lpv_preview.addon.extract import extract_camera
from lpv_preview.addon.viewport import ViewportSession

parser = argparse.ArgumentParser(description="a viewport redraw's cost on Blender's thread")
parser.add_argument("--scene", default="cornell", choices=demo.SCENES)
parser.add_argument("--width", type=int, default=960)
parser.add_argument("--height", type=int, default=540)
parser.add_argument("--redraws", type=int, default=20, help="redraws with nothing to do, once the view converged")
parser.add_argument("--sets", type=int, default=4, help="the still view's viewport_vpl_sets")
args = parser.parse_args()

scene = demo.build(args.scene, resolution=(args.width, args.height))
import lpv_preview  # noqa: E402  (registered after the scene is built: building resets Blender)
lpv_preview.register()
scene.lpv_preview.viewport_vpl_sets = args.sets
session = ViewportSession()
depsgraph = bpy.context.evaluated_depsgraph_get()
camera = extract_camera(depsgraph, (args.width, args.height))
size = (args.width, args.height)
kinds = {"starts a frame": [], "finds one rendering": [], "takes a finished one": [], "nothing to do": []}
frame_ms = []
while len(kinds["nothing to do"]) < args.redraws:
    was_rendering, was_done = session.rendering, session.frame_done
    started = time.perf_counter()
    frame = session.redraw(depsgraph, camera, size)
    spent = (time.perf_counter() - started) * 1000
    if was_rendering:
        kinds["takes a finished one" if was_done else "finds one rendering"].append(spent)
        if was_done:
            frame_ms.append(frame.stats["total_ms"])
    else:
        kinds["starts a frame" if session.rendering else "nothing to do"].append(spent)
    time.sleep(0.005)  # Blender redraws on its own schedule
session.release()
lpv_preview.unregister()


def summary(values):
    return {"redraws": len(values), "median_ms": round(statistics.median(values), 3),
            "min_ms": round(min(values), 3), "max_ms": round(max(values), 3)} if values else {"redraws": 0}


print(json.dumps({"scene": args.scene, "size": list(size), "blender_thread": {k: summary(v) for k, v in kinds.items()},
                  "gl_thread_frame": summary(frame_ms)}, indent=1))
