"""What F12 renders, as one hash: the Cycles references' cache key (cycles_reference.py).

It is read from the depsgraph Blender evaluates for a render (render_scene.py), which
holds what the viewport's does not: render visibility, collections excluded from the view
layer, particle counts and instancers as renders show them. A reference must be rendered
again whenever what F12 would show changes, and only then: so the hash covers every
instance (its object, transform, random id, ray visibility, materials and evaluated
geometry or data), the camera, the world's and every used material's nodes, the view
layer (which one and what it renders, not its passes) and the render settings that change
the linear image (film, filter, bounces, clamping, ...; not colour management, not the
settings a reference replaces: samples, seed, noise-only settings, size and output).
Selection, the viewport's display and node layout are left out.
"""
import hashlib

import numpy as np

PLAIN_TYPES = {"BOOLEAN", "INT", "FLOAT", "STRING", "ENUM"}

RENDER_SETTINGS_REPLACED = ("engine", "resolution_", "border_", "use_border", "use_crop_to_border", "filepath",
                            "threads", "threads_mode", "stamp_", "use_stamp", "use_stamp_", "metadata_input",
                            "use_persistent_data", "use_lock_interface", "use_file_extension", "use_overwrite",
                            "use_placeholder", "use_compositing", "use_sequencer", "use_freestyle", "use_multiview",
                            "views_format", "fps", "fps_base", "frame_map_", "use_high_quality_normals")
"""The `scene.render` settings (a name ending in "_": those it begins) that do not change a reference: the engine (a
reference is Cycles'), the size and border (the comparison's own), the output, the
compositor and sequencer (a reference is the view layer's Combined, before them)."""

CYCLES_SETTINGS_REPLACED = ("samples", "seed", "use_animated_seed", "use_adaptive_sampling", "adaptive_",
                            "time_limit", "use_denoising", "denoiser", "denoising_", "device", "use_sample_subset",
                            "sample_offset", "sample_subset_length", "use_layer_samples", "preview_",
                            "use_preview_", "tile_size", "use_auto_tile", "debug_")
"""The `scene.cycles` settings that change the noise, not the converged image
(replaced by a reference's plain samples), or the viewport only."""

VIEW_LAYER_SETTINGS = ("use_solid", "use_sky", "use_ao", "use_strand", "use_volumes", "use_motion_blur")
"""What of the view layer changes its Combined pass (its passes do not)."""

OBJECT_SETTINGS = ("pass_index", "color", "visible_camera", "visible_diffuse", "visible_glossy",
                   "visible_transmission", "visible_volume_scatter", "visible_shadow", "is_holdout",
                   "is_shadow_catcher", "lightgroup", "shadow_terminator_normal_offset",
                   "shadow_terminator_geometry_offset", "shadow_terminator_shading_offset")
"""What of an object beside its transform and data changes a Cycles render."""

NODE_LAYOUT = ("name", "label", "location", "location_absolute", "width", "height", "dimensions", "select", "hide",
               "show_options", "show_preview", "show_texture", "use_custom_color", "color", "color_tag",
               "warning_propagation", "type")
"""Node properties that only lay the node editor out."""

DATA_NOT_RENDERED = ("name", "name_full", "session_uid", "users", "use_fake_user", "use_extra_user", "tag",
                     "id_type", "total_", "is_", "use_mirror_", "use_paint_")
"""Settings of a data-block (mesh, light, camera...) a render does not see: its name (its
instances name it), its id in this session (new at each evaluation), its users,
selection counts and edit-mode state."""

ATTRIBUTE_FIELDS = {"FLOAT": ("value", 1, np.float32), "INT": ("value", 1, np.int32),
                    "BOOLEAN": ("value", 1, bool), "INT8": ("value", 1, np.int32),
                    "FLOAT_VECTOR": ("vector", 3, np.float32), "FLOAT2": ("vector", 2, np.float32),
                    "FLOAT_COLOR": ("color", 4, np.float32), "BYTE_COLOR": ("color", 4, np.float32),
                    "INT32_2D": ("value", 2, np.int32), "QUATERNION": ("value", 4, np.float32),
                    "FLOAT4X4": ("value", 16, np.float32)}
"""How to read each attribute type with foreach_get: field, numbers per element, dtype."""


def plain(value):
    """A setting as a value that prints the same whenever it is the same."""
    if isinstance(value, float):
        return round(value, 7)
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, set):  # an enum of flags
        return tuple(sorted(value))
    try:
        return tuple(plain(v) for v in value)
    except TypeError:
        return repr(value)


def left_out(name, leave_out):
    """Whether `leave_out` names `name`: itself, or a beginning of it ending in "_"."""
    return any(name == entry or (entry.endswith("_") and name.startswith(entry)) for entry in leave_out)


def plain_values(struct, leave_out=()):
    """Every plain setting of a Blender struct, sorted, but those `leave_out` names
    (`left_out`)."""
    values = []
    for prop in struct.bl_rna.properties:
        name = prop.identifier
        if prop.type not in PLAIN_TYPES or name == "rna_type" or prop.is_deprecated or left_out(name, leave_out):
            continue
        try:
            values.append((name, plain(getattr(struct, name))))
        except (AttributeError, TypeError, ValueError):  # a property this build cannot read
            continue
    return sorted(values)


