"""Drawing a rendered frame into the 3D view with Blender's `gpu` module.

Imported only by the viewport: in background mode Blender has no drawing functions, and
everything that decides what to draw is computed (and tested) elsewhere.
"""
import gpu
import numpy as np
from gpu_extras.presets import draw_texture_2d

from .viewport import DisplayRows


class ViewportImage(DisplayRows):
    """The frame's rows in a Blender GPU buffer (the pipeline reads into it through the
    buffer protocol) and the texture made from them, once per new frame: a redraw with
    nothing new draws the same texture again."""

    def __init__(self):
        super().__init__()
        self.buffer = None
        self.texture = None

    def allocate(self, count):
        # Blender 5.0 makes textures from FLOAT buffers only.
        self.buffer = gpu.types.Buffer("FLOAT", count)
        return np.asarray(self.buffer)

    def draw(self, engine, scene, region_size):
        """Draw the last frame over the whole region (of `region_size`; the frame may be
        smaller), through the scene's view transform like every render engine's viewport
        image."""
        if self.fresh or self.texture is None:
            self.texture = gpu.types.GPUTexture(self.size, format="RGBA16F", data=self.buffer)
            self.fresh = False
        gpu.state.blend_set("ALPHA_PREMULT")
        engine.bind_display_space_shader(scene)
        draw_texture_2d(self.texture, (0, 0), *region_size)
        engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")
