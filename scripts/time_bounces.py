"""What bounces after the first cost: exported scenes rendered with one bounce and with as
many as their Light Paths say, without Blender.

    python scripts/time_bounces.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and times
one-set 1920×1080 frames with every stage redone, through the light grid and the
per-pixel VPL gather, printing per scene, method and case the bounces, the median
frame's wall milliseconds with its least and most, and the median stages of the
indirect light (`bounce_ms`: the later generations; `gather_ms` or
`pixel_gather_ms`: the gather, which has their points to gather too), as JSON.
"""
from lpv_preview.bench.timing import time_cases_command
from lpv_preview.gpu.settings import Settings

STAGES = ("bounce_ms", "gather_ms", "pixel_gather_ms", "inject_ms")


def cases(scene):
    """The scene with one bounce and with as many as its Light Paths say, through the
    light grid (the default) and the per-pixel VPL gather (the accurate preset's)."""
    for method in ("light_grid", "vpl_gather"):
        for case, bounces in (("one bounce", 1), ("Light Paths", 0)):
            yield f"{method}, {case}", scene, Settings(width=1920, height=1080, bounces=bounces,
                                                       indirect_method=method)


if __name__ == "__main__":
    time_cases_command("what bounces after the first cost", cases, STAGES)
