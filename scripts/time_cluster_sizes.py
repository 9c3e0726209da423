"""The culling clusters' size against the frame: a light edit and a camera move of the
1,228,800-triangle room (bench/synthetic.py room_scene) with the cube map and with WDPM,
for each size of cluster a view culls together (gpu/mesh_buffer.py CLUSTER_TRIANGLES),
wall-clock medians of 15 redraws with least and most, and the GPU stages over 0.3 ms.

    python scripts/time_cluster_sizes.py 64 128 256 512
"""
import argparse
import dataclasses
import statistics
import time

import numpy as np

from lpv_preview.bench.synthetic import room_scene
from lpv_preview.gpu import mesh_buffer
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_edits import camera_path
from lpv_preview.gpu.settings import preset_settings

SIZE = (1920, 1080)
FRAMES = 15


def edits(scene, edit):
    """The scenes of FRAMES + 1 redraws: the lamp's power 1 % up and down, or the camera
    turned a quarter of a degree a redraw."""
    if edit == "light edit":
        lamp = scene.lights[0]
        return [dataclasses.replace(scene, lights=[dataclasses.replace(lamp, power=lamp.power * (1.01 if i % 2 else 1.0))])
                for i in range(FRAMES + 1)]
    return [dataclasses.replace(scene, camera=camera)
            for camera in camera_path(scene.camera, FRAMES + 1, degrees=0.25 * FRAMES / 2)]


def main():
    parser = argparse.ArgumentParser(description="cluster size against light edits and camera moves")
    parser.add_argument("sizes", nargs="+", type=int)
    args = parser.parse_args()
    room = room_scene(320)
    room.sanitize()
    room.geometry_key(), room.bounds()
    display = np.empty(SIZE[0] * SIZE[1] * 4, dtype=np.float32)
    for size in args.sizes:
        mesh_buffer.CLUSTER_TRIANGLES = size
        for method in ("cm", "wdpm"):
            for edit in ("light edit", "camera move"):
                pipeline = Pipeline(preset_settings(None, width=SIZE[0], height=SIZE[1], method=method))
                try:
                    scenes = edits(room, edit)
                    pipeline.render(scenes[0], passes=(), display_into=display)
                    times, stages = [], []
                    for scene in scenes[1:]:
                        began = time.perf_counter()
                        frame = pipeline.render(scene, passes=(), display_into=display)
                        times.append((time.perf_counter() - began) * 1000.0)
                        stages.append(frame.stats)
                finally:
                    pipeline.release()
                gpu = {key: round(statistics.median(s.get(key, 0.0) for s in stages), 2)
                       for key in sorted({k for s in stages for k in s if k.startswith("gpu_")})}
                print(size, method, edit, round(statistics.median(times), 2), round(min(times), 2), round(max(times), 2),
                      {key: value for key, value in gpu.items() if value > 0.3}, flush=True)


if __name__ == "__main__":
    main()
