"""Drawing a rendered frame into the 3D view with Blender's `gpu` module.

Imported only inside `view_draw`: in background mode Blender has no drawing functions,
and everything that decides what to draw is computed (and tested) elsewhere.
"""
import gpu
from gpu_extras.presets import draw_texture_2d


def draw_image(engine, scene, rows, size):
    """Draw `rows` (bottom row first, RGBA float32) over the whole region, through the
    scene's view transform like every render engine's viewport image."""
    width, height = size
    pixels = gpu.types.Buffer("FLOAT", rows.size, rows.ravel())
    texture = gpu.types.GPUTexture((width, height), format="RGBA16F", data=pixels)
    gpu.state.blend_set("ALPHA_PREMULT")
    engine.bind_display_space_shader(scene)
    draw_texture_2d(texture, (0, 0), width, height)
    engine.unbind_display_space_shader()
    gpu.state.blend_set("NONE")
