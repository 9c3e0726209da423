"""What bounces after the first cost: exported scenes rendered with one bounce and with as
many as their Light Paths say, without Blender.

    python scripts/time_bounces.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and times
one-set 1920×1080 frames with every stage redone, printing per scene and case the
bounces, the median frame's wall milliseconds with its least and most, and the median
stages of the indirect light (`bounce_ms`: the later generations; `gather_ms` or
`pixel_gather_ms`: the gather, which has their points to gather too), as JSON.
"""
from lpv_preview.bench.timing import time_cases_command
from lpv_preview.gpu.settings import Settings

STAGES = ("bounce_ms", "gather_ms", "pixel_gather_ms", "inject_ms")


def cases(scene):
    """The scene with one bounce and with as many as its Light Paths say."""
    for case, bounces in (("one bounce", 1), ("Light Paths", 0)):
        yield case, scene, Settings(width=1920, height=1080, bounces=bounces)


if __name__ == "__main__":
    time_cases_command("what bounces after the first cost", cases, STAGES)
