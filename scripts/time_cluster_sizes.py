"""The culling clusters' size against the frame: a light edit and a camera move of the
1,228,800-triangle room (bench/synthetic.py room_scene) with the cube map and with WDPM,
for each size of cluster a view culls together (gpu/mesh_buffer.py CLUSTER_TRIANGLES),
wall-clock medians of 15 redraws with least and most (bench/viewport_work.py), and the
GPU stages over 0.3 ms.

    python scripts/time_cluster_sizes.py 64 128 256 512
"""
import argparse

from lpv_preview.bench.synthetic import room_scene
from lpv_preview.bench.viewport_work import display_buffer, edited_frames, timed_redraws
from lpv_preview.gpu import mesh_buffer
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import preset_settings

SIZE = (1920, 1080)
FRAMES = 15


def main():
    parser = argparse.ArgumentParser(description="cluster size against light edits and camera moves")
    parser.add_argument("sizes", nargs="+", type=int)
    args = parser.parse_args()
    room = room_scene(320)
    for size in args.sizes:
        mesh_buffer.CLUSTER_TRIANGLES = size
        for method in ("cm", "wdpm"):
            settings = preset_settings(None, width=SIZE[0], height=SIZE[1], method=method)
            for edit in ("light edit", "camera move"):
                pipeline = Pipeline(settings)
                try:
                    timed = timed_redraws(pipeline, edited_frames(room, edit, FRAMES), display_buffer(settings))
                finally:
                    pipeline.release()
                gpu = {key: value for key, value in timed["stages"].items() if key.startswith("gpu_") and value > 0.3}
                print(size, method, edit, timed["frame_ms"], timed["least_ms"], timed["most_ms"], gpu, flush=True)


if __name__ == "__main__":
    main()
