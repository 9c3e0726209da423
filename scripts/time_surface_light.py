"""What the light of surfaces' own features costs (soft shadows, highlights and
reflections, cut-outs and glass): exported scenes rendered as they are and with each
feature taken out, without Blender.

    python scripts/time_surface_light.py DIR NAME [NAME ...] [--frames 15]

reads DIR/NAME.npz (`python -m lpv_preview export NAME --out DIR/NAME.npz`) and times
one-set 1920×1080 frames with every stage redone, for the scene as it is ("all"), with
every light's size 0 (hard shadows), with no glossy surface (no highlights, no
reflections), and with none of these nor cut-outs or glass ("none"). It prints per scene
and case the median frame's wall milliseconds, its least and most, and the median
direct stage (`direct_ms`: shadows and highlights) and composite (`indirect_ms`: the
reflections), as JSON; "all" less "none" is what the features cost.
"""
import dataclasses

from lpv_preview.bench.timing import time_cases_command
from lpv_preview.gpu.settings import Settings

STAGES = ("direct_ms", "indirect_ms")


def cases(scene):
    """The scene and its variants, by name."""
    hard = [dataclasses.replace(light, radius=0.0, size=(0.0, 0.0), angle=0.0) for light in scene.lights]
    variants = {"all": scene, "sizes 0": dataclasses.replace(scene, lights=hard),
                "no gloss": dataclasses.replace(scene, specular=None),
                "none": dataclasses.replace(scene, lights=hard, specular=None, alpha=None, alpha_layers=None,
                                            transmission=None)}
    for case, shown in variants.items():
        yield case, shown, Settings(width=1920, height=1080)


if __name__ == "__main__":
    time_cases_command("what surfaces' own light costs", cases, STAGES)
