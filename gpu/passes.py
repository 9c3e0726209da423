"""The render passes: one table for the Blender engine, the image files and the comparison.

Each pass has its name in Blender (the RenderResult pass and the multi-layer EXR layer
of F12) and its channels there, the pipeline's name (`Pipeline.render`'s `passes`, our EXR layers and PNGs),
whether it is a debug pass (written only when "Debug passes" is on) and where the
comparison with Cycles lists it (None: not compared; Cycles' references have direct,
indirect and their sum, and the comparison measures the indirect light first, which is
what the preview approximates).
"""
from dataclasses import dataclass


@dataclass(frozen=True)
class RenderPass:
    blender_name: str
    name: str
    channels: str = "RGB"
    debug: bool = False
    compared: int = None


RENDER_PASSES = (
    RenderPass("Combined", "combined", "RGBA", compared=2),
    RenderPass("Direct", "direct"),
    RenderPass("Indirect", "indirect", compared=1),
    RenderPass("Reflections", "reflections"),
    RenderPass("VPL Splats", "vpl_splats", debug=True),
    RenderPass("Warp Status", "warp_status", debug=True),
)

PASS_NAMES = tuple(p.name for p in RENDER_PASSES if not p.debug)
"""What a render reads back unless told otherwise."""
DEBUG_PASS_NAMES = tuple(p.name for p in RENDER_PASSES if p.debug)
COMPARED_PASS_NAMES = tuple(p.name for p in sorted((p for p in RENDER_PASSES if p.compared), key=lambda p: p.compared))
"""The images the comparison with Cycles measures, in its order."""


def render_passes(debug=False):
    """The passes a render writes: ours, and the debug ones when `debug`."""
    return tuple(p for p in RENDER_PASSES if debug or not p.debug)
