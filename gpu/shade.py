"""The camera's side: G-buffer, direct light per light, LPV lookup and composite."""
from dataclasses import dataclass

import moderngl
import numpy as np

from .closed_meshes import ROOM_DEFINES
from .context import (clear_depth_only, dispatch, dispatch_indirect, dispatch_row, made_or_refused, set_uniforms,
                      zero_buffer)
from .grids import VIEW_LATTICE
from .host_buffer import HostBuffer
from .mesh_buffer import SURFACE_VERTICES_BINDING
from .settings import INDIRECT_METHODS
from .specular_albedo import RASTER_UNIT

DISPLAY_CHANNELS = 3
"""Floats a pixel of the viewport's rows: RGB, as the viewport is never transparent (its
alpha would be 1 everywhere), a quarter less to read back than RGBA."""
DISC_LIST_START = np.array([0, 1, 1, 0], dtype=np.uint32).tobytes()
"""The head of the point emitters' disc list before it is filled (shaders/point_glow.comp):
a dispatch command of no workgroups, and no discs."""


class FrameTargets:
    """The camera's G-buffer and the output images of one resolution.

    The G-buffer is a depth texture and one packed RGBA32UI texel per pixel (normal and
    albedo, shaders/gbuffer.glsl), 20 bytes a pixel where position, normal and albedo as
    float images would take 52. A second texel (RGBA16UI, `specular`) holds the glossy
    reflection: F0, roughness and metallic. The raster writes neither: only the depth, the
    triangle each pixel sees (R32UI, `triangles`) and, in a scene with images, their colour
    (RGBA16F, `image_colours`); a compute pass makes the texels from them (render_gbuffer):
    the H100 has few raster units, and what they write per pixel counts
    (docs/performance.md, "Raster passes").
    """

    def __init__(self, gl, width, height):
        self.gl = gl
        self.size = (width, height)
        # `direct` is a VPL set's direct light, `direct_mean` the mean of the sets averaged
        (self.direct, self.direct_mean, self.indirect, self.combined, self.surface, self.triangles, self.specular,
         self.depth) = made_or_refused(
            gl, lambda: (*(gl.texture(self.size, 4, dtype="f4") for _ in range(4)),
                         gl.texture(self.size, 4, dtype="u4"), gl.texture(self.size, 1, dtype="u4"),
                         gl.texture(self.size, 4, dtype="u2"), gl.depth_texture(self.size)),
            f"{width} x {height} images", "lower the resolution")
        for texture in (self.surface, self.triangles, self.specular, self.depth):
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.depth.compare_func = ""
        self.framebuffer = gl.framebuffer(color_attachments=[self.triangles], depth_attachment=self.depth)
        self.image_colours = self.image_framebuffer = None  # the colour of surfaces' images, made on first use
        self.display = None  # the composite as the viewport's rows, made on its first request
        self.seen = gl.buffer(reserve=VIEW_LATTICE * VIEW_LATTICE * 16)  # seen_points' positions
        self.vpl_splats = self.warp_status = None  # debug passes (gpu/debug_views.py), made on first use
        self.splat_framebuffer = None
        self.glow = self.glow_framebuffer = None  # emissive surfaces' radiance, made on first use
        self.glow_sums = self.glow_discs = None  # the point emitters' glow (point_glow_buffers)
        self.passing_tint = self.tint_framebuffer = None  # transmitting surfaces' tint, made on first use
        self.reflections = None  # the light glossy surfaces reflect of their surroundings, made on first use
        self.reflecting = False  # whether the last composite wrote the reflections

    def image_colour_images(self):
        """The image colours the camera sees and the G-buffer's framebuffer that writes them
        beside the triangles, made on first use."""
        if self.image_colours is None:
            self.image_colours = self.gl.texture(self.size, 4, dtype="f2")
            self.image_colours.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self.image_framebuffer = self.gl.framebuffer(color_attachments=[self.triangles, self.image_colours],
                                                         depth_attachment=self.depth)
        return self.image_colours, self.image_framebuffer

    def debug_images(self):
        """The VPL Splats and Warp Status images, and the framebuffer the splats are drawn
        into (tested against the G-buffer's depth, never writing it), made on first use."""
        if self.vpl_splats is None:
            self.vpl_splats, self.warp_status = (self.gl.texture(self.size, 4, dtype="f4") for _ in range(2))
            self.splat_framebuffer = self.gl.framebuffer(color_attachments=[self.vpl_splats],
                                                         depth_attachment=self.depth)
            self.splat_framebuffer.depth_mask = False
        return self.vpl_splats, self.warp_status, self.splat_framebuffer

    def glow_images(self):
        """The glow image and its framebuffer (tested against the G-buffer's depth, never
        writing it), made on first use."""
        if self.glow is None:
            self.glow = self.gl.texture(self.size, 4, dtype="f4")
            self.glow_framebuffer = self.gl.framebuffer(color_attachments=[self.glow], depth_attachment=self.depth)
            self.glow_framebuffer.depth_mask = False
        return self.glow, self.glow_framebuffer

    def point_glow_buffers(self, count):
        """The sums of the point emitters' glow and the share of each pixel they cover (four
        floats a pixel) and the list of `count` emitters' discs headed by its dispatch
        command (shaders/point_glow.comp), made on first use and grown to `count`."""
        if self.glow_sums is None:
            self.glow_sums = self.gl.buffer(reserve=self.size[0] * self.size[1] * 4 * 4)
        if self.glow_discs is None or self.glow_discs.size < len(DISC_LIST_START) + 4 * count:
            if self.glow_discs is not None:
                self.glow_discs.release()
            self.glow_discs = self.gl.buffer(reserve=len(DISC_LIST_START) + 4 * max(count, 1))
        return self.glow_sums, self.glow_discs

    def tint_images(self):
        """The tint image of what is seen through transmitting surfaces and its
        framebuffer (tested against the G-buffer's depth, never writing it), made on first
        use."""
        if self.passing_tint is None:
            self.passing_tint = self.gl.texture(self.size, 4, dtype="f2")
            self.passing_tint.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self.tint_framebuffer = self.gl.framebuffer(color_attachments=[self.passing_tint],
                                                        depth_attachment=self.depth)
            self.tint_framebuffer.depth_mask = False
        return self.passing_tint, self.tint_framebuffer

    def reflection_image(self):
        """The reflections image, made on first use."""
        if self.reflections is None:
            self.reflections = self.gl.texture(self.size, 4, dtype="f4")
        return self.reflections

    def display_buffer(self):
        """The viewport's rows: in the host's memory where the driver maps it
        (gpu/host_buffer.py), else a buffer the driver reads back."""
        if self.display is None:
            size = self.size[0] * self.size[1] * DISPLAY_CHANNELS * 4
            self.display = HostBuffer.make(self.gl, size) or self.gl.buffer(reserve=size)
        return self.display

    def read(self, name):
        """An output image as (height, width, 3) float32, top row first."""
        return np.ascontiguousarray(self.read_rgba(name)[..., :3])

    def read_rgba(self, name):
        """An output image with its alpha as (height, width, 4) float32, top row first: the
        combined image's alpha is the coverage (1 where the camera sees a surface or an
        emitter, 0 where it sees the background)."""
        width, height = self.size
        if name == "reflections" and not self.reflecting:
            return np.zeros((height, width, 4), np.float32)
        texture = self.direct_mean if name == "direct" else getattr(self, name)  # the direct pass: the sets' mean
        return np.frombuffer(texture.read(), dtype=np.float32).reshape(height, width, 4)[::-1]

    def read_display_into(self, out):
        """The composite as shade_indirect wrote it into the display buffer (DISPLAY_CHANNELS
        float32 a pixel, bottom row first: the layout Blender's textures take) into `out`,
        a writable buffer of width x height x DISPLAY_CHANNELS floats; returns it as
        (height, width, DISPLAY_CHANNELS)."""
        self.display.read_into(out)
        width, height = self.size
        return np.frombuffer(out, dtype=np.float32).reshape(height, width, DISPLAY_CHANNELS)

    def resources(self):
        """Every texture and buffer made so far in GPU memory (the display and debug ones on
        request)."""
        return tuple(resource for resource in (self.depth, self.surface, self.triangles, self.image_colours,
                                               self.specular, self.direct, self.direct_mean, self.indirect,
                                               self.combined,
                                               self.seen, self.vpl_splats, self.warp_status, self.glow,
                                               self.glow_sums, self.glow_discs,
                                               self.passing_tint, self.reflections,
                                               None if isinstance(self.display, HostBuffer) else self.display)
                     if resource is not None)

    def release(self):
        self.framebuffer.release()
        for framebuffer in (self.image_framebuffer, self.splat_framebuffer, self.glow_framebuffer,
                            self.tint_framebuffer):
            if framebuffer is not None:
                framebuffer.release()
        for resource in self.resources():
            resource.release()
        if isinstance(self.display, HostBuffer):
            self.display.release()


