"""Blender depsgraph -> `gpu.scene.Scene`: world-space triangles, albedo, lights, camera.

Everything is read with `foreach_get` into numpy and transformed in bulk, so a mesh of a
million triangles costs a fraction of a second and a thousand instances of one mesh cost
one read of that mesh and one batched transform.
"""
import numpy as np

from ..gpu.scene import SEEN_BY_CAMERA, SEEN_BY_LIGHTS, Camera, Light, Scene

DEFAULT_ALBEDO = (0.8, 0.8, 0.8)
"""Blender's colour for a surface without a material."""

MESH_LIKE_TYPES = {"MESH", "SURFACE", "META"}
"""Object types whose evaluated geometry `Object.to_mesh` turns into triangles. Curve and
text objects are absent on purpose: as in Cycles, their evaluated mesh reaches us as a
separate MESH instance, so reading them too would count them twice."""

NON_REFLECTING_SHADERS = {"EMISSION", "HOLDOUT", "BSDF_TRANSPARENT"}
"""Shader nodes that reflect no light diffusely."""

UPSTREAM_IMAGE_SEARCH_DEPTH = 8
"""How many nodes back from a colour socket an Image Texture is still looked for."""


def render_resolution(scene, width=None):
    """The final render's size in pixels, as Blender computes it (percentage applied), or
    with `width` that many pixels across at the same aspect."""
    render = scene.render
    percent = render.resolution_percentage
    size = (max(1, render.resolution_x * percent // 100), max(1, render.resolution_y * percent // 100))
    return size if width is None else (width, max(1, round(width * size[1] / size[0])))


def extract_scene(depsgraph, resolution=None, view3d=None):
    """Build the sanitized `Scene` that `depsgraph` shows.

    `resolution` (W, H) overrides the render resolution for the camera projection (a
    viewport's size, say). `view3d`, the SpaceView3D of a viewport render, hides what
    that viewport hides (local view, per-viewport collection visibility); objects hidden
    for the whole view layer are already absent from the depsgraph, as are objects
    disabled in renders when the depsgraph is a render one.
    Raises LPVError when nothing with triangles or no light is visible.
    """
    geometry, lights = extract_parts(depsgraph, view3d, geometry=True, lights=True)
    return Scene(**geometry, lights=lights, camera=extract_camera(depsgraph, resolution)).sanitize()


def extract_parts(depsgraph, view3d=None, geometry=True, lights=True):
    """One pass over the depsgraph's instances reading what is asked for: the Scene's
    geometry fields (world-space triangles, normals, albedo, visibility) of everything
    visible (unsanitized; empty arrays when not asked) and the visible lights (empty when
    not asked)."""
    materials = MaterialAlbedo()
    meshes = {}
    batches = {}
    found_lights = []
    for instance in depsgraph.object_instances:
        obj = instance.object
        if not instance.show_self or not _visible_in_view3d(instance, view3d):
            continue
        if obj.type == "LIGHT":
            if lights:
                found_lights.append(_light(obj, np.array(instance.matrix_world, dtype=np.float64)))
        elif geometry and obj.type in MESH_LIKE_TYPES:
            seen = _ray_visibility(instance)
            if not seen:
                continue
            key = _mesh_key(obj)
            if key not in meshes:
                meshes[key] = LocalMesh.read(obj)
            mesh = meshes[key]
            if mesh.triangle_count:
                palette = materials.palette(obj, mesh.material_count)
                batch = batches.setdefault(key, ([], [], []))
                batch[0].append(np.array(instance.matrix_world, dtype=np.float64))
                batch[1].append(palette)
                batch[2].append(seen)
    total = sum(len(matrices) * meshes[key].triangle_count for key, (matrices, _, _) in batches.items())
    triangles = np.empty((total, 3, 3), dtype=np.float32)
    normals = np.empty((total, 3, 3), dtype=np.float32)
    albedo = np.empty((total, 3), dtype=np.float32)
    visibility = np.empty(total, dtype=np.uint8)
    start = 0
    for key, (matrices, palettes, seen) in batches.items():
        end = start + len(matrices) * meshes[key].triangle_count
        meshes[key].write_world(np.stack(matrices), np.stack(palettes),
                                triangles[start:end], normals[start:end], albedo[start:end])
        visibility[start:end] = np.repeat(np.array(seen, dtype=np.uint8), meshes[key].triangle_count)
        start = end
    return {"triangles": triangles, "normals": normals, "albedo": albedo, "visibility": visibility}, found_lights


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


class LocalMesh:
    """One evaluated mesh in object space: vertex positions, and per triangle its vertex
    indices, corner normals and material slot."""

    def __init__(self, positions, triangle_vertices, corner_normals, material_index):
        self.positions = positions
        self.triangle_vertices = triangle_vertices
        self.corner_normals = corner_normals
        self.material_index = material_index

    @property
    def triangle_count(self):
        return len(self.triangle_vertices)

    @property
    def material_count(self):
        return int(self.material_index.max()) + 1 if self.triangle_count else 1

    @staticmethod
    def read(obj):
        """Read the evaluated object's triangles (modifiers applied) with foreach_get."""
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
        finally:
            obj.to_mesh_clear()
        return LocalMesh(positions.reshape(-1, 3), triangle_vertices.reshape(-1, 3),
                         normals.reshape(-1, 3)[corners].reshape(-1, 3, 3), material_index)

    def write_world(self, matrices, palettes, triangles, normals, albedo):
        """Write this mesh placed by each of `matrices` into the output slices.

        `matrices` is (K, 4, 4) world matrices, `palettes` (K, S, 3) the albedo of each
        instance's material slots; `triangles` and `normals` are (K*T, 3, 3) and
        `albedo` (K*T, 3) views of the scene's arrays. Mirroring matrices get their
        triangles' winding reversed so it keeps agreeing with the normals.
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
        slots = np.minimum(self.material_index, palettes.shape[1] - 1)
        np.take(palettes, slots, axis=1, out=albedo.reshape(instances, -1, 3))


def _triangle_material_index(mesh, count):
    attribute = mesh.attributes.get("material_index")
    if attribute is None or attribute.domain != "FACE":
        return np.zeros(count, dtype=np.int32)
    per_face = np.empty(len(mesh.polygons), dtype=np.int32)
    attribute.data.foreach_get("value", per_face)
    face_of_triangle = np.empty(count, dtype=np.int32)
    mesh.loop_triangle_polygons.foreach_get("value", face_of_triangle)
    return np.maximum(per_face[face_of_triangle], 0)


class MaterialAlbedo:
    """Linear diffuse albedo of materials, cached per material and per image."""

    def __init__(self):
        self._materials = {}
        self._images = {}

    def palette(self, obj, size):
        """(size, 3) albedo of the object's material slots; indices past the last slot use
        the last slot, as Blender does."""
        slots = [slot.material for slot in obj.material_slots] or [None]
        colors = [self.albedo(material) for material in slots[:size]]
        colors += [colors[-1]] * (size - len(colors))
        return np.array(colors, dtype=np.float32)

    def albedo(self, material):
        if material is None:
            return DEFAULT_ALBEDO
        key = material.as_pointer()
        if key not in self._materials:
            self._materials[key] = self._material_albedo(material)
        return self._materials[key]

    def _material_albedo(self, material):
        """Follow the Cycles output's Surface to a Principled or Diffuse BSDF's colour.

        Mix and Add shaders combine their inputs; any other shader, or a material
        without nodes, falls back to the material's viewport display colour.
        """
        fallback = tuple(material.diffuse_color[:3])
        tree = material.node_tree
        output = tree.get_output_node("CYCLES") if tree is not None else None
        if output is None:
            return fallback
        color = self._shader_albedo(output.inputs["Surface"], fallback, depth=0)
        return tuple(float(c) for c in np.clip(color, 0.0, 1.0))

    def _shader_albedo(self, socket, fallback, depth):
        node = _linked_node(socket)
        if node is None:
            return np.zeros(3)  # An unconnected surface renders black in Cycles.
        if depth > 32:
            return np.asarray(fallback)
        if node.type == "BSDF_PRINCIPLED":
            return self._color(node.inputs["Base Color"])
        if node.type == "BSDF_DIFFUSE":
            return self._color(node.inputs["Color"])
        if node.type == "MIX_SHADER":
            factor = node.inputs[0]
            weight = 0.5 if factor.is_linked else float(np.clip(factor.default_value, 0.0, 1.0))
            return ((1 - weight) * self._shader_albedo(node.inputs[1], fallback, depth + 1)
                    + weight * self._shader_albedo(node.inputs[2], fallback, depth + 1))
        if node.type == "ADD_SHADER":
            return (self._shader_albedo(node.inputs[0], fallback, depth + 1)
                    + self._shader_albedo(node.inputs[1], fallback, depth + 1))
        if node.type in NON_REFLECTING_SHADERS:
            return np.zeros(3)
        return np.asarray(fallback)

    def _color(self, socket):
        """The socket's colour, or the average of the nearest Image Texture feeding it.

        Nodes between the image and the socket (tints, mixes) are not evaluated.
        """
        if socket.is_linked:
            image = _upstream_image(socket)
            if image is not None:
                average = self._image_average(image)
                if average is not None:
                    return average
        return np.array(socket.default_value[:3], dtype=np.float64)

    def _image_average(self, image):
        key = image.as_pointer()
        if key not in self._images:
            self._images[key] = _image_average_linear(image)
        return self._images[key]


def _linked_node(socket):
    """The node feeding `socket`, looking through reroutes, muted links and muted nodes."""
    for _ in range(64):
        links = [link for link in socket.links if not link.is_muted]
        if not links:
            return None
        node = links[0].from_node
        if node.type == "REROUTE":
            socket = node.inputs[0]
        elif node.mute:
            passing = [link.from_socket for link in node.internal_links if link.to_socket == links[0].from_socket]
            if not passing:
                return None
            socket = passing[0]
        else:
            return node
    return None


def _upstream_image(socket):
    """The image of the nearest Image Texture node upstream of `socket`, if any."""
    frontier = [socket]
    for _ in range(UPSTREAM_IMAGE_SEARCH_DEPTH):
        nodes = [node for node in (_linked_node(s) for s in frontier) if node is not None]
        for node in nodes:
            if node.type == "TEX_IMAGE" and node.image is not None:
                return node.image
        frontier = [s for node in nodes for s in node.inputs if s.is_linked]
        if not frontier:
            return None
    return None


def _image_average_linear(image):
    """Mean linear RGB of an image, or None when it has no pixels (a missing file).

    Float images hold scene-linear values; byte images hold their colour space's
    encoding, which for anything but linear or non-colour data is taken as sRGB.
    """
    width, height = image.size
    channels = image.channels
    if width * height == 0 or channels == 0:
        return None
    pixels = np.empty(width * height * channels, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    rgb = pixels.reshape(-1, channels)[:, :3] if channels >= 3 else np.repeat(pixels.reshape(-1, channels)[:, :1], 3, 1)
    colorspace = image.colorspace_settings.name.lower()
    if not image.is_float and not ("linear" in colorspace or "non-color" in colorspace):
        rgb = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    return rgb.mean(axis=0, dtype=np.float64)


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
    return Light(kind=light.type, position=matrix[:3, 3], direction=-axes[:, 2], up=axes[:, 1],
                 color=color, power=power, radius=light.shadow_soft_size, size=size,
                 name=obj.name, **spot)


def extract_camera(depsgraph, resolution=None):
    """The scene camera's view and projection (None without a scene camera)."""
    scene = depsgraph.scene_eval
    camera = scene.camera
    if camera is None:
        return None
    width, height = resolution if resolution is not None else render_resolution(scene)
    projection = camera.calc_matrix_camera(depsgraph, x=int(width), y=int(height),
                                           scale_x=scene.render.pixel_aspect_x,
                                           scale_y=scene.render.pixel_aspect_y)
    # Blender's view matrix ignores the camera object's scale.
    view = np.array(camera.matrix_world.normalized().inverted(), dtype=np.float64)
    return Camera(view, np.array(projection, dtype=np.float64))
