"""Reflective shadow maps: the cube faces (CM) or paraboloid hemispheres (DPM) a light
needs, or one orthographic map for a sun.

All faces of one light share an atlas (up to three faces a row) of three float textures:
position + shadow distance, light-facing normal + surfel area, reflected flux; and, in a
scene with transmitting surfaces, a fourth: the tint of the light reaching the texel's
surface through them. A texel's
flux is albedo x intensity x the texel's solid angle (METHOD §2), so the texels' fluxes
add up to the power the light delivers to visible surfaces times their albedo.
"""
import math
from dataclasses import dataclass

import moderngl
import numpy as np

from .context import clear_depth_only, dispatch, set_uniforms, zero_buffer
from .mesh_buffer import CROSSING, FRONT
from .scene import look_at_view, perspective
from .shade import cut_out_defines, multiply_blend
from .specular_albedo import RASTER_UNIT

LIGHT_KIND_INDEX = {"POINT": 0, "SPOT": 1, "AREA": 2, "SUN": 3}
PROJECTION_CUBE, PROJECTION_PARABOLOID, PROJECTION_ORTHO = 0, 1, 2
ATLAS_COLUMNS = 3
NEAREST_BINDING = 3
"""Where rim_split.comp, rsm_resolve.comp and rsm.frag find the nearest depth of each texel
a compute pass rasterised, and at the next binding its triangle (paraboloid_raster.glsl)."""


@dataclass
class ReflectiveShadowMap:
    """One light's RSM atlas and what the shading needs to look it up."""

    glc: object
    light: object
    resolution: int
    projection_kind: int
    face_matrices: np.ndarray           # (faces, 4, 4): view-projection, or hemisphere view for DPM
    face_origins: np.ndarray            # (faces, 2) lower-left texel of each face in the atlas
    atlas_size: tuple
    position: moderngl.Texture
    normal: moderngl.Texture
    flux: moderngl.Texture
    light_uniforms: dict
    ortho_texel: float                  # sun: a texel's width in world units, else 0
    flux_bound: float                   # no channel of the total flux can exceed this
    tint: moderngl.Texture = None       # what transmitting surfaces in front multiply its light by (None: no such surface)
    glossy: bool = False                # its flux.w holds its surfaces' glossy share (shaders/glossy_word.glsl)

    @property
    def face_count(self):
        return len(self.face_matrices)

    def lookup_uniforms(self):
        """The uniforms of shaders/rsm_lookup.glsl for this map (faces padded to six)."""
        matrices = np.zeros((6, 4, 4))
        matrices[:self.face_count] = self.face_matrices
        origins = np.zeros((6, 2), dtype=np.int32)
        origins[:self.face_count] = self.face_origins
        return {"lookup_matrix": matrices, "lookup_origin": origins, "lookup_faces": self.face_count,
                "lookup_resolution": self.resolution,
                "lookup_paraboloid": self.projection_kind == PROJECTION_PARABOLOID}

    def read(self, texture):
        """An atlas texture as a (height, width, 4) float32 array (GL's bottom row first)."""
        width, height = self.atlas_size
        return np.frombuffer(texture.read(), dtype=np.float32).reshape(height, width, 4)

    def release(self):
        self.glc.recycle(self.position, self.normal, self.flux, *((self.tint,) if self.tint is not None else ()))


