"""Blender depsgraph -> `gpu.scene.Scene`: world-space triangles, albedo, lights, camera.

Everything is read with `foreach_get` into numpy and transformed in bulk, so a mesh of a
million triangles costs a fraction of a second and a thousand instances of one mesh cost
one read of that mesh and one batched transform.
"""
from dataclasses import dataclass

import numpy as np

from ..gpu.errors import LPVError
from ..gpu.output_layout import OutputLayout
from ..gpu.scene import SEEN_BY_CAMERA, SEEN_BY_LIGHTS, Camera, Film, Light, Scene, SurfaceImage, local_origin
from .image_pixels import tile_numbers
from .materials import MaterialSurfaces
from .world import world_and_lights
from .point_emitters import PointEmitters

MESH_LIKE_TYPES = {"MESH", "SURFACE", "META"}
"""Object types whose evaluated geometry `Object.to_mesh` turns into triangles. Curve and
text objects are absent on purpose: as in Cycles, their evaluated mesh reaches us as a
separate MESH instance, so reading them too would count them twice."""



def render_resolution(scene, width=None):
    """The final render's size in pixels, as Blender computes it (percentage applied), or
    with `width` that many pixels across at the same aspect."""
    render = scene.render
    percent = render.resolution_percentage
    size = (max(1, render.resolution_x * percent // 100), max(1, render.resolution_y * percent // 100))
    return size if width is None else (width, max(1, round(width * size[1] / size[0])))


def output_layout(scene, size=None):
    """What F12 writes of `scene`'s frame (of `size`, (width, height); None: the render
    resolution): its render region, cropped or not, and Film Transparent
    (gpu/output_layout.py)."""
    render = scene.render
    border = ((render.border_min_x, render.border_max_x, render.border_min_y, render.border_max_y)
              if render.use_border else None)
    return OutputLayout.of_border(size or render_resolution(scene), border, render.use_crop_to_border,
                                  render.film_transparent)


def extract_scene(depsgraph, resolution=None, view3d=None):
    """Build the sanitized `Scene` that `depsgraph` shows.

    `resolution` (W, H) overrides the render resolution for the camera projection (a
    viewport's size, say). `view3d`, the SpaceView3D of a viewport render, hides what
    that viewport hides (local view, per-viewport collection visibility); objects hidden
    for the whole view layer are already absent from the depsgraph, as are objects
    disabled in renders when the depsgraph is a render one.
    Raises LPVError for a panoramic camera (before reading anything else) and when
    nothing with triangles or no light is visible.
    """
    camera = extract_camera(depsgraph, resolution)
    geometry, lights, _ = extract_parts(depsgraph, view3d, geometry=True, lights=True)
    scene = Scene(**geometry, lights=[], **render_settings_of(depsgraph.scene_eval))
    world, lights = world_and_lights(depsgraph.scene_eval, lights)
    return scene.in_local_frame(lights, camera, world).sanitize()


def render_settings_of(scene, viewport=False):
    """The Scene fields a bpy scene's render settings give: its film (`film_of`), its
    Light Paths' diffuse bounces (`diffuse_bounces_of`) and Filter Glossy."""
    cycles = getattr(scene, "cycles", None)
    return {"film": film_of(scene, viewport), "diffuse_bounces": diffuse_bounces_of(scene),
            "filter_glossy": float(cycles.blur_glossy) if cycles is not None else 0.0}


def film_of(scene, viewport=False):
    """The Film of a bpy scene's render settings: its pixel filter, and Film Transparent
    (not in a `viewport`, which shows the world as Cycles' does)."""
    render = scene.render
    return Film(float(render.filter_size), bool(render.film_transparent) and not viewport)


def diffuse_bounces_of(scene):
    """How often diffuse light may bounce in a bpy scene, as its Light Paths say: Cycles'
    Diffuse bounces within Max Bounces; None where Cycles' settings are not there."""
    cycles = getattr(scene, "cycles", None)
    if cycles is None:
        return None
    return int(min(cycles.diffuse_bounces, cycles.max_bounces))


def extract_parts(depsgraph, view3d=None, geometry=True, lights=True):
    """One pass over the depsgraph's instances reading what is asked for: the Scene's
    geometry fields (triangles relative to their local origin, normals, albedo,
    visibility, the surfaces' vertex colours, UVs, image layers, images and approximated
    materials, and the origin, and the point emitters of emissive particles and instances)
    of everything visible (unsanitized; empty when not asked), the visible lights in
    world space (empty when not asked), and the PointEmitters read with the geometry (None
    when not asked)."""
    surfaces = MaterialSurfaces()
    meshes = {}
    batches = {}
    found_lights = []
    emitters = PointEmitters(depsgraph, surfaces, _shown_in(view3d)) if geometry else None
    wholly_emitters, last_parent, skipping = bool(emitters and emitters.whole_instancers), None, False
    for instance in depsgraph.object_instances:
        if wholly_emitters and instance.is_instance:  # the cheapest test first: a particle's object costs most
            parent = instance.parent
            if parent != last_parent:  # an instancer's instances come one after another
                last_parent, skipping = parent, emitters.skips_all_of(parent)
            if skipping:
                continue
        obj = instance.object
        if not instance.show_self or not _visible_in_view3d(instance, view3d):
            continue
        if obj.type == "LIGHT":
            if lights:
                found_lights.append(_light(obj, np.array(instance.matrix_world, dtype=np.float64)))
        elif geometry and obj.type in MESH_LIKE_TYPES:
            if emitters.names and emitters.stands_for(instance, obj):
                continue
            seen = _ray_visibility(instance)
            if not seen:
                continue
            slots = surfaces.palette(obj, max(1, len(obj.material_slots)))
            uv_maps = tuple(sorted({colour.uv_map for colour in slots if colour.image is not None} |
                                   {colour.alpha_uv_map for colour in slots if colour.alpha_image is not None}))
            attributes = tuple(sorted({colour.attribute for colour in slots if colour.attribute is not None}))
            key = (_mesh_key(obj), uv_maps, attributes)
            if key not in meshes:
                meshes[key] = LocalMesh.read(obj, uv_maps, attributes)
            mesh = meshes[key]
            if mesh.triangle_count:
                batch = batches.setdefault(key, ([], [], []))
                batch[0].append(np.array(instance.matrix_world, dtype=np.float64))
                batch[1].append(tuple(slots + slots[-1:] * (mesh.material_count - len(slots))))
                batch[2].append(seen)
    return _assemble(meshes, batches, surfaces, emitters), found_lights, emitters


def extract_point_emitters(depsgraph, view3d=None):
    """The point emitters alone (a PointEmitters: addon/point_emitters.py), read in bulk
    without the walk over the depsgraph's instances: for an edit that moved nothing but
    instancers whose instances are all point emitters (addon/sync.py)."""
    return PointEmitters(depsgraph, MaterialSurfaces(), _shown_in(view3d))


def _shown_in(view3d):
    """Whether an object shows in the viewport `view3d` (every object without one)."""
    return lambda obj: view3d is None or obj.visible_in_viewport_get(view3d)


def _assemble(meshes, batches, surfaces, emitters=None):
    """The Scene's geometry fields from the batches of instances of each mesh, placed
    relative to the local origin of their world bounds (float64 until then)."""
    origin = _batches_origin(meshes, batches)
    total = sum(len(matrices) * meshes[key].triangle_count for key, (matrices, _, _) in batches.items())
    triangles = np.empty((total, 3, 3), dtype=np.float32)
    normals = np.empty((total, 3, 3), dtype=np.float32)
    albedo = np.empty((total, 3), dtype=np.float32)
    emission = np.zeros((total, 3), dtype=np.float32)
    visibility = np.empty(total, dtype=np.uint8)
    image_layers = np.full(total, -1, dtype=np.int16)
    colours = [colour for _, palettes, _ in batches.values() for slots in palettes for colour in slots]
    textured = any(colour.image is not None or colour.alpha_image is not None for colour in colours)
    alpha_images = {colour.alpha_image.as_pointer() for colour in colours if colour.alpha_image is not None}
    see_through = not all(colour.opaque for colour in colours)
    alpha = np.ones(total, dtype=np.float32) if see_through else None
    alpha_layers = np.full(total, -1, dtype=np.int16) if alpha_images else None
    transmission = np.zeros((total, 4), dtype=np.float32) if see_through else None
    glossy = any(any(colour.specular) for colour in colours)
    specular = np.zeros((total, 5), dtype=np.float32) if glossy else None
    coloured = any(colour.attribute is not None for _, palettes, _ in batches.values() for slots in palettes
                   for colour in slots)
    uvs = np.zeros((total, 3, 2), dtype=np.float32) if textured else None
    vertex_colors = np.ones((total, 3, 3), dtype=np.float32) if coloured else None
    solids = np.full(total, -1, dtype=np.int32) if any(meshes[key].closed for key in batches) else None
    pieces = 0
    images, layers = [], {}

    def layer_of(image, tile=None):
        """The layer of `image` (of a tiled one, of its tile `tile`)."""
        key = (image.as_pointer(), tile)
        if key not in layers:
            layers[key] = len(images)
            images.append(SurfaceImage(image.name if tile is None else f"{image.name}.{tile}",
                                       surfaces.rgba(image, tile) if image.as_pointer() in alpha_images
                                       else surfaces.pixels(image, tile)))
        return layers[key]

    approximated = set(surfaces.approximated)
    start = 0
    for key, (matrices, palettes, seen) in batches.items():
        mesh = meshes[key]
        end = start + len(matrices) * mesh.triangle_count
        placed = np.stack(matrices)
        placed[:, :3, 3] -= origin
        mirrored = mesh.write_world(placed, triangles[start:end], normals[start:end])
        visibility[start:end] = np.repeat(np.array(seen, dtype=np.uint8), mesh.triangle_count)
        if mesh.closed:
            solids[start:end] = np.repeat(np.arange(pieces, pieces + len(matrices), dtype=np.int32),
                                          mesh.triangle_count)
            pieces += len(matrices)

        def per_instance(array):
            return array[start:end].reshape(len(matrices), mesh.triangle_count, *array.shape[1:])

        for slots in dict.fromkeys(palettes):  # instances of one mesh mostly share their materials
            which = [index for index, instance_slots in enumerate(palettes) if instance_slots == slots]
            surface = mesh.surface(slots, surfaces, layer_of)
            per_instance(albedo)[which] = surface.albedo
            per_instance(emission)[which] = surface.emission
            per_instance(image_layers)[which] = surface.layers
            if surface.uvs is not None:
                per_instance(uvs)[which] = surface.uvs
            if surface.colors is not None:
                per_instance(vertex_colors)[which] = surface.colors
            if see_through:
                per_instance(alpha)[which] = surface.alpha
                per_instance(transmission)[which] = surface.transmission
            if alpha_layers is not None:
                per_instance(alpha_layers)[which] = surface.alpha_layers
            if specular is not None:
                per_instance(specular)[which] = surface.specular
            approximated |= surface.approximated
        if mirrored.any():
            reversed_corners = np.flatnonzero(mirrored) + start
            for corners in (uvs, vertex_colors):
                if corners is not None:
                    corners[reversed_corners] = corners[reversed_corners][:, ::-1]
        start = end
    return {"triangles": triangles, "normals": normals, "albedo": albedo,
            "emission": emission if emission.any() else None, "visibility": visibility,
            "vertex_colors": vertex_colors, "uvs": uvs, "image_layers": image_layers if images else None,
            "alpha": alpha, "alpha_layers": alpha_layers, "transmission": transmission, "specular": specular,
            "solids": solids, "images": images, "approximated_materials": surfaces.approximated_entries(approximated), "origin": origin,
            "missing_images": sorted(surfaces.missing_images),
            "point_emitters": emitters.array(origin) if emitters is not None else None}


def _batches_origin(meshes, batches):
    """local_origin of the instances' world bounds (their meshes' boxes, transformed)."""
    corners = []
    for key, (matrices, _, _) in batches.items():
        positions = meshes[key].positions
        positions = positions[np.isfinite(positions).all(axis=1)]  # broken vertices are dropped later
        if not len(positions):
            continue
        low, high = positions.min(axis=0).astype(np.float64), positions.max(axis=0).astype(np.float64)
        box = np.array([[x, y, z, 1.0] for x in (low[0], high[0]) for y in (low[1], high[1])
                        for z in (low[2], high[2])])
        corners.append((np.stack(matrices) @ box.T).transpose(0, 2, 1)[..., :3].reshape(-1, 3))
    if not corners:
        return np.zeros(3)
    corners = np.concatenate(corners)
    return local_origin(corners.min(axis=0), corners.max(axis=0))


def _ray_visibility(instance):
    """SEEN_BY_CAMERA and SEEN_BY_LIGHTS bits of an instance, from its object's ray
    visibility "Camera" and "Shadow" and, for an instance, its instancer's too, as Cycles
    combines them."""
    owners = (instance.object, instance.parent) if instance.is_instance and instance.parent else (instance.object,)
    seen = SEEN_BY_CAMERA | SEEN_BY_LIGHTS
    for owner in owners:
        seen &= (SEEN_BY_CAMERA if owner.visible_camera else 0) | (SEEN_BY_LIGHTS if owner.visible_shadow else 0)
    return seen


def _visible_in_view3d(instance, view3d):
    if view3d is None:
        return True
    # Instanced objects are not in the view layer; their instancer carries the visibility.
    owner = instance.parent if instance.is_instance else instance.object
    return owner.visible_in_viewport_get(view3d)


def _mesh_key(obj):
    """Objects with the same key have the same evaluated triangles (in object space).

    Evaluated meshes are keyed by their data block's address, not name: a modified
    object's evaluated mesh is a new block that may share a name with an unrelated one.
    Surfaces and metaballs are tessellated per original object (an instance's object is
    a temporary whose address the depsgraph reuses for the next instance).
    """
    if obj.type == "MESH":
        return ("MESH", obj.data.as_pointer())
    return (obj.type, obj.original.as_pointer(), obj.data.as_pointer())


@dataclass
class MeshSurface:
    """One instance's surface per triangle of a LocalMesh: albedo (T, 3), image layer
    (T, ), corner UVs (T, 3, 2) and colours (T, 3, 3) (None: not read), the materials
    approximated for want of a UV map or colour attribute, emitted radiance (T, 3), and
    what of the surface lets light through (gpu/scene.py Scene): alpha (T,), the image
    layer whose alpha multiplies it (T,) and the transmission (T, 4); its glossy
    reflection (T, 5): F0 rgb, roughness and metallic."""

    albedo: np.ndarray
    layers: np.ndarray
    uvs: np.ndarray
    colors: np.ndarray
    approximated: set
    emission: np.ndarray
    alpha: np.ndarray = None
    alpha_layers: np.ndarray = None
    transmission: np.ndarray = None
    specular: np.ndarray = None


class LocalMesh:
    """One evaluated mesh in object space: vertex positions, and per triangle its vertex
    indices, corner normals and material slot; and the corner UVs and colours of the UV
    maps and colour attributes its materials read ({name: array}, None for a missing one;
    "" names the active render one)."""

    def __init__(self, positions, triangle_vertices, corner_normals, material_index, uvs=None, colors=None):
        self.positions = positions
        self.triangle_vertices = triangle_vertices
        self.corner_normals = corner_normals
        self.material_index = material_index
        self.uvs = uvs or {}
        self.colors = colors or {}
        self._surfaces = {}
        self._closed = None

    @property
    def triangle_count(self):
        return len(self.triangle_vertices)

    @property
    def material_count(self):
        return int(self.material_index.max()) + 1 if self.triangle_count else 1

    @property
    def closed(self):
        """Whether the mesh bounds a solid: every edge is shared by exactly two triangles
        that run along it in opposite directions (watertight, consistently wound), so one
        side of each face is its inside."""
        if self._closed is None:
            corners = self.triangle_vertices.astype(np.int64)
            starts, ends = corners.ravel(), np.roll(corners, -1, axis=1).ravel()
            vertices = int(corners.max()) + 1 if len(corners) else 1
            directed = starts * vertices + ends
            reverse = ends * vertices + starts
            unique, counts = np.unique(directed, return_counts=True)
            self._closed = bool(len(corners)) and bool(np.all(counts == 1)) and bool(np.all(starts != ends)) and \
                bool(np.all(np.isin(reverse, unique, assume_unique=False)))
        return self._closed

    @staticmethod
    def read(obj, uv_maps=(), attributes=()):
        """Read the evaluated object's triangles (modifiers applied) with foreach_get, and
        the corner values of `uv_maps` and colour `attributes`."""
        mesh = obj.to_mesh()
        try:
            triangles = mesh.loop_triangles
            count = len(triangles)
            if count == 0:  # an empty mesh has not even a position attribute
                return LocalMesh(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32),
                                 np.zeros((0, 3, 3), np.float32), np.zeros(0, np.int32))
            positions = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.attributes["position"].data.foreach_get("vector", positions)
            corners = np.empty(count * 3, dtype=np.int32)
            triangles.foreach_get("loops", corners)
            triangle_vertices = np.empty(count * 3, dtype=np.int32)
            triangles.foreach_get("vertices", triangle_vertices)
            normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
            mesh.corner_normals.foreach_get("vector", normals)
            material_index = _triangle_material_index(mesh, count)
            uvs = {name: _corner_uvs(mesh, name, corners) for name in uv_maps}
            colors = {name: _corner_colors(mesh, name, corners, triangle_vertices) for name in attributes}
        finally:
            obj.to_mesh_clear()
        return LocalMesh(positions.reshape(-1, 3), triangle_vertices.reshape(-1, 3),
                         normals.reshape(-1, 3)[corners].reshape(-1, 3, 3), material_index, uvs, colors)

    def write_world(self, matrices, triangles, normals):
        """Write this mesh placed by each of `matrices` into the output slices; returns
        which triangles were mirrored.

        `matrices` is (K, 4, 4) world matrices; `triangles` and `normals` are (K*T, 3, 3)
        views of the scene's arrays. Mirroring matrices get their triangles' winding
        reversed so it keeps agreeing with the normals (the caller reverses the corners of
        UVs and colours the same way).
        """
        instances = len(matrices)
        linear = matrices[:, :3, :3]
        positions = (self.positions @ linear.transpose(0, 2, 1) + matrices[:, None, :3, 3]).astype(np.float32)
        corners = triangles.reshape(instances, -1, 3)
        np.take(positions, self.triangle_vertices.ravel(), axis=1, out=corners)
        determinant = np.linalg.det(linear)
        invertible = np.abs(determinant) > 1e-30
        # Normals transform by the inverse transpose (as row vectors: n @ inverse); a
        # singular matrix leaves no area to shade.
        safe = np.where(invertible[:, None, None], linear, np.eye(3))
        normal_matrices = np.where(invertible[:, None, None], np.linalg.inv(safe), 0.0).astype(np.float32)
        corner_normals = normals.reshape(instances, -1, 3)
        np.matmul(self.corner_normals.reshape(-1, 3), normal_matrices, out=corner_normals)
        length = np.sqrt(np.einsum("kci,kci->kc", corner_normals, corner_normals))[..., None]
        np.divide(corner_normals, length, out=corner_normals, where=length > 0)
        mirrored = np.repeat(determinant < 0, self.triangle_count)
        if mirrored.any():
            triangles[mirrored] = triangles[mirrored][:, ::-1]
            normals[mirrored] = normals[mirrored][:, ::-1]
        return mirrored

    def surface(self, slots, surfaces, layer_of):
        """The MeshSurface of an instance whose material slots have the BaseColours
        `slots`; `layer_of(image, tile)` is the image's (UDIM tile's) layer in the scene.
        Kept per slots."""
        if slots not in self._surfaces:
            self._surfaces[slots] = self._surface(slots, surfaces, layer_of)
        return self._surfaces[slots]

    def _surface(self, slots, surfaces, layer_of):
        slot = np.minimum(self.material_index, len(slots) - 1)
        factors = np.array([colour.factor for colour in slots], dtype=np.float32)
        layers = np.full(self.triangle_count, -1, dtype=np.int16)
        alpha_layers = np.full(self.triangle_count, -1, dtype=np.int16)
        uvs = colors = None
        approximated = set()
        for index, colour in enumerate(slots):
            triangles = slot == index
            if colour.image is not None:
                uv = self.uvs.get(colour.uv_map)
                if uv is None:  # the mesh has no such UV map: Cycles reads (0, 0); we take the average
                    factors[index] *= surfaces.average(colour.image)
                    approximated.add(colour.material)
                else:
                    layers[triangles] = _image_layers(colour.image, uv[triangles], layer_of)
                    uvs = np.zeros((self.triangle_count, 3, 2), np.float32) if uvs is None else uvs
                    uvs[triangles] = uv[triangles]
            if colour.attribute is not None:
                corner = self.colors.get(colour.attribute)
                if corner is None:  # no such colour attribute: white, as the attribute is missing in Cycles too
                    approximated.add(colour.material)
                else:
                    colors = np.ones((self.triangle_count, 3, 3), np.float32) if colors is None else colors
                    colors[triangles] = corner[triangles]
            if colour.alpha_image is not None:
                uv = self.uvs.get(colour.alpha_uv_map)
                if uv is None or colour.image is not None and colour.alpha_uv_map != colour.uv_map:
                    approximated.add(colour.material)  # no such UV map, or another than the colour's: opaque
                else:
                    alpha_layers[triangles] = _image_layers(colour.alpha_image, uv[triangles], layer_of)
                    uvs = np.zeros((self.triangle_count, 3, 2), np.float32) if uvs is None else uvs
                    uvs[triangles] = uv[triangles]
        emission = np.array([colour.emission for colour in slots], dtype=np.float32)
        alpha = np.array([colour.alpha for colour in slots], dtype=np.float32)
        transmission = np.array([(*colour.transmission_tint, colour.transmission) for colour in slots], np.float32)
        specular = np.array([(*colour.specular, colour.roughness, colour.metallic) for colour in slots], np.float32)
        return MeshSurface(factors[slot], layers, uvs, colors, approximated, emission[slot], alpha[slot],
                           alpha_layers, transmission[slot], specular[slot])


def _image_layers(image, uvs, layer_of):
    """The image layer of each triangle of corner UVs `uvs` that reads `image`: its own,
    or for a tiled (UDIM) image the layer of the tile under the triangle
    (addon/image_pixels.py says why per triangle)."""
    if image.source != "TILED":
        return layer_of(image)
    tiles = tile_numbers(uvs)
    layers = np.empty(len(tiles), dtype=np.int16)
    for tile in np.unique(tiles):
        layers[tiles == tile] = layer_of(image, int(tile))
    return layers


def _corner_uvs(mesh, name, corners):
    """(T, 3, 2) UVs of the UV map `name` ("": the active render one), or None."""
    layers = mesh.uv_layers
    layer = next((uv for uv in layers if uv.active_render), None) if name == "" else layers.get(name)
    if layer is None:
        return None
    values = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    layer.uv.foreach_get("vector", values)
    return values.reshape(-1, 2)[corners].reshape(-1, 3, 2)


def _corner_colors(mesh, name, corners, triangle_vertices):
    """(T, 3, 3) linear colours of the colour attribute `name` ("": the active render
    one), per corner or per vertex as it is stored, or None."""
    attributes = mesh.color_attributes
    if name == "":
        index = attributes.render_color_index
        attribute = attributes[index] if 0 <= index < len(attributes) else None
    else:
        attribute = attributes.get(name)
    if attribute is None or attribute.domain not in ("CORNER", "POINT"):
        return None
    values = np.empty(len(attribute.data) * 4, dtype=np.float32)
    attribute.data.foreach_get("color", values)  # linear for byte and float colours alike
    rgb = values.reshape(-1, 4)[:, :3]
    return rgb[corners if attribute.domain == "CORNER" else triangle_vertices].reshape(-1, 3, 3)


def _triangle_material_index(mesh, count):
    attribute = mesh.attributes.get("material_index")
    if attribute is None or attribute.domain != "FACE":
        return np.zeros(count, dtype=np.int32)
    per_face = np.empty(len(mesh.polygons), dtype=np.int32)
    attribute.data.foreach_get("value", per_face)
    face_of_triangle = np.empty(count, dtype=np.int32)
    mesh.loop_triangle_polygons.foreach_get("value", face_of_triangle)
    return np.maximum(per_face[face_of_triangle], 0)


def _light(obj, matrix):
    """A `Light` in Blender's units: watts (sun: W/m²), exposure and area folded in."""
    light = obj.data
    color = np.array(light.color, dtype=np.float64)
    if light.use_temperature:
        color *= np.array(light.temperature_color, dtype=np.float64)
    power = light.energy * 2.0 ** light.exposure
    axes = matrix[:3, :3]
    size = (0.0, 0.0)
    if light.type == "AREA":
        # Cycles scales an area light by its object's scale.
        rectangular = light.shape in ("RECTANGLE", "ELLIPSE")
        size = (light.size * np.linalg.norm(axes[:, 0]),
                (light.size_y if rectangular else light.size) * np.linalg.norm(axes[:, 1]))
        if not light.normalize:
            elliptic = light.shape in ("ELLIPSE", "DISK")
            power *= size[0] * size[1] * (np.pi / 4 if elliptic else 1.0)
    spot = {"spot_size": light.spot_size, "spot_blend": light.spot_blend} if light.type == "SPOT" else {}
    softness = {"shape": light.shape} if light.type == "AREA" else {"angle": light.angle} if light.type == "SUN" else {}
    return Light(kind=light.type, position=matrix[:3, 3], direction=-axes[:, 2], up=axes[:, 1],
                 color=color, power=power, radius=light.shadow_soft_size, size=size,
                 name=obj.name, **spot, **softness)


def check_camera(scene):
    """Refuse a scene whose camera is panoramic, in one sentence: the G-buffer is a
    raster of one view and projection matrix, which no panoramic mapping has."""
    camera = scene.camera
    data = getattr(camera, "data", None)
    if getattr(data, "type", None) == "PANO":
        kind = data.panorama_type.replace("_", " ").lower()
        raise LPVError(f"The camera '{camera.name}' is panoramic ({kind}), which LPV Preview cannot render; set its "
                       f"Lens Type to Perspective or Orthographic, or render it with Cycles.")


def extract_camera(depsgraph, resolution=None):
    """The scene camera's view and projection (None without a scene camera); a
    panoramic one is refused (check_camera)."""
    scene = depsgraph.scene_eval
    camera = scene.camera
    if camera is None:
        return None
    check_camera(scene)
    width, height = resolution if resolution is not None else render_resolution(scene)
    projection = camera.calc_matrix_camera(depsgraph, x=int(width), y=int(height),
                                           scale_x=scene.render.pixel_aspect_x,
                                           scale_y=scene.render.pixel_aspect_y)
    # Blender's view matrix ignores the camera object's scale.
    view = np.array(camera.matrix_world.normalized().inverted(), dtype=np.float64)
    return Camera(view, np.array(projection, dtype=np.float64))