def gbuffer_uniforms(camera):
    """The uniforms of shaders/gbuffer.glsl (texture units 0 and 1)."""
    inverse = np.linalg.inv(camera.projection.astype(np.float64) @ camera.view.astype(np.float64))
    return {"g_depth": 0, "g_surface": 1, "inverse_view_projection": inverse}


def bind_gbuffer(targets):
    targets.depth.use(location=0)
    targets.surface.use(location=1)


SPECULAR_UNIT, TINT_UNIT, TRIANGLES_UNIT = 3, 4, 5
"""The texture units of the G-buffer's glossy texel, the map's tint and the triangles the
camera sees in shade_direct (the RSM's position is 2)."""


def cut_out_defines(mesh):
    """The defines of the raster passes' fragment shaders: CUT_OUT where some triangle is
    cut out or transmits (a discard costs the early depth test, so only then)."""
    return {"CUT_OUT": 1} if mesh.see_through else {}


def render_gbuffer(glc, mesh, camera, targets, pattern=0):
    """Rasterise the scene from the camera, cut-outs hashed in VPL pattern `pattern`, into
    each pixel's depth and triangle (shaders/gbuffer.frag); make the surface texels from
    them (gbuffer_resolve.comp), the sides of solids' faces no light reaches black
    (MeshBuffer.show_open_sides); tint what is seen through transmitting surfaces. Clears
    the direct image for the lights to add into."""
    gl = glc.gl
    imaged = {"SURFACE_IMAGES": 1} if mesh.textured else {}
    program = glc.program("raster", "gbuffer", **cut_out_defines(mesh), **imaged)
    framebuffer = targets.image_colour_images()[1] if imaged else targets.framebuffer
    framebuffer.use()
    framebuffer.viewport = (0, 0, *targets.size)
    clear_depth_only(framebuffer)  # every reader of the surface texels asks the depth first
    gl.enable(moderngl.DEPTH_TEST)
    gl.disable(moderngl.CULL_FACE)
    uniforms = {"view_projection": camera.projection @ camera.view, "cut_out_pattern": pattern}
    set_uniforms(program, **uniforms)
    mesh.draw(program, moderngl.TRIANGLES, mesh.camera_triangles, uniforms["view_projection"])
    resolve_gbuffer(glc, mesh, camera, targets, imaged)
    if mesh.transmits:
        tint_seen_through(glc, mesh, targets, uniforms)
    glc.clear(targets.direct)


