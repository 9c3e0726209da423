"""What a viewport redraw costs after each kind of edit, through the engine's own path
(ViewportSession: extraction of what changed, then the pipeline's cached stages).

    .venv/bin/python scripts/time_viewport_updates.py [cornell atrium city] [--size 960x540] [--repeats 5]

Prints, per demo scene, the median milliseconds of a full update (everything extracted
and every stage redone), a camera move, a light move and a mesh edit, with the stages
each one ran, and the camera move's share of the full update.
"""
import argparse
import statistics
import sys
import time

import bpy

import lpv_preview
from lpv_preview import demo
from lpv_preview.addon.viewport import ViewportSession
from lpv_preview.addon.extract import extract_camera
from lpv_preview.addon.sync import CAMERA, EVERYTHING, GEOMETRY, LIGHTS

STAGES = ("extract_ms", "upload_ms", "rsm_ms", "warp_ms", "vpl_ms", "inject_ms", "propagate_ms", "gbuffer_ms",
          "direct_ms", "indirect_ms", "readback_ms")


def nudge_camera():
    bpy.context.scene.camera.location.x += 0.01


def nudge_light():
    next(o for o in bpy.context.scene.objects if o.type == "LIGHT").location.x += 0.01


def nudge_mesh():
    mesh = max((o for o in bpy.context.scene.objects if o.type == "MESH"), key=lambda o: len(o.data.vertices)).data
    mesh.vertices[0].co.z += 0.001
    mesh.update()


EDITS = {"full": (None, EVERYTHING), "camera": (nudge_camera, {CAMERA}), "light": (nudge_light, {LIGHTS}),
         "mesh": (nudge_mesh, {GEOMETRY})}


def timed_update(session, size, edit, parts, full):
    if edit is not None:
        edit()
    if full:
        session.pipeline.invalidate()
    session.pending |= set(parts)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    start = time.perf_counter()
    frame = session.frame(depsgraph, extract_camera(depsgraph, size), size)
    return (time.perf_counter() - start) * 1000.0, frame.stats


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=["cornell", "atrium"])
    parser.add_argument("--size", default="960x540")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    size = tuple(int(v) for v in args.size.split("x"))
    for name in args.scenes:
        demo.build(name)
        lpv_preview.register()
        session = ViewportSession()
        try:
            timed_update(session, size, None, EVERYTHING, full=True)  # compile shaders, fill caches
            medians = {}
            for kind, (edit, parts) in EDITS.items():
                samples = [timed_update(session, size, edit, parts, full=kind == "full") for _ in range(args.repeats)]
                medians[kind] = statistics.median(ms for ms, _ in samples)
                stats = samples[-1][1]
                ran = ", ".join(f"{s[:-3]} {stats[s]:.1f}" for s in STAGES if s in stats)
                print(f"{name} {kind:6s} {medians[kind]:8.1f} ms   ({ran})", flush=True)
            print(f"{name}: camera move {medians['camera'] / medians['full']:.1%} of a full update "
                  f"({stats['triangles']:,} triangles, {size[0]}x{size[1]}, {session.pipeline.glc.renderer})",
                  flush=True)
        finally:
            session.release()
            lpv_preview.unregister()


if __name__ == "__main__":
    main(sys.argv[1:])