def light_frame(light):
    """The light's local axes in world space: right (+X), up (+Y), back (+Z = -direction)."""
    back = -light.direction
    up = light.up - back * np.dot(light.up, back)
    if np.linalg.norm(up) < 1e-6:
        up = np.array([0.0, 0.0, 1.0]) if abs(back[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
        up = up - back * np.dot(up, back)
    up /= np.linalg.norm(up)
    return np.cross(up, back), up, back


def cube_face_count(light):
    """How many cube faces the light needs (METHOD §1): all six for a point light, the
    front one for a spot of half-angle <= 45 degrees (its cone lies inside it), the front
    hemisphere's five for a wider spot or an area light."""
    if light.kind == "POINT":
        return 6
    return 1 if light.kind == "SPOT" and light.spot_size / 2 <= math.pi / 4 + 1e-9 else 5


def cube_faces(light):
    """(forward, up) of each cube face the light needs, front face first, then the sides
    and the back."""
    right, up, back = light_frame(light)
    faces = [(-back, up), (right, up), (-right, up), (up, back), (-up, back), (back, up)]
    return faces[:cube_face_count(light)]


def hemisphere_count(light):
    """How many paraboloid hemispheres the light needs: both for a point light, the front
    one for a spot or area light."""
    return 2 if light.kind == "POINT" else 1


def hemisphere_views(light, origin):
    """World-to-hemisphere matrices (+z the axis) of the paraboloid maps the light needs,
    front first.

    The back hemisphere negates z and mirrors x, so both maps keep their orientation.
    """
    right, up, back = light_frame(light)
    front = np.eye(4)
    front[:3, :3] = np.stack([right, up, -back])
    rear = np.eye(4)
    rear[:3, :3] = np.stack([-right, up, back])
    views = [front, rear][:hemisphere_count(light)]
    for view in views:
        view[:3, 3] = -view[:3, :3] @ origin
    return views


def map_face_count(light, method):
    """How many faces render_rsm draws for the light: a sun's one orthographic map, else
    its paraboloid hemispheres ("dpm") or cube faces."""
    if light.kind == "SUN":
        return 1
    return hemisphere_count(light) if method == "dpm" else cube_face_count(light)


def face_atlas_size(face_count, resolution):
    """The (width, height) of an atlas of `face_count` faces, up to ATLAS_COLUMNS a row."""
    return min(face_count, ATLAS_COLUMNS) * resolution, -(-face_count // ATLAS_COLUMNS) * resolution


def light_uniforms(light, position):
    cos_half = math.cos(light.spot_size / 2)
    blend_width = (1.0 - cos_half) * light.spot_blend
    return {
        "light_kind": LIGHT_KIND_INDEX[light.kind],
        "light_position": tuple(float(v) for v in position),
        "light_direction": tuple(float(v) for v in light.direction),
        "light_peak": tuple(float(v) for v in light.peak_intensity),
        "spot_cos_half": cos_half,
        "spot_smooth": 1.0 / blend_width if blend_width > 1e-12 else 1e20,
    }


def sun_half_width(light, bounds, fitted=False):
    """Half the width across a sun's rays of its map of `bounds`: the box's bounding
    sphere's radius, or `fitted`, the most any corner of the box lies from its centre
    along the light's +X or +Y axis (the box's square shadow on the map's plane)."""
    low, high = (np.asarray(corner, dtype=np.float64) for corner in bounds)
    if not fitted:
        return max(float(np.linalg.norm(high - low)) / 2, 1e-6)
    right, up, _ = light_frame(light)
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
    offsets = corners - (low + high) / 2
    return max(float(np.max(np.abs(offsets @ np.stack([right, up], axis=1)))), 1e-6)


def resolve_rasterised(glc, mesh, textures, faces, face_uniforms, glossy, uniforms):
    """Write every texel of a paraboloid map's faces from what rim_split.comp rasterised
    (shaders/rsm_resolve.comp): position, normal and flux where it kept a triangle, empty
    elsewhere. Its nearest depths and triangles are bound at NEAREST_BINDING."""
    program = glc.compute("rsm_resolve", **glossy)
    glc.use_specular_albedo(program, RASTER_UNIT)
    mesh.bind_surfaces(program)
    for unit, texture in enumerate(textures):
        texture.bind_to_image(unit, read=False, write=True)
    for matrix, face in zip(faces, face_uniforms):
        set_uniforms(program, hemisphere_view=matrix, projection_kind=PROJECTION_PARABOLOID, ortho_texel_area=0.0,
                     **face, **uniforms)
        dispatch(program, int(face["resolution"]), int(face["resolution"]))


def render_rsm(glc, mesh, light, resolution, bounds, method="cm", tessellation_unit=None, reach=None, fitted=False,
               pattern=0):
    """Rasterise the light's RSM faces: cube faces for "cm", hemispheres for "dpm",
    tessellated hemispheres (thesis eq. 8-9, unit in map units) when a unit is given. A
    sun's map covers `bounds` across its rays (its bounding sphere, or `fitted` the box's
    own shadow: sun_half_width) and, along them, `reach` (a box holding every occluder;
    `bounds` when None). Cut-outs are hashed in VPL pattern `pattern`; the flux that
    passes transmitting surfaces is tinted by them (a second pass)."""
    low, high = bounds
    centre = (low + high) / 2
    radius = sun_half_width(light, bounds, fitted) if light.kind == "SUN" else \
        max(float(np.linalg.norm(high - low)) / 2, 1e-6)
    near = far = 0.0
    if light.kind == "SUN":
        depth_low, depth_high = bounds if reach is None else reach
        corners = np.array([[x, y, z] for x in (depth_low[0], depth_high[0]) for y in (depth_low[1], depth_high[1])
                            for z in (depth_low[2], depth_high[2])])
        along = max(radius, float(np.max(np.linalg.norm(corners - centre, axis=1))))
        origin = centre - light.direction * along * 1.01
        _, up, _ = light_frame(light)
        view = look_at_view(origin, light.direction, up)
        depth = 2.02 * along
        projection = np.diag([1 / radius, 1 / radius, -2 / depth, 1.0])
        projection[2, 3] = -1.0
        kind, faces = PROJECTION_ORTHO, [projection @ view]
        ortho_texel = 2 * radius / resolution
        flux_bound = float(np.max(light.rgb_power)) * (2 * radius) ** 2
    else:
        origin = light.position
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
        far = float(np.max(np.linalg.norm(corners - origin, axis=1))) * 1.01 + 1e-6
        near = far * 1e-5
        if method == "dpm":
            kind, faces = PROJECTION_PARABOLOID, hemisphere_views(light, origin)
        else:
            projection = perspective(math.pi / 2, 1.0, near, far)
            kind = PROJECTION_CUBE
            faces = [projection @ look_at_view(origin, forward, up) for forward, up in cube_faces(light)]
        ortho_texel = 0.0
        flux_bound = float(np.max(light.rgb_power))
    atlas_size = face_atlas_size(len(faces), resolution)
    origins = np.array([((f % ATLAS_COLUMNS) * resolution, (f // ATLAS_COLUMNS) * resolution)
                        for f in range(len(faces))], dtype=np.int32)
    gl = glc.gl
    textures = [glc.texture(atlas_size, 4) for _ in range(3)]
    tint = glc.texture(atlas_size, 4, dtype="f2") if mesh.transmits else None
    depth = glc.depth_renderbuffer(atlas_size)
    framebuffer = gl.framebuffer(color_attachments=textures + ([tint] if tint is not None else []),
                                 depth_attachment=depth)
    tessellated = kind == PROJECTION_PARABOLOID and tessellation_unit is not None
    if tessellated:
        gl.patch_vertices = 3

    def face_programs(fragment, **defines):
        if tessellated:
            return [glc.program("pass_through", fragment, geometry="dpm", tessellation="tdpm", **defines)] * 2
        if kind == PROJECTION_PARABOLOID:  # in front: project per vertex; crossing the rim: clip first
            return [glc.program("dpm", fragment, **defines), glc.program("pass_through", fragment, geometry="dpm",
                                                                         **defines)]
        return [glc.program("raster", fragment, **defines)]
    tinted = {"TINT_MAP": 1} if tint is not None else {}
    glossy = {"GLOSSY_LAYER": 1} if mesh.glossy else {}
    # Small triangles in front of a hemisphere's rim rasterised by a compute pass, where
    # every fragment is rsm.frag's alone (no cut-outs, no tint pass): rim_split.comp.
    rasterised = kind == PROJECTION_PARABOLOID and not tessellated and not mesh.transmits and \
        not cut_out_defines(mesh)
    passes = [(face_programs("rsm", **cut_out_defines(mesh), **tinted, **glossy,
                             **({"RASTERISED": 1} if rasterised else {})), False)]
    if mesh.transmits:
        passes.append((face_programs("passing_tint", TINT_ATTACHMENT=2, **tinted), True))
    uniforms = light_uniforms(light, origin)
    if not rasterised:  # else rsm_resolve.comp writes every texel
        glc.clear(*textures, *([tint] if tint is not None else []))  # faster than the framebuffer's colour clear
    framebuffer.use()
    clear_depth_only(framebuffer)
    gl.enable(moderngl.DEPTH_TEST)
    gl.disable(moderngl.CULL_FACE)
    mode = moderngl.PATCHES if tessellated else moderngl.TRIANGLES
    nearest = [glc.scratch_buffer(atlas_size[0] * atlas_size[1] * 4) for _ in range(2)] if rasterised else []
    for binding, buffer in enumerate(nearest, start=NEAREST_BINDING):
        zero_buffer(glc, buffer)
        buffer.bind_to_storage_buffer(binding)
    face_uniforms = [{"face_origin": tuple(float(v) for v in face_origin), "resolution": float(resolution),
                      "atlas_width": atlas_size[0], "near": near, "far": far} for face_origin in origins]
    rims = [mesh.split_at_rim(matrix, face, face_uniforms[face] if rasterised else None)
            for face, matrix in enumerate(faces)] if kind == PROJECTION_PARABOLOID else None
    if rasterised:
        resolve_rasterised(glc, mesh, textures, faces, face_uniforms, glossy, uniforms)
    for programs, tinting in passes:
        for program in programs:
            glc.use_specular_albedo(program, RASTER_UNIT)
        framebuffer.depth_mask = not tinting
        for face, (matrix, face_origin) in enumerate(zip(faces, origins)):
            framebuffer.viewport = (int(face_origin[0]), int(face_origin[1]), resolution, resolution)
            for program in programs:
                set_uniforms(program, view_projection=matrix, hemisphere_view=matrix, projection_kind=kind,
                             ortho_texel_area=ortho_texel ** 2, tessellation_unit=float(tessellation_unit or 0.0),
                             cut_out_pattern=pattern, **face_uniforms[face], **uniforms)
            if kind == PROJECTION_PARABOLOID:
                lists, commands = rims[face]
                draw = lambda: [mesh.vertex_array(program, lists).render_indirect(  # noqa: E731
                    commands, mode, count=1, first=command) for program, command in zip(programs, (FRONT, CROSSING))]
            else:
                draw = lambda: mesh.draw(programs[0], mode, mesh.light_triangles, matrix)  # noqa: E731
            if tinting:
                multiply_blend(gl, draw)
            else:
                draw()
    framebuffer.depth_mask = True
    framebuffer.release()
    glc.recycle(depth, *nearest)
    return ReflectiveShadowMap(glc, light, resolution, kind, np.array(faces), origins, atlas_size, *textures,
                               uniforms, ortho_texel, flux_bound, tint, mesh.glossy)
