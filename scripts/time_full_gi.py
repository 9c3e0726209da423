"""The GPU time of the frames scripts/full_gi_rooms.py measures, without Blender.

    python scripts/time_full_gi.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`scripts/full_gi_rooms.py DIR --export`) and times 1920×1080 frames of
the default settings with every stage redone: one VPL set, and converged over 16 sets (the
full-GI table's converged column), and the same with one bounce (what the later bounces
cost). Prints per scene and case the bounces, the median frame's wall milliseconds with
its least and most, and the median stages of the indirect light (its lookup: indirect_ms), the
world's and the VPLs' draw from the maps (vpl_ms), as JSON.
"""
from lpv_preview.bench.timing import time_cases_command
from lpv_preview.gpu.settings import Settings

STAGES = ("bounce_ms", "emitter_bounce_ms", "gather_ms", "indirect_ms", "inject_ms", "vpl_ms", "world_ms")
CONVERGED_SETS = 16


def cases(scene):
    """One set and a converged frame with the scene's Light Paths, and one set of one bounce."""
    frame = Settings(width=1920, height=1080)
    yield "one set", scene, frame
    yield f"{CONVERGED_SETS} sets", scene, frame.with_changes(converge_sets=CONVERGED_SETS)
    yield "one set, one bounce", scene, frame.with_changes(bounces=1)


if __name__ == "__main__":
    time_cases_command("what a full-GI frame costs", cases, STAGES)
