"""Exact stand-ins for the approximate stages, to measure what each costs in accuracy.

`gathered_indirect` replaces the LPV (injection, propagation, lookup) by gathering every
VPL's light at every pixel directly: the same VPLs, no grid, no SH, no visibility. With
the VPL count raised to the RSM's texel count it also stands in for the VPL sampling.
What is left between it and Cycles' one-bounce reference is the RSM itself and the
visibility between a VPL and the surfaces it lights. Its shader lives with the others
in gpu/shaders (vpl_gather_indirect.comp), where the GL context loads shaders from.
"""
import numpy as np

from ..gpu.context import dispatch, set_uniforms
from ..gpu.shade import bind_gbuffer, gbuffer_uniforms


def gathered_indirect(pipeline, camera, intensity=1.0):
    """The indirect image of `pipeline`'s last frame, gathered from its VPLs instead of the
    LPV: (height, width, 3) float32, top row first."""
    glc, targets = pipeline.glc, pipeline.targets
    image = glc.texture(targets.size, 4)
    glc.clear(image)
    program = glc.compute("vpl_gather_indirect")
    bind_gbuffer(targets)
    image.bind_to_image(0, read=True, write=True)
    for maps in pipeline.last_light_maps:
        maps.vpls.buffer.bind_to_storage_buffer(0)
        set_uniforms(program, **gbuffer_uniforms(camera), vpl_count=maps.vpls.count, intensity=float(intensity))
        dispatch(program, *targets.size)
    width, height = targets.size
    pixels = np.frombuffer(image.read(), dtype=np.float32).reshape(height, width, 4)
    glc.recycle(image)
    return np.ascontiguousarray(pixels[::-1, :, :3])