def node_tree_signature(tree, seen=None):
    """What of a node tree can change a render: each node's settings and input values, its
    image (name, size, file, colour space) or node group (recursively), and the links."""
    if tree is None:
        return None
    seen = set() if seen is None else seen
    if tree.name in seen:
        return ("group", tree.name)
    seen.add(tree.name)
    nodes = []
    for node in sorted(tree.nodes, key=lambda n: n.name):
        inputs = tuple((i.identifier, plain(getattr(i, "default_value", None))) for i in node.inputs)
        image = getattr(node, "image", None)
        group = getattr(node, "node_tree", None)
        nodes.append((node.name, node.bl_idname, tuple(plain_values(node, NODE_LAYOUT)), inputs,
                      None if image is None else (image.name, tuple(image.size), image.filepath, image.source,
                                                  image.colorspace_settings.name),
                      None if group is None else node_tree_signature(group, seen)))
    links = tuple(sorted((link.from_node.name, link.from_socket.identifier, link.to_node.name,
                          link.to_socket.identifier, link.is_muted) for link in tree.links))
    return (tuple(nodes), links)


def material_signature(material):
    """What of a material (or world) can change a Cycles render: its settings and node
    tree (`node_tree_signature`), its colour among them."""
    if material is None:
        return None
    return (material.name, tuple(plain_values(material, DATA_NOT_RENDERED)),
            node_tree_signature(material.node_tree))


def attributes_digest(data, digest):
    """Feed every attribute of a Mesh, Curves or PointCloud into `digest`, selection and
    hiding left out."""
    for attribute in sorted(data.attributes, key=lambda a: a.name):
        name = attribute.name
        if name.startswith(".") and ("select" in name or "hide" in name):
            continue
        digest.update(repr((name, attribute.domain, attribute.data_type)).encode())
        read = ATTRIBUTE_FIELDS.get(attribute.data_type)
        if read is None or not len(attribute.data):
            continue
        field, width, dtype = read
        values = np.empty(len(attribute.data) * width, dtype=dtype)
        attribute.data.foreach_get(field, values)
        digest.update(values.tobytes())


def mesh_digest(mesh, digest):
    """An evaluated mesh's faces and attributes (positions, corners, UVs, sharpness...)."""
    starts = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", starts)
    digest.update(starts.tobytes())
    attributes_digest(mesh, digest)
    digest.update(repr([m.name if m else None for m in mesh.materials]).encode())


def data_signature(obj):
    """The hash of an evaluated object's data as Cycles renders it."""
    digest = hashlib.sha1(obj.type.encode())
    data = obj.data
    if obj.type in {"MESH", "CURVE", "SURFACE", "META", "FONT"}:
        try:
            mesh = obj.to_mesh()
        except RuntimeError:  # an object that cannot make a mesh: its own, if it is one
            mesh = data if obj.type == "MESH" else None
        try:
            if mesh is not None:
                mesh_digest(mesh, digest)
        finally:
            obj.to_mesh_clear()
    elif data is not None and hasattr(data, "attributes"):  # hair curves, point clouds
        attributes_digest(data, digest)
    if data is not None:
        digest.update(repr(plain_values(data, DATA_NOT_RENDERED)).encode())
        if getattr(data, "node_tree", None) is not None:  # a light's nodes
            digest.update(repr(node_tree_signature(data.node_tree)).encode())
        if obj.type == "CAMERA":
            digest.update(repr(plain_values(data.dof)).encode())
    return digest.hexdigest()


def object_settings(obj):
    """An object's ray visibility, shading settings and materials."""
    cycles = getattr(obj, "cycles", None)
    return (tuple(plain(getattr(obj, name, None)) for name in OBJECT_SETTINGS),
            tuple(plain_values(cycles)) if cycles is not None else (),
            tuple(slot.material.name if slot.material else None for slot in obj.material_slots))


def render_signature(depsgraph):
    """The hash of what a render of `depsgraph` (a render depsgraph: Blender's own for
    F12) shows, but for its size, samples and seed."""
    scene, view_layer = depsgraph.scene_eval, depsgraph.view_layer_eval
    digest = hashlib.sha1()
    parts = [plain_values(scene.render, RENDER_SETTINGS_REPLACED),
             plain_values(scene.cycles, CYCLES_SETTINGS_REPLACED) if hasattr(scene, "cycles") else None,
             scene.frame_current, scene.frame_subframe, scene.camera.name if scene.camera else None,
             view_layer.name, [plain(getattr(view_layer, name)) for name in VIEW_LAYER_SETTINGS]]
    overrides = [getattr(view_layer, name, None) for name in ("material_override", "world_override")]
    parts += [None if o is None else o.name for o in overrides]
    world = overrides[1] or scene.world
    parts.append(material_signature(world))
    digest.update(repr(parts).encode())
    described, materials = {}, {}  # an object's data hash and settings, read once for all its instances

    def description(obj):
        owner = (obj.type, obj.original.as_pointer(), obj.data.as_pointer() if obj.data else 0)
        if owner not in described:
            described[owner] = (obj.name, data_signature(obj), object_settings(obj))
            for material in [slot.material for slot in obj.material_slots] + list(getattr(obj.data, "materials", ())):
                if material is not None:
                    materials.setdefault(material.name, material)
        return described[owner]

    for instance in depsgraph.object_instances:
        parent = instance.parent if instance.is_instance else None
        digest.update(repr((description(instance.object), instance.is_instance, instance.show_self,
                            instance.show_particles, instance.random_id,
                            None if parent is None else description(parent))).encode())
        digest.update(np.array(instance.matrix_world, dtype=np.float32).tobytes())
    if overrides[0] is not None:
        materials.setdefault(overrides[0].name, overrides[0])
    for name in sorted(materials):
        digest.update(repr(material_signature(materials[name])).encode())
    return digest.hexdigest()[:20]
