"""The scene's triangles on the GPU, shared by every raster pass (RSM faces, G-buffer)."""
import numpy as np

from .context import dispatch, set_uniforms
from .surface_images import SurfaceImages

# The two DrawElementsIndirect commands (count, instances, first index, base vertex, base
# instance) of split_at_rim, in this order.
FRONT, CROSSING = 0, 1
RIM_COMMAND_BYTES = 2 * 5 * 4


VERTEX_LAYOUT = ("3f 3f 4f 4f 4f 4f 1f", "in_position", "in_normal", "in_albedo", "in_surface", "in_transmission",
                 "in_specular", "in_metallic")
"""A vertex's floats and attributes (shaders/vertex_layout.glsl says where the compute
passes find them)."""


def vertex_albedo(scene):
    """(T, 3, 4) each corner's albedo and alpha: the triangle's albedo times the corner's
    vertex colour, divided where the surface transmits by what does not (the opaque part's
    albedo, shaders/surface.glsl), and the triangle's alpha."""
    albedo = np.repeat(scene.albedo[:, None, :], 3, axis=1)
    if scene.vertex_colors is not None:
        albedo = albedo * scene.vertex_colors
    if scene.transmission is not None:
        opaque = 1.0 - scene.transmission[:, 3]
        albedo = np.clip(albedo / np.maximum(opaque, 1e-6)[:, None, None], 0.0, 1.0)
    alpha = np.ones((len(albedo), 3, 1), np.float32) if scene.alpha is None else np.repeat(
        scene.alpha[:, None, None], 3, axis=1)
    return np.concatenate([albedo, alpha], axis=2)


class MeshBuffer:
    """One interleaved vertex buffer and its vertex arrays, and the scene's images.

    A vertex is its position, normal, albedo (the triangle's times its corner's vertex
    colour) and alpha, surface coordinate (u, v, image layer, alpha image layer; layer -1:
    no image), transmission (tint, share) and glossy reflection (F0 rgb, roughness; F0
    black: none) and metallic share, twenty-three floats (VERTEX_LAYOUT).
    `see_through` says whether any triangle is cut out or transmits (the raster passes
    test alpha), `hashed` whether that differs from one VPL pattern to the next, and
    `transmits` whether light passing some triangle is tinted.
    The camera draws its `camera_triangles` and the lights' maps its `light_triangles`
    ((first, count) ranges of a sanitized Scene's ordering)."""

    def __init__(self, glc, scene):
        count = scene.triangle_count
        surface = np.zeros((count, 3, 4), dtype=np.float32)
        surface[..., 2:] = -1.0
        if scene.uvs is not None:
            surface[..., :2] = scene.uvs
        if scene.image_layers is not None:
            surface[..., 2] = scene.image_layers[:, None]
        if scene.alpha_layers is not None:
            surface[..., 3] = scene.alpha_layers[:, None]
        transmission = np.zeros((count, 3, 4), dtype=np.float32)
        transmission[..., :3] = 1.0
        if scene.transmission is not None:
            transmission[:] = scene.transmission[:, None, :]
        specular = np.zeros((count, 3, 5), dtype=np.float32)
        specular[..., 3] = 1.0
        if scene.specular is not None:
            specular[:] = scene.specular[:, None, :]
        interleaved = np.concatenate([scene.triangles, scene.normals, vertex_albedo(scene), surface, transmission,
                                      specular], axis=2).astype(np.float32)
        self.see_through = scene.see_through
        self.hashed = scene.hashed
        self.transmits = scene.transmission is not None
        self.glc = glc
        self.images = SurfaceImages(glc.gl, scene.images)
        self.triangle_count = count
        self.vertex_count = count * 3
        self.camera_triangles = scene.camera_triangles or (0, count)
        self.light_triangles = scene.light_triangles or (0, count)
        first, shadowing = self.light_triangles
        corners = scene.triangles[first:first + shadowing].reshape(-1, 3) if shadowing else np.zeros((1, 3))
        self.occluder_bounds = corners.min(axis=0).astype(np.float64), corners.max(axis=0).astype(np.float64)
        self.buffer = glc.gl.buffer(interleaved.tobytes())
        self.emission = None  # each triangle's emitted radiance (vec4), for the camera's glow
        if scene.emission is not None:
            emission = np.zeros((count, 4), dtype=np.float32)
            emission[:, :3] = scene.emission
            self.emission = glc.gl.buffer(emission.tobytes())
        self._arrays = {}
        self.rim_lists = {}

    def vertex_array(self, program, indices=None):
        if (program, indices) not in self._arrays:
            self._arrays[program, indices] = self.glc.gl.vertex_array(
                program, [(self.buffer, *VERTEX_LAYOUT)],
                index_buffer=indices, index_element_size=4, skip_errors=True)
        self.images.bind(program)
        return self._arrays[program, indices]

    def draw(self, program, mode, triangles):
        """Draw the (first, count) range `triangles` with `program`."""
        first, count = triangles
        if count:
            self.vertex_array(program).render(mode, vertices=3 * count, first=3 * first)

    def split_at_rim(self, hemisphere_view, hemisphere):
        """Sort the triangles by a paraboloid hemisphere's rim plane on the GPU
        (shaders/rim_split.comp): returns one index buffer holding the triangles wholly in
        front and those crossing it, and the indirect draw commands (FRONT, CROSSING) that
        draw each list. Triangles wholly behind are in neither, so each hemisphere draws
        only its own; only the lights' triangles are sorted. Each hemisphere (0 or 1) has its own buffers: drawing one never
        waits on sorting the other."""
        gl = self.glc.gl
        capacity = self.vertex_count
        if hemisphere not in self.rim_lists:
            self.rim_lists[hemisphere] = (gl.buffer(reserve=max(2 * capacity, 1) * 4),
                                           gl.buffer(reserve=RIM_COMMAND_BYTES))
        lists, commands = self.rim_lists[hemisphere]
        for binding, buffer in enumerate((self.buffer, commands, lists)):
            buffer.bind_to_storage_buffer(binding)
        program = self.glc.compute("rim_split")
        first, count = self.light_triangles
        set_uniforms(program, hemisphere_view=hemisphere_view, first_triangle=first, triangle_count=count,
                     capacity=capacity, reset=True)
        dispatch(program, 10, local=(64, 1, 1))
        if count:
            set_uniforms(program, reset=False)
            dispatch(program, count, local=(64, 1, 1))
        return lists, commands

    def resources(self):
        """The vertex buffer, the images and each hemisphere's rim-split lists and draw
        commands."""
        return (self.buffer, *self.images.resources(), *((self.emission,) if self.emission is not None else ()),
                *(buffer for buffers in self.rim_lists.values() for buffer in buffers))

    def release(self):
        for array in self._arrays.values():
            array.release()
        for resource in self.resources():
            resource.release()
