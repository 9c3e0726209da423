"""Drawing a rendered frame into the 3D view with Blender's `gpu` module.

Imported only by the viewport: in background mode Blender has no drawing functions, and
everything that decides what to draw is computed (and tested) elsewhere.
"""
import gpu
import numpy as np
from gpu_extras.presets import draw_texture_2d

from .viewport import DisplayRows


class ViewportImage(DisplayRows):
    """The frames' rows in Blender GPU buffers (the pipeline reads into them through the
    buffer protocol, on the GL thread) and the texture made from the drawn ones, once per
    new frame: a redraw with nothing new draws the same texture again."""

    def __init__(self):
        super().__init__()
        self.texture = None

    def allocate(self, count):
        # Blender 5.0 makes textures from FLOAT buffers only.
        buffer = gpu.types.Buffer("FLOAT", count)
        return np.asarray(buffer), buffer

    def draw(self, engine, scene, region_size):
        """Draw the last frame over the whole region (of `region_size`; the frame may be
        smaller), through the scene's view transform like every render engine's viewport
        image."""
        if self.fresh or self.texture is None:
            self.texture = gpu.types.GPUTexture(self.size, format="RGB16F", data=self.handle)
            self.fresh = False
        gpu.state.blend_set("ALPHA_PREMULT")
        engine.bind_display_space_shader(scene)
        draw_texture_2d(self.texture, (0, 0), *region_size)
        engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")