def resolve_gbuffer(glc, mesh, camera, targets, imaged):
    """The G-buffer's surface texels from the triangle each pixel sees (and with
    `imaged` the colour of its image there; shaders/gbuffer_resolve.comp)."""
    shut = {"SHUT_SIDES": 1} if mesh.open_sides is not None else {}
    program = glc.compute("gbuffer_resolve", **shut, **imaged)
    if shut:
        mesh.open_sides.bind_to_storage_buffer(0)
    mesh.buffer.bind_to_storage_buffer(SURFACE_VERTICES_BINDING)
    targets.depth.use(location=0)
    targets.triangles.use(location=1)
    if imaged:
        targets.image_colours.use(location=2)
    targets.surface.bind_to_image(0, read=False, write=True)
    targets.specular.bind_to_image(1, read=False, write=True)
    glc.use_specular_albedo(program, RASTER_UNIT)
    set_uniforms(program, **gbuffer_uniforms(camera), g_triangles=1, g_image_colours=2)
    dispatch(program, *targets.size)


def tint_seen_through(glc, mesh, targets, uniforms):
    """Multiply the G-buffer's albedo by the tint of the transmitting surfaces in front of
    it (shaders/passing_tint.frag, gbuffer_tint.comp)."""
    gl = glc.gl
    tint, framebuffer = targets.tint_images()
    framebuffer.use()
    framebuffer.viewport = (0, 0, *targets.size)
    framebuffer.clear(1.0, 1.0, 1.0, 1.0)
    program = glc.program("raster", "passing_tint", TINT_ATTACHMENT=0)
    set_uniforms(program, **uniforms)
    multiply_blend(gl, lambda: mesh.draw(program, moderngl.TRIANGLES, mesh.camera_triangles,
                                         uniforms["view_projection"]))
    program = glc.compute("gbuffer_tint")
    targets.surface.bind_to_image(0, read=True, write=True)
    tint.use(location=0)
    set_uniforms(program, passing_tint=0)
    dispatch(program, *targets.size)


