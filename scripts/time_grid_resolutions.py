"""What the light grid's resolution costs a frame on the GPU, without Blender.

    python scripts/time_grid_resolutions.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`scripts/full_gi_rooms.py DIR --export`) and times 1920×1080 frames of
the default settings, one VPL set with every stage redone, with grids of 16³ (the
default) and 32³ (the balanced preset's). Prints per scene and case the median frame's
wall milliseconds with its least and most and the median GPU milliseconds of the stages
the resolution changes (gpu_gather_ms: the light grid's gather), as JSON.
"""
from lpv_preview.bench.timing import time_cases_command
from lpv_preview.gpu.settings import Settings

RESOLUTIONS = (16, 32)
STAGES = tuple(f"gpu_{stage}_ms" for stage in ("inject", "gather", "emitter_bounce", "bounce", "indirect"))


def cases(scene):
    """One VPL set at each of RESOLUTIONS."""
    for resolution in RESOLUTIONS:
        yield f"{resolution}³", scene, Settings(width=1920, height=1080, lpv_resolution=resolution)


if __name__ == "__main__":
    time_cases_command("what the light grid's resolution costs a frame", cases, STAGES)
