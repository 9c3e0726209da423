"""The scene's triangles on the GPU, shared by every raster pass (RSM faces, G-buffer)."""
import numpy as np

from .context import dispatch, dispatch_row, set_uniforms
from .scene import triangle_bounds
from .surface_images import SurfaceImages

# The two DrawElementsIndirect commands (count, instances, first index, base vertex, base
# instance) of split_at_rim, in this order.
FRONT, CROSSING = 0, 1
RIM_COMMAND_BYTES = 2 * 5 * 4
RASTER_SPAN = 8
"""Texels a paraboloid map's triangle in front of the rim may span each way and still be
rasterised by rim_split.comp rather than the rasterizer: most of a large scene's
triangles are smaller than a texel (docs/performance.md, "Speed")."""
CLUSTER_TRIANGLES = 128
"""Consecutive triangles a view culls together (shaders/frustum_cull.comp): few enough that a
cube face draws little more than its sixth of a scene, many enough that a million
triangles are 8,192 draws (docs/performance.md compares 64 to 512)."""
CULL_SLOTS = 8
"""Views culled in turn into a range's command buffer before its first slot is written
again: a cube map's six faces and the camera's passes never write what a draw still reads."""
CULL_COMMAND_BYTES = 5 * 4
"""A cluster's DrawArraysIndirect command, padded to five uints: moderngl's render_indirect
reads commands 20 bytes apart (DrawElementsIndirect's size) for arrays too."""


VERTEX_LAYOUT = ("3f 3f 4f 4f 4f 4f 1f", "in_position", "in_normal", "in_albedo", "in_surface", "in_transmission",
                 "in_specular", "in_metallic")
"""A vertex's floats in the vertex buffer, by attribute (shaders/vertex_layout.glsl says
where the compute passes and the raster passes' fragments find them)."""
_WIDTHS = [int(attribute[:-1]) for attribute in VERTEX_LAYOUT[0].split()]
VERTEX_FLOATS = sum(_WIDTHS)
VERTEX_SLICES = {name: slice(sum(_WIDTHS[:i]), sum(_WIDTHS[:i + 1])) for i, name in enumerate(VERTEX_LAYOUT[1:])}
"""Where each attribute's floats lie in a vertex, by its name in VERTEX_LAYOUT."""
SURFACE_VERTICES_BINDING = 5
"""The storage binding of the vertex buffer, from which a raster pass's fragments read
their surface (shaders/surface_vertices.glsl): the vertex shader passes on only the
triangle's number and two weights."""


SURFACE_ARRAYS = (("albedo", 3), ("colours", 9), ("alpha", 1), ("transmission", 4), ("uvs", 6), ("layers", 2),
                  ("specular", 5))
"""The surface arrays shaders/mesh_interleave.comp reads, with their floats a triangle."""
STAGED_FLOATS_PER_TRIANGLE = 9 + sum(width for _, width in SURFACE_ARRAYS)
"""Floats a triangle uploads at most (normals, every surface array) to be interleaved and
released (gpu/capacity.py counts them beside the vertex buffer and the positions)."""
POSITION_BYTES = 3 * 4
"""A vertex's bytes in the positions the raster passes draw from: fetched from the
interleaved vertex, 23 floats apart, each position cost a memory line of its own
(docs/performance.md, "Raster passes")."""


def surface_arrays(scene):
    """The scene's surface arrays by SURFACE_ARRAYS' names (None where it has none), as
    float32 rows of a triangle each."""
    layers = None
    if scene.image_layers is not None or scene.alpha_layers is not None:
        layers = np.full((scene.triangle_count, 2), -1.0, dtype=np.float32)
        for column, array in enumerate((scene.image_layers, scene.alpha_layers)):
            if array is not None:
                layers[:, column] = array
    arrays = {"albedo": scene.albedo, "colours": scene.vertex_colors, "alpha": scene.alpha,
              "transmission": scene.transmission, "uvs": scene.uvs, "layers": layers, "specular": scene.specular}
    return {name: None if array is None else np.ascontiguousarray(array, dtype=np.float32).reshape(len(array), -1)
            for name, array in arrays.items()}


