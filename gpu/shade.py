"""The camera's side: G-buffer, direct light per light, LPV lookup and composite."""
import moderngl
import numpy as np

from .context import dispatch, set_uniforms

PASS_NAMES = ("combined", "direct", "indirect")


class FrameTargets:
    """The camera's G-buffer and the output images of one resolution."""

    def __init__(self, gl, width, height):
        self.size = (width, height)
        self.position, self.normal, self.albedo, self.direct, self.indirect, self.combined = (
            gl.texture(self.size, 4, dtype="f4") for _ in range(6))
        for texture in (self.position, self.normal, self.albedo):
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.depth = gl.depth_renderbuffer(self.size)
        self.framebuffer = gl.framebuffer(color_attachments=[self.position, self.normal, self.albedo],
                                          depth_attachment=self.depth)
        self.direct_framebuffer = gl.framebuffer(color_attachments=[self.direct])

    def read(self, name):
        """An output image as (height, width, 3) float32, top row first."""
        width, height = self.size
        image = np.frombuffer(getattr(self, name).read(), dtype=np.float32).reshape(height, width, 4)
        return np.ascontiguousarray(image[::-1, :, :3])

    def release(self):
        self.framebuffer.release()
        self.direct_framebuffer.release()
        self.depth.release()
        for texture in (self.position, self.normal, self.albedo, self.direct, self.indirect, self.combined):
            texture.release()


def render_gbuffer(glc, mesh, camera, targets):
    """Rasterise the scene from the camera; clears the direct image for the lights to add into."""
    gl = glc.gl
    program = glc.program("raster", "gbuffer")
    targets.framebuffer.use()
    targets.framebuffer.viewport = (0, 0, *targets.size)
    targets.framebuffer.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    gl.enable(moderngl.DEPTH_TEST)
    gl.disable(moderngl.CULL_FACE)
    set_uniforms(program, view_projection=camera.projection @ camera.view,
                 camera_position=tuple(float(v) for v in camera.position))
    mesh.vertex_array(program).render(moderngl.TRIANGLES)
    targets.direct_framebuffer.clear(0.0, 0.0, 0.0, 0.0)


def shade_direct(glc, targets, rsm, shadow_bias):
    """Add one light's shadowed Lambert term into the direct image."""
    program = glc.compute("shade_direct")
    for unit, texture in enumerate((targets.position, targets.normal, targets.albedo, rsm.position)):
        texture.use(location=unit)
    targets.direct.bind_to_image(0, read=True, write=True)
    set_uniforms(program, g_position=0, g_normal=1, g_albedo=2, rsm_position=3, **rsm.lookup_uniforms(),
                 texel_angle=2.0 / rsm.resolution, ortho_texel=rsm.ortho_texel, shadow_bias=shadow_bias,
                 **rsm.light_uniforms)
    dispatch(program, *targets.size)


def shade_indirect(glc, targets, lpv, intensity):
    """Look the LPV up at every pixel and write the indirect and combined images."""
    program = glc.compute("shade_indirect")
    for unit, texture in enumerate((targets.position, targets.normal, targets.albedo, *lpv.sums)):
        texture.use(location=unit)
    targets.direct.bind_to_image(0, read=True, write=False)
    targets.indirect.bind_to_image(1, read=False, write=True)
    targets.combined.bind_to_image(2, read=False, write=True)
    grid = lpv.grid
    set_uniforms(program, g_position=0, g_normal=1, g_albedo=2, lpv_r=3, lpv_g=4, lpv_b=5,
                 grid_origin=grid.origin, cell_size=grid.cell_size, grid_size=grid.size, intensity=intensity)
    dispatch(program, *targets.size)
