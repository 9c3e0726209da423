"""The light grid's gather alone, wall clock after the GPU finished (llvmpipe's timer queries
are meaningless), on demo scenes at the defaults.

    .venv/bin/python scripts/time_light_grid_gather.py [default_cube,cornell,area_room,atrium] [--frames 3]
        [--exports DIR] [--resolution 16]

prints per scene the emitter clusters, the grids and the median gather over the frames (each
frame a new VPL set, so the clusters are gathered again), with its least and most. The
scenes are built with bpy, or read from DIR/NAME.npz (`python -m lpv_preview export NAME`)
where there is no Blender, as on the GPU machine.
"""
import argparse
import statistics
import time

from lpv_preview.gpu import light_grid
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import Settings

SIZE = (64, 36)  # the gather does not depend on the image's size


def main():
    parser = argparse.ArgumentParser(description="the light grid's gather alone")
    parser.add_argument("scenes", nargs="?", default="default_cube,cornell,area_room,atrium")
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--resolution", type=int, default=Settings().lpv_resolution, help="cells a grid side")
    parser.add_argument("--exports", help="read the scenes from this folder's NAME.npz files")
    args = parser.parse_args()
    timed = []
    gather = light_grid.LightGrid.gather

    def timed_gather(self, *arguments):
        self.glc.gl.finish()
        began = time.perf_counter()
        gather(self, *arguments)
        self.glc.gl.finish()
        timed.append((time.perf_counter() - began, self.cluster_count(), len(self.grids), self.grids[0].size))

    light_grid.LightGrid.gather = timed_gather
    for name in args.scenes.split(","):
        if args.exports:
            scene = load_scene(f"{args.exports}/{name}.npz")
        else:
            from lpv_preview import demo
            scene = demo.extracted(name, resolution=SIZE)
        pipeline = Pipeline(Settings(width=SIZE[0], height=SIZE[1], lpv_resolution=args.resolution))
        timed.clear()
        try:
            for frame in range(args.frames):
                pipeline.render(scene, vpl_set=frame)
        finally:
            pipeline.release()
        seconds = [entry[0] for entry in timed]
        _, clusters, grids, size = timed[-1]
        print(f"{name}: {clusters} clusters, {grids} grids of {size}³: gather median "
              f"{1000 * statistics.median(seconds):.2f} ms ({1000 * min(seconds):.2f}-{1000 * max(seconds):.2f}, "
              f"{len(seconds)} gathers)", flush=True)


if __name__ == "__main__":
    main()