def interleave(glc, scene):
    """The vertex buffer of a sanitized scene, and its positions alone (what the raster
    passes draw from): its arrays uploaded as they are and interleaved on the GPU
    (shaders/mesh_interleave.comp): writing 23 floats a vertex on the host, and uploading
    them, took most of a second at a million triangles."""
    gl = glc.gl
    count = scene.triangle_count
    vertices = gl.buffer(reserve=max(count, 1) * 3 * VERTEX_FLOATS * 4)
    if not count:
        return vertices, gl.buffer(reserve=POSITION_BYTES)
    corners, normal_rows = (np.ascontiguousarray(rows, dtype=np.float32) for rows in (scene.triangles, scene.normals))
    positions, normals = gl.buffer(reserve=corners.nbytes), gl.buffer(reserve=normal_rows.nbytes)
    glc.write(positions, [corners])
    glc.write(normals, [normal_rows])
    arrays = surface_arrays(scene)
    offsets, at = {}, 0
    for name, width in SURFACE_ARRAYS:
        offsets[f"{name}_at"] = at if arrays[name] is not None else -1
        at += count * width if arrays[name] is not None else 0
    surfaces = gl.buffer(reserve=max(at, 1) * 4)
    glc.write(surfaces, [np.ascontiguousarray(arrays[name]) for name, _ in SURFACE_ARRAYS if arrays[name] is not None])
    program = glc.compute("mesh_interleave")
    for binding, buffer in enumerate((positions, surfaces, vertices, normals)):
        buffer.bind_to_storage_buffer(binding)
    dispatch_row(program, count, "first_triangle", triangle_count=count, **offsets)
    normals.release()
    surfaces.release()
    return vertices, positions