def multiply_blend(gl, draw):
    """Run `draw` with its colours multiplied into the framebuffer's, behind the depth
    (depth test "<"), and put the blend back."""
    gl.enable(moderngl.BLEND)
    gl.blend_func = moderngl.DST_COLOR, moderngl.ZERO
    try:
        draw()
    finally:
        gl.blend_func = moderngl.DEFAULT_BLENDING
        gl.disable(moderngl.BLEND)


def render_glow(glc, mesh, camera, targets, point_emitters=None):
    """Draw the radiance the camera sees of the emissive surfaces (when the mesh has
    them) and of the point emitters (a buffer of emitter rows with a count: glow_points),
    behind the G-buffer's depth, into the glow image."""
    gl = glc.gl
    glow, framebuffer = targets.glow_images()
    glc.clear(glow)
    framebuffer.use()
    framebuffer.viewport = (0, 0, *targets.size)
    gl.enable(moderngl.DEPTH_TEST)
    view_projection = camera.projection @ camera.view
    if mesh.emission is not None:
        program = glc.program("raster", "glow")
        gl.depth_func = "<="
        mesh.emission.bind_to_storage_buffer(0)
        set_uniforms(program, view_projection=view_projection)
        mesh.draw(program, moderngl.TRIANGLES, mesh.camera_triangles, view_projection)
        gl.depth_func = "<"
    if point_emitters is not None:
        glow_points(glc, targets, view_projection, camera, *point_emitters)


def glow_points(glc, targets, view_projection, camera, buffer, count):
    """The glow of `count` point emitters (emitter rows in `buffer`) into the glow image,
    each disc added into its pixels by a compute pass (shaders/point_glow.comp)."""
    sums, discs = targets.point_glow_buffers(count)
    zero_buffer(glc, sums)
    discs.write(DISC_LIST_START)
    glow = {"camera_position": tuple(map(float, camera.position)), "pixel_angle": camera.pixel_angle(targets.size[1]),
            "view_projection": view_projection, "g_depth": 0}
    for binding, bound in enumerate((buffer, sums, discs)):
        bound.bind_to_storage_buffer(binding)
    targets.depth.use(location=0)
    program = glc.compute("point_glow", STAGE=0)
    set_uniforms(program, **glow)
    dispatch_row(program, count, "first_emitter", emitter_count=count)
    program = glc.compute("point_glow", STAGE=2)
    set_uniforms(program, **glow)
    dispatch_indirect(program, discs)
    program = glc.compute("point_glow", STAGE=1)
    targets.glow.bind_to_image(0, read=True, write=True)
    sums.bind_to_storage_buffer(1)
    dispatch(program, *targets.size)


def draw_points(gl, program, point_sets):
    """Draw one point per entry of each (buffer, count) of `point_sets` (the buffer at
    storage binding 0, read by the vertex shader), added up into the framebuffer in use."""
    gl.enable(moderngl.BLEND | moderngl.PROGRAM_POINT_SIZE)
    gl.blend_func = moderngl.ONE, moderngl.ONE
    points = gl.vertex_array(program, [])
    for buffer, count in point_sets:
        buffer.bind_to_storage_buffer(0)
        points.render(moderngl.POINTS, vertices=count)
    points.release()
    gl.disable(moderngl.BLEND | moderngl.PROGRAM_POINT_SIZE)


def add_irradiance(glc, targets, uniforms, irradiance):
    """Add albedo / π times the `irradiance` image (a texture) into the direct image: the
    light of emitters gathered or looked up at every pixel. `uniforms` are the G-buffer's."""
    program = glc.compute("add_irradiance")
    bind_gbuffer(targets)
    irradiance.use(location=2)
    targets.direct.bind_to_image(0, read=True, write=True)
    set_uniforms(program, **uniforms, gathered=2)
    dispatch(program, *targets.size)


VIEW_MAP_EDGE = 0.9
"""A sun's view map (gpu/light_maps.py fit_view_maps) shades the pixels within this share
of its half-width of its centre (the filter's taps beyond its edge would find no
blocker); coarser maps the rest."""


def seen_room_defines(binding):
    """The defines of a pass that reads shaders/seen_room.glsl, its sides buffer at `binding`."""
    return dict(ROOM_DEFINES, SIDES_BINDING=binding)


