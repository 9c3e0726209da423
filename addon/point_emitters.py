"""Emissive particles and instances -> point emitters (gpu/scene.py `point_emitters`).

An instancer (a particle system showing an object, or geometry nodes' instances of an
object, a geometry or a collection) that places at least BULK_INSTANCES copies of an
emissive mesh makes each copy one point emitter: its position, the mesh's emitted flux
scaled by the copy's scale², and the area it comes from. Their places are read in bulk
from the instancer's evaluated instances (`foreach_get` on their point cloud, which holds
a particle system's shown particles too, at their size), never one instance at a time,
and the depsgraph walk leaves those copies out of the triangles. Fewer copies stay meshes whose emissive surfaces are
sampled exactly (gpu/surface_emitters.py).
"""
import bpy
import numpy as np

BULK_INSTANCES = 64
"""Copies of one emissive mesh from one instancer from which on they are point emitters."""
GEOMETRY_TYPES = {"MESH", "CURVES", "POINTCLOUD", "VOLUME", "GREASEPENCIL", "CURVE", "SURFACE", "FONT", "META"}
"""Object types whose evaluated geometry may hold instances."""
NESTING = 4  # geometry sets within instances read at most this deep
NESTED_INSTANCES = 256  # instances of one nested geometry set read one by one at most (a collection's objects)


def mesh_emission(mesh, palette):
    """(flux rgb one side sends, W; area, m²) of a mesh whose material slots have the
    BaseColours `palette`: π × radiance × area summed over its faces."""
    count = len(mesh.polygons)
    if count == 0:
        return np.zeros(3), 0.0
    areas = np.empty(count, dtype=np.float64)
    mesh.polygons.foreach_get("area", areas)
    slots = np.empty(count, dtype=np.int32)
    mesh.polygons.foreach_get("material_index", slots)
    radiance = np.array([colour.emission for colour in palette], dtype=np.float64).reshape(-1, 3)
    slots = np.clip(slots, 0, len(radiance) - 1)
    return np.pi * (areas[:, None] * radiance[slots]).sum(axis=0), float(areas.sum())


class PointEmitters:
    """The point emitters of one depsgraph and which instances they stand for."""

    def __init__(self, depsgraph, surfaces, visible):
        self.rows = []
        self.instancers = {}  # instancer's original pointer -> names of the emissive meshes it places (an
        # instance's mesh is a copy of the one geometry nodes hold, only the name is the same)
        self.names = set()    # every one of those names
        self._power = {}      # mesh pointer -> (flux, area)
        for obj in depsgraph.objects:
            if not visible(obj):
                continue
            self._geometry_instances(obj, surfaces)

    def _emission(self, mesh, palette_of):
        key = mesh.as_pointer()
        if key not in self._power:
            self._power[key] = mesh_emission(mesh, palette_of())
        return self._power[key]

    def _add(self, instancer, mesh, positions, scales, flux, area):
        rows = np.zeros((len(positions), 7), dtype=np.float64)
        rows[:, :3] = positions
        rows[:, 3:6] = flux * (scales ** 2)[:, None]
        rows[:, 6] = area * scales ** 2
        self.rows.append(rows)
        self.instancers.setdefault(instancer.original.as_pointer(), set()).add(mesh.name)
        self.names.add(mesh.name)

    def _geometry_instances(self, obj, surfaces):
        if obj.type not in GEOMETRY_TYPES:
            return
        geometry = obj.evaluated_geometry()
        cloud = geometry.instances_pointcloud() if geometry is not None else None
        if cloud is None or len(cloud.points) < BULK_INSTANCES:
            return
        references = geometry.instance_references()
        which = instance_references(cloud)
        transforms = None
        for index, reference in enumerate(references):
            chosen = which == index
            if chosen.sum() < BULK_INSTANCES:
                continue
            for mesh, palette_of, local in _reference_meshes(reference, surfaces):
                flux, area = self._emission(mesh, palette_of)
                if not flux.any():
                    continue
                if transforms is None:  # placed by the instancer's world matrix
                    transforms = np.array(obj.matrix_world, dtype=np.float64) @ instance_matrices(cloud)
                placed = transforms[chosen] @ local
                scales = np.cbrt(np.abs(np.linalg.det(placed[:, :3, :3])))
                self._add(obj, mesh, placed[:, :3, 3], scales, flux, area)

    def stands_for(self, instance, obj):
        """Whether a depsgraph instance (whose object is `obj`) is one of the copies made
        point emitters (its mesh's name first: the cheapest test of the million)."""
        data = obj.data
        if data is None or data.name not in self.names or not instance.is_instance:
            return False
        parent = instance.parent
        return parent is not None and data.name in self.instancers.get(parent.original.as_pointer(), ())

    def array(self, origin):
        """The (M, 7) rows relative to `origin`, or None without emitters."""
        if not self.rows:
            return None
        rows = np.concatenate(self.rows)
        rows[:, :3] -= origin
        return rows


def instance_matrices(cloud):
    """The (N, 4, 4) float64 matrices of the instances of an instances point cloud."""
    count = len(cloud.points)
    transforms = np.empty(count * 16, dtype=np.float32)
    cloud.attributes["instance_transform"].data.foreach_get("value", transforms)
    return transforms.reshape(count, 4, 4).transpose(0, 2, 1).astype(np.float64)  # stored column-major


def instance_references(cloud):
    """Each instance's index into its geometry's instance_references()."""
    which = np.empty(len(cloud.points), dtype=np.int32)
    cloud.attributes[".reference_index"].data.foreach_get("value", which)
    return which


def _reference_meshes(reference, surfaces, depth=0):
    """(mesh, a function giving its palette, its matrix within the instance) of each mesh
    an instance reference places: an object's, a collection's mesh objects (placed as in
    the collection, less its instance offset), a geometry set's own mesh and, nested, its
    instances' (Collection Info gives a geometry set holding the collection)."""
    if isinstance(reference, bpy.types.Object):
        return [(reference.data, lambda: surfaces.palette(reference, max(1, len(reference.material_slots))),
                 np.eye(4))] if reference.type == "MESH" else []
    if isinstance(reference, bpy.types.Collection):
        offset = np.eye(4)
        offset[:3, 3] = -np.array(reference.instance_offset, dtype=np.float64)
        return [(member.data, lambda member=member: surfaces.palette(member, max(1, len(member.material_slots))),
                 offset @ np.array(member.matrix_world, dtype=np.float64))
                for member in reference.all_objects if member.type == "MESH"]
    parts = []
    mesh = getattr(reference, "mesh", None)  # a GeometrySet
    if mesh is not None:
        parts.append((mesh, lambda: [surfaces.base_colour(material) for material in mesh.materials] or
                      [surfaces.base_colour(None)], np.eye(4)))
    cloud = reference.instances_pointcloud() if depth < NESTING and hasattr(reference, "instances_pointcloud") \
        else None
    if cloud is not None and len(cloud.points) <= NESTED_INSTANCES:
        nested = reference.instance_references()
        for transform, index in zip(instance_matrices(cloud), instance_references(cloud)):
            parts += [(inner, palette_of, transform @ local)
                      for inner, palette_of, local in _reference_meshes(nested[index], surfaces, depth + 1)]
    return parts