class MeshBuffer:
    """One interleaved vertex buffer and its vertex arrays, and the scene's images.

    A vertex is its position, normal, albedo (the triangle's times its corner's vertex
    colour) and alpha, surface coordinate (u, v, image layer, alpha image layer; layer -1:
    no image), transmission (tint, share) and glossy reflection (F0 rgb, roughness; F0
    black: none) and metallic share, twenty-three floats (VERTEX_LAYOUT).
    `see_through` says whether any triangle is cut out or transmits (the raster passes
    test alpha), `hashed` whether that differs from one VPL pattern to the next,
    `transmits` whether light passing some triangle is tinted, and `glossy` whether some
    triangle has a glossy layer (the light maps bounce its light then).
    The camera draws its `camera_triangles` and the lights' maps its `light_triangles`
    ((first, count) ranges of a sanitized Scene's ordering)."""

    def __init__(self, glc, scene):
        count = scene.triangle_count
        self.buffer, self.positions = interleave(glc, scene)
        self.see_through = scene.see_through
        self.glossy = scene.specular is not None
        self.hashed = scene.hashed
        self.transmits = scene.transmission is not None
        self.glc = glc
        self.images = SurfaceImages(glc.gl, scene.images)
        self.textured = bool(scene.images)  # some surface has an image
        self.triangle_count = count
        self.vertex_count = count * 3
        self.camera_triangles = scene.camera_triangles or (0, count)
        self.light_triangles = scene.light_triangles or (0, count)
        first, shadowing = self.light_triangles
        self.occluder_bounds = scene.bounds() if (first, shadowing) == (0, count) else \
            triangle_bounds(scene.triangles[first:first + shadowing])
        self.emission = None  # each triangle's emitted radiance (vec4), for the camera's glow
        if scene.emission is not None:
            emission = np.zeros((count, 4), dtype=np.float32)
            emission[:, :3] = scene.emission
            self.emission = glc.gl.buffer(emission.tobytes())
        self.open_sides = None  # a byte a triangle: the sides of its faces light reaches (gpu/closed_meshes.py)
        self._open_sides_of = None  # the array `open_sides` holds
        self._arrays = {}
        self.rim_lists = {}
        self._cluster_boxes = {}  # (first, count) -> (boxes, draw commands, clusters)
        self._cull_slot = {}  # (first, count) -> the slot of its commands the last view culled wrote
        self._culled = {}  # (first, count) -> {a view's matrix (bytes): the slot holding its commands}

    def show_open_sides(self, sides):
        """Hold `sides` ((T,) uint8 of gpu/closed_meshes.py, or None: every side open) for the
        G-buffer, uploaded again only when it is another array."""
        if sides is self._open_sides_of:
            return
        if self.open_sides is not None:
            self.open_sides.release()
            self.open_sides = None
        if sides is not None:
            padded = np.zeros(-(-len(sides) // 4) * 4, dtype=np.uint8)
            padded[:len(sides)] = sides
            self.open_sides = self.glc.gl.buffer(padded)
        self._open_sides_of = sides

    def vertex_array(self, program, indices=None):
        """The vertex array that draws the triangles with `program` (through `indices`)
        from their positions, its fragments' vertex buffer and images bound."""
        if (program, indices) not in self._arrays:
            self._arrays[program, indices] = self.glc.gl.vertex_array(
                program, [(self.positions, "3f", "in_position")], index_buffer=indices, index_element_size=4)
        self.bind_surfaces(program)
        return self._arrays[program, indices]

    def draw(self, program, mode, triangles, view_projection=None):
        """Draw the (first, count) range `triangles` with `program`; with `view_projection`
        (4 × 4), only its clusters whose boxes may lie in that view's frustum, in order."""
        first, count = triangles
        if not count:
            return
        if view_projection is None:
            self.vertex_array(program).render(mode, vertices=3 * count, first=3 * first)
            return
        boxes, commands, clusters = self._clusters(triangles)
        views = self._culled.setdefault(triangles, {})
        view = np.asarray(view_projection, np.float32).tobytes()
        slot = views.get(view)
        if slot is None:  # a view not culled lately (a second pass of one view draws its commands again)
            slot = self._cull_slot[triangles] = (self._cull_slot.get(triangles, -1) + 1) % CULL_SLOTS
            for overwritten in [key for key, used in views.items() if used == slot]:
                del views[overwritten]
            views[view] = slot
            cull = self.glc.compute("frustum_cull", CLUSTER_TRIANGLES=CLUSTER_TRIANGLES)
            boxes.bind_to_storage_buffer(6)
            commands.bind_to_storage_buffer(7)
            set_uniforms(cull, view_projection=view_projection, first_triangle=first, triangle_count=count,
                         first_command=slot * clusters)
            dispatch(cull, clusters, local=(64,))
        self.vertex_array(program).render_indirect(commands, mode, count=clusters, first=slot * clusters)

    def _clusters(self, triangles):
        """The boxes of the range's clusters of CLUSTER_TRIANGLES (shaders/cluster_bounds.comp),
        made once, with the range's draw commands (CULL_SLOTS views' worth) and the cluster
        count."""
        if triangles not in self._cluster_boxes:
            first, count = triangles
            clusters = -(-count // CLUSTER_TRIANGLES)
            gl = self.glc.gl
            boxes = gl.buffer(reserve=clusters * 32)
            commands = gl.buffer(bytes(clusters * CULL_COMMAND_BYTES * CULL_SLOTS))  # no draw before a cull
            program = self.glc.compute("cluster_bounds", CLUSTER_TRIANGLES=CLUSTER_TRIANGLES)
            self.buffer.bind_to_storage_buffer(6)
            boxes.bind_to_storage_buffer(7)
            set_uniforms(program, first_triangle=first, triangle_count=count)
            dispatch(program, clusters, local=(64,))
            self._cluster_boxes[triangles] = (boxes, commands, clusters)
        return self._cluster_boxes[triangles]

    def split_at_rim(self, hemisphere_view, hemisphere, raster=None):
        """Sort the triangles by a paraboloid hemisphere's rim plane on the GPU
        (shaders/rim_split.comp): returns one index buffer holding the triangles wholly in
        front and those crossing it, and the indirect draw commands (FRONT, CROSSING) that
        draw each list. Triangles wholly behind are in neither, so each hemisphere draws
        only its own; only the lights' triangles are sorted. Each hemisphere (0 or 1) has
        its own buffers: drawing one never waits on sorting the other. With `raster` (the
        uniforms of shaders/paraboloid_raster.glsl, its two buffers bound at 3 and 4), the
        triangles wholly in front whose box on the map spans at most RASTER_SPAN texels
        each way are rasterised into those buffers instead of listed."""
        gl = self.glc.gl
        capacity = self.vertex_count
        if hemisphere not in self.rim_lists:
            self.rim_lists[hemisphere] = (gl.buffer(reserve=max(2 * capacity, 1) * 4),
                                           gl.buffer(reserve=RIM_COMMAND_BYTES))
        lists, commands = self.rim_lists[hemisphere]
        for binding, buffer in enumerate((self.buffer, commands, lists)):
            buffer.bind_to_storage_buffer(binding)
        stages = [{}] if raster is None else [{"RASTER": 1, "RASTER_SPAN": RASTER_SPAN, "STAGE": stage}
                                              for stage in (1, 2)]
        first, count = self.light_triangles
        for stage, defines in enumerate(stages):
            program = self.glc.compute("rim_split", **defines)
            set_uniforms(program, hemisphere_view=hemisphere_view, first_triangle=first, triangle_count=count,
                         capacity=capacity, reset=True, first_invocation=0, **(raster or {}))
            if stage == 0:
                dispatch(program, 10, local=(64, 1, 1))
            if count:
                set_uniforms(program, reset=False)
                dispatch_row(program, count, "first_invocation")
        return lists, commands

    def bind_surfaces(self, program):
        """Bind the vertex buffer and images through which `program` reads surfaces by a
        triangle's number (shaders/triangle_corners.glsl, surface.glsl)."""
        self.buffer.bind_to_storage_buffer(SURFACE_VERTICES_BINDING)
        self.images.bind(program)

    def resources(self):
        """The vertex buffer and positions, the images, each hemisphere's rim-split lists
        and draw commands, and the culled ranges' cluster boxes and draw commands."""
        return (self.buffer, self.positions, *self.images.resources(),
                *(buffer for buffer in (self.emission, self.open_sides) if buffer is not None),
                *(buffer for buffers in self.rim_lists.values() for buffer in buffers),
                *(buffer for boxes, commands, _ in self._cluster_boxes.values() for buffer in (boxes, commands)))

    def release(self):
        for array in self._arrays.values():
            array.release()
        for resource in self.resources():
            resource.release()