def bind_seen_room(program, targets, room_sides, binding, unit):
    """Bind what shaders/seen_room.glsl reads: the mesh's sides-and-rooms buffer at
    `binding` (seen_room_defines) and the G-buffer's triangles at texture `unit`."""
    room_sides.bind_to_storage_buffer(binding)
    targets.triangles.use(location=unit)
    set_uniforms(program, g_triangles=unit)


def shade_direct(glc, targets, camera, rsm, shadow_bias, shadow, inside=None, outside=None, room=None):
    """Add one light's shadowed Lambert and glossy terms into the direct image; `shadow` the uniforms
    of its soft shadow (gpu/soft_shadows.py shadow_uniforms). `inside` and `outside`
    (a sun's orthographic view maps, or None) keep to the pixels within VIEW_MAP_EDGE of
    the one and beyond it of the other. With `room` (the mesh's sides-and-rooms buffer and
    the light's room, gpu/closed_meshes.py) it lights only the pixels in its room."""
    program = glc.compute("shade_direct", **(seen_room_defines(0) if room is not None else {}))
    bind_gbuffer(targets)
    if room is not None:
        bind_seen_room(program, targets, room[0], 0, TRIANGLES_UNIT)
        set_uniforms(program, light_room=room[1])
    rsm.position.use(location=2)
    targets.specular.use(location=SPECULAR_UNIT)
    if rsm.tint is not None:
        rsm.tint.use(location=TINT_UNIT)
    targets.direct.bind_to_image(0, read=True, write=True)
    set_uniforms(program, **gbuffer_uniforms(camera), rsm_position=2, g_specular=SPECULAR_UNIT, rsm_tint=TINT_UNIT,
                 use_tint=rsm.tint is not None, **rsm.lookup_uniforms(),
                 texel_angle=2.0 / rsm.resolution, ortho_texel=rsm.ortho_texel, shadow_bias=shadow_bias,
                 **rsm.light_uniforms, **shadow, use_inside=inside is not None, use_outside=outside is not None,
                 inside_matrix=np.eye(4) if inside is None else inside.face_matrices[0],
                 outside_matrix=np.eye(4) if outside is None else outside.face_matrices[0], view_map_edge=VIEW_MAP_EDGE)
    dispatch(program, *targets.size)


def seen_points(glc, targets, camera):
    """The surface points the camera sees on a lattice of VIEW_LATTICE^2 pixels, (k, 3)
    float64: where gpu/grids.py places the grids."""
    program = glc.compute("view_points")
    bind_gbuffer(targets)
    targets.seen.bind_to_storage_buffer(0)
    set_uniforms(program, **gbuffer_uniforms(camera), lattice=VIEW_LATTICE)
    dispatch(program, VIEW_LATTICE, VIEW_LATTICE)
    points = np.frombuffer(targets.seen.read(), dtype=np.float32).reshape(-1, 4)
    return points[points[:, 3] > 0, :3].astype(np.float64)


@dataclass
class GBufferRecord:
    """What the G-buffer says of every pixel, (height, width, ...) top row first, read back
    for the corrections toward Cycles: the surface's position (where `seen`; elsewhere the
    ray's direction) in the scene's local frame, its normal and albedo, and a pixel's width
    there (`footprint`)."""

    position: np.ndarray
    normal: np.ndarray
    albedo: np.ndarray
    seen: np.ndarray
    footprint: np.ndarray

    @property
    def size(self):
        return self.seen.shape[1], self.seen.shape[0]


def read_gbuffer_record(glc, targets, camera):
    """The G-buffer as a GBufferRecord."""
    width, height = targets.size
    program = glc.compute("gbuffer_read")
    bind_gbuffer(targets)
    buffer = glc.gl.buffer(reserve=width * height * 48)
    try:
        buffer.bind_to_storage_buffer(0)
        set_uniforms(program, **gbuffer_uniforms(camera))
        dispatch(program, width, height)
        texels = np.frombuffer(buffer.read(), dtype=np.float32).reshape(height, width, 3, 4)[::-1]
    finally:
        buffer.release()
    position, normal, albedo = (np.ascontiguousarray(texels[:, :, i, :3]) for i in range(3))
    seen = texels[:, :, 0, 3] > 0
    if camera.projection[3, 3] == 1:  # orthographic: a pixel is as wide at every distance
        distance = 1.0
    else:
        distance = np.linalg.norm(position - camera.position.astype(np.float32), axis=-1)
    footprint = np.where(seen, distance, 0.0) * camera.pixel_angle(height)
    return GBufferRecord(position, normal, albedo, seen, footprint.astype(np.float32))


