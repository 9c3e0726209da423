"""Whether a 1.2M-triangle room's G-buffer draw depends on the room or on what was drawn
before it in the process, on the GPU: for each room in the order given (bench/synthetic.py
NAMED_SCENES), twelve camera moves then twelve light edits at 1920×1080, and per case
the median GPU milliseconds of the frame's G-buffer and of the same draw made again right
after the frame (same view, a view 0.1° on, after 20 ms idle, after every texture unit
is rebound to a dummy texture).

    python scripts/time_gbuffer_order.py [room1200k room1200k_glossy]
"""
import statistics
import sys
import time

import numpy as np

from lpv_preview.bench.synthetic import NAMED_SCENES
from lpv_preview.bench.viewport_work import edited_frames
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_edits import camera_path
from lpv_preview.gpu.settings import preset_settings
from lpv_preview.gpu.shade import DISPLAY_CHANNELS, render_gbuffer

SIZE = (1920, 1080)

FRAMES = 12


def gbuffer_ms(pipeline, camera):
    """The GPU milliseconds of one more G-buffer draw of the pipeline's mesh from `camera`."""
    stats = {}
    with pipeline.glc.timed(stats, "draw"):
        render_gbuffer(pipeline.glc, pipeline._mesh.value, camera, pipeline.targets, pipeline.vpl_pattern)
    pipeline.glc.read_timings()
    return stats.get("gpu_draw", stats["draw"])


def main():
    names = sys.argv[1:] or ["room1200k", "room1200k_glossy"]
    for name in names:
        scene = NAMED_SCENES[name]()
        pipeline = Pipeline(preset_settings(None, width=SIZE[0], height=SIZE[1]))
        display = np.zeros(SIZE[0] * SIZE[1] * DISPLAY_CHANNELS, np.float32)
        dummy = pipeline.glc.gl.texture((1, 1), 4)
        for kind in ("camera move", "light edit"):
            scenes = edited_frames(scene, kind, FRAMES)
            pipeline.render(scenes[0], passes=(), display_into=display)
            rows = {key: [] for key in ("frame", "same view", "new view", "after idle", "units rebound")}
            for shot in scenes[1:]:
                frame = pipeline.render(shot, passes=(), display_into=display)
                rows["frame"].append(frame.stats.get("gpu_gbuffer_ms", frame.stats["gbuffer_ms"]))
                rows["same view"].append(gbuffer_ms(pipeline, shot.camera))
                rows["new view"].append(gbuffer_ms(pipeline, camera_path(shot.camera, 2, degrees=0.1)[1]))
                time.sleep(0.02)
                rows["after idle"].append(gbuffer_ms(pipeline, shot.camera))
                for unit in range(32):
                    dummy.use(location=unit)
                rows["units rebound"].append(gbuffer_ms(pipeline, shot.camera))
            print(name, kind, {key: round(statistics.median(values), 2) for key, values in rows.items()}, flush=True)
        dummy.release()
        pipeline.release()


if __name__ == "__main__":
    main()
