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
        self.whole_instancers = set()  # original pointers of instancers all of whose instances are point emitters
        self.alone_instancers = set()  # those of them that draw nothing themselves: moving them moves emitters alone
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
        self.rows.append((positions, scales, flux, area))
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
        which = instance_references(cloud) if len(references) > 1 else np.zeros(len(cloud.points), dtype=np.int32)
        columns = None
        covered = 0  # instances that are one point emitter each and nothing else
        for index, reference in enumerate(references):
            chosen = which == index
            if chosen.sum() < BULK_INSTANCES:
                continue
            meshes = _reference_meshes(reference, surfaces)
            for mesh, palette_of, local in meshes:
                flux, area = self._emission(mesh, palette_of)
                if not flux.any():
                    continue
                if columns is None:
                    columns = instance_columns(cloud)
                positions, scales = placements(columns, chosen, np.array(obj.matrix_world, dtype=np.float64), local)
                self._add(obj, mesh, positions, scales, flux, area)
                covered += int(chosen.sum()) if len(meshes) == 1 else 0
        if covered == len(cloud.points) and obj.instance_type == "NONE":  # no instances of children beside them
            self.whole_instancers.add(obj.original.as_pointer())
            if obj.type == "MESH" and (geometry.mesh is None or not len(geometry.mesh.polygons)) and \
                    geometry.curves is None and geometry.pointcloud is None and geometry.volume is None:
                self.alone_instancers.add(obj.original.as_pointer())

    def skips_all_of(self, parent):
        """Whether every instance `parent` (a depsgraph instance's instancer, or None) makes
        is a point emitter: the depsgraph walk passes over them on their instancer alone,
        never reading their objects (a million particles a frame)."""
        return parent is not None and parent.original.as_pointer() in self.whole_instancers

    def stands_for(self, instance, obj):
        """Whether a depsgraph instance (whose object is `obj`) is one of the copies made
        point emitters (its mesh's name first: the cheapest test of the million)."""
        data = obj.data
        if data is None or data.name not in self.names or not instance.is_instance:
            return False
        parent = instance.parent
        return parent is not None and data.name in self.instancers.get(parent.original.as_pointer(), ())

    def array(self, origin):
        """The (M, 7) float32 rows relative to `origin` (subtracted in float64), or None
        without emitters."""
        if not self.rows:
            return None
        rows = np.empty((sum(len(positions) for positions, *_ in self.rows), 7), dtype=np.float32)
        at = 0
        for positions, scales, flux, area in self.rows:
            part = rows[at:at + len(positions)]
            part[:, :3] = positions - origin
            squared = (scales * scales).astype(np.float32)
            part[:, 3:6] = squared[:, None] * flux.astype(np.float32)
            part[:, 6] = squared * np.float32(area)
            at += len(positions)
        return rows


def instance_columns(cloud):
    """The (N, 4, 4) float32 transforms of the instances of an instances point cloud as
    stored, column-major: [i, c, r] is row r of column c of instance i's matrix."""
    count = len(cloud.points)
    values = np.empty(count * 16, dtype=np.float32)
    cloud.attributes["instance_transform"].data.foreach_get("value", values)
    return values.reshape(count, 4, 4)


def placements(columns, chosen, world, local):
    """The world positions (n, 3) float64 and scales (n,) (the cube root of the volume
    scale) of the `chosen` instances of `columns` (instance_columns), each placed by
    `world` @ its transform @ `local` (4 x 4): from the columns each needs, never a
    product of matrices an instance."""
    if not chosen.all():
        columns = columns[chosen]
    basis = columns[:, :3, :3]  # [i, c, r]: column c of the instance's 3 x 3
    places = columns[:, 3, :3].astype(np.float64)
    if np.any(local[:3, 3]):
        places += np.einsum("c,icr->ir", local[:3, 3], basis.astype(np.float64))
    positions = places @ world[:3, :3].T + world[:3, 3]
    scales = np.cbrt(np.abs(_volumes(basis) * np.linalg.det(world[:3, :3]) * np.linalg.det(local[:3, :3])))
    return positions, scales


def _volumes(basis):
    """The determinants of (n, 3, 3) bases, column by column (a · (b × c)): each term over
    every instance at once, where np.cross took longer than the rest of the read."""
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = ([basis[:, column, row] for row in range(3)] for column in range(3))
    return ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)


def instance_matrices(cloud):
    """The (N, 4, 4) float64 matrices of the instances of an instances point cloud."""
    return instance_columns(cloud).transpose(0, 2, 1).astype(np.float64)


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