@dataclass
class ReflectionInputs:
    """What the reflections of shaders/reflections.glsl read besides the G-buffer: the
    world's lighting map with its mip chain (None: no world), the occupancy a ray that
    leaves the screen is marched through with its levels' layers (None: not marched), how
    far a ray goes and the VPL pattern that draws the rays."""

    world: object
    occupancy: object
    layers: tuple
    trace_length: float
    pattern: int


def shade_indirect(glc, targets, camera, indirect, levels, phases, intensity, display=False, accumulated=0,
                   glow=False, world=None, reflections=None, room_sides=None):
    """Look the indirect grids (gpu/indirect.py: `levels` nested levels of `phases` grids
    each) up at every pixel and write the indirect and combined images, and with `display`
    the combined one into the display buffer too. With `accumulated` > 0 the indirect
    image holds the mean of that many VPL sets' light, which this set's joins. With `glow`
    the composite adds the glow image (render_glow); with `world` (the background map's
    texture, gpu/world_light.py) it shows the world where the camera sees no surface; with
    `reflections` (ReflectionInputs) it adds what glossy surfaces reflect. With
    `room_sides` (the mesh's sides-and-rooms buffer, where the scene has rooms) a grid
    whose cells know their rooms (the method's `cell_rooms`) is read only in the room of
    the side looked up (gpu/closed_meshes.py)."""
    march = reflections is not None and reflections.occupancy is not None
    defines = {"REFLECTIONS": 1} if reflections is not None else {}
    cell_rooms = indirect.cell_rooms() if room_sides is not None else None
    if cell_rooms is not None:
        defines.update(seen_room_defines(1))
    if march:
        defines.update(MARCH_ESCAPE=1, MARCH_LEVELS=len(reflections.layers))
    program = glc.compute("shade_indirect", LEVELS=levels, PHASES=phases,
                          INDIRECT=INDIRECT_METHODS.index(indirect.name), **defines)
    bind_gbuffer(targets)
    units = indirect.lookup_uniforms(first_unit=2)
    targets.direct.bind_to_image(0, read=True, write=False)
    targets.indirect.bind_to_image(1, read=True, write=True)
    targets.combined.bind_to_image(2, read=True, write=True)
    targets.direct_mean.bind_to_image(4, read=True, write=True)
    if glow:
        targets.glow.bind_to_image(3, read=True, write=False)
    if display:
        targets.display_buffer().bind_to_storage_buffer(0)
    grids = indirect.grids
    world_unit = 1 + max(int(np.max(unit)) for unit in units.values())
    if world is not None:
        world.use(location=world_unit)
    set_uniforms(program, **gbuffer_uniforms(camera), **units, write_display=display,
                 grid_origins=np.array([grid.origin for grid in grids]),
                 cell_sizes=np.array([grid.cell_size for grid in grids]), grid_size=grids[0].size,
                 intensity=intensity, accumulated=accumulated, add_glow=glow, add_world=world is not None,
                 world_background=world_unit)
    targets.reflecting = reflections is not None
    if reflections is not None:
        targets.reflection_image().bind_to_image(5, read=True, write=True)
        targets.specular.use(location=world_unit + 1)
        if reflections.world is not None:
            reflections.world.use(location=world_unit + 2)
        glc.use_specular_albedo(program, world_unit + 3)
        march_uniforms = (reflections.occupancy.march_uniforms(list(reflections.layers), first_unit=world_unit + 4)
                          if march else {})
        set_uniforms(program, **march_uniforms, g_specular=world_unit + 1, world_reflection=world_unit + 2,
                     reflect_world=reflections.world is not None,
                     reflection_levels=int(np.log2(max(reflections.world.size))) if reflections.world is not None else 0,
                     view_projection=camera.projection @ camera.view, view_z_row=tuple(map(float, camera.view[2])),
                     projection_z=tuple(float(camera.projection[i, j]) for i, j in ((2, 2), (2, 3), (3, 2), (3, 3))),
                     trace_length=reflections.trace_length,
                     reflection_pattern=reflections.pattern)
    if cell_rooms is not None:  # after the march's units
        bind_seen_room(program, targets, room_sides, 1, world_unit + 6)
        cell_rooms.use(location=world_unit + 7)
        set_uniforms(program, cell_rooms=world_unit + 7)
    dispatch(program, *targets.size)
