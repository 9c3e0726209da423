"""Shared pieces of the demo scenes: quad-grid meshes built in numpy, materials, lights,
cameras.

Geometry is a list of parametric quad grids ("surfaces"); a `MeshBuilder` created with
`evaluate=False` only counts their quads, so a scene can search for the detail level that
meets a triangle budget without building anything.
"""
import math

import bpy
import numpy as np
from mathutils import Vector


class MeshBuilder:
    """Collects quad grids and turns them into one Blender mesh with foreach_set.

    Each surface has its own vertices: edges between surfaces stay sharp, while a curved
    surface (a column, a banner) shades smoothly across its own quads.
    """

    def __init__(self, evaluate=True):
        self.evaluate = evaluate
        self.quad_count = 0
        self._positions = []
        self._quads = []
        self._materials = []
        self._vertex_count = 0

    @property
    def triangle_count(self):
        return 2 * self.quad_count

    def surface(self, nu, nv, point_at, material=0, closed_u=False):
        """Add an nu x nv grid of quads; `point_at(u, v)` maps parameter arrays in [0, 1]
        to (..., 3) points. Quad (i, j) is wound so its normal is dP/du x dP/dv.

        `material` is a slot index, an (nu, nv) array of them, or a function of (nu, nv)
        that returns one (called only when evaluating). `closed_u` joins the last column
        to the first (a cylinder's seam).
        """
        self.quad_count += nu * nv
        if not self.evaluate:
            return
        if callable(material):
            material = material(nu, nv)
        u, v = np.meshgrid(np.linspace(0.0, 1.0, nu + 1), np.linspace(0.0, 1.0, nv + 1), indexing="ij")
        points = np.asarray(point_at(u, v), dtype=np.float64)
        columns = nu if closed_u else nu + 1
        points = points[:columns]
        index = np.arange(columns * (nv + 1)).reshape(columns, nv + 1) + self._vertex_count
        next_column = np.roll(index, -1, axis=0)[:nu] if closed_u else index[1:]
        quads = np.stack([index[:nu, :-1], next_column[:, :-1], next_column[:, 1:], index[:nu, 1:]], axis=-1)
        self._positions.append(points.reshape(-1, 3))
        self._quads.append(quads.reshape(-1, 4))
        self._materials.append(np.broadcast_to(np.asarray(material, dtype=np.int32), (nu, nv)).ravel())
        self._vertex_count += len(points.reshape(-1, 3))

    def parallelogram(self, origin, edge_u, edge_v, nu=1, nv=1, material=0):
        """A flat nu x nv grid spanning origin + u*edge_u + v*edge_v; it faces edge_u x edge_v."""
        origin, edge_u, edge_v = (np.asarray(x, dtype=np.float64) for x in (origin, edge_u, edge_v))
        self.surface(nu, nv, lambda u, v: origin + u[..., None] * edge_u + v[..., None] * edge_v, material)

    def prism(self, footprint, bottom, top, nu=1, nv=1, material=0, faces=("sides", "top", "bottom"),
              cap_steps=(1, 1)):
        """A vertical prism over a convex quadrilateral footprint (xy corners), faces outward.

        Each side is an nu x nv grid (nv along the height), top and bottom are cap_steps
        grids (along the footprint's first and second edge); `faces` picks what is built.
        """
        footprint = np.asarray(footprint, dtype=np.float64).reshape(4, 2)
        if _signed_area(footprint) < 0:
            footprint = footprint[::-1]
        height = np.array([0.0, 0.0, top - bottom])
        corners = np.column_stack([footprint, np.full(4, bottom)])
        if "sides" in faces:
            for start, end in zip(corners, np.roll(corners, -1, axis=0)):
                self.parallelogram(start, end - start, height, nu, nv, material)
        if "top" in faces:
            self.surface(*cap_steps, _bilinear(*(corners + height)), material)
        if "bottom" in faces:
            self.surface(*cap_steps, _bilinear(*corners[::-1]), material)

    def to_object(self, name, materials, collection):
        """Create the mesh and its object, with `materials` in its slots, in `collection`."""
        positions = np.concatenate(self._positions).astype(np.float32)
        quads = np.concatenate(self._quads).astype(np.int32)
        mesh = bpy.data.meshes.new(name)
        mesh.vertices.add(len(positions))
        mesh.vertices.foreach_set("co", positions.ravel())
        mesh.loops.add(quads.size)
        mesh.loops.foreach_set("vertex_index", quads.ravel())
        mesh.polygons.add(len(quads))
        mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=np.int32))
        mesh.polygons.foreach_set("material_index", np.concatenate(self._materials))
        mesh.update(calc_edges=True)
        for material in materials:
            mesh.materials.append(material)
        obj = bpy.data.objects.new(name, mesh)
        collection.objects.link(obj)
        return obj


def _signed_area(polygon):
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _bilinear(p00, p10, p11, p01):
    """point_at for the bilinear patch through four corners (in winding order)."""
    p00, p10, p11, p01 = (np.asarray(p, dtype=np.float64) for p in (p00, p10, p11, p01))

    def point_at(u, v):
        u, v = u[..., None], v[..., None]
        return (1 - u) * (1 - v) * p00 + u * (1 - v) * p10 + u * v * p11 + (1 - u) * v * p01
    return point_at


def rectangle_footprint(center, width, depth, angle=0.0):
    """Corners of a width x depth rectangle around `center`, turned by `angle` about z."""
    c, s = math.cos(angle), math.sin(angle)
    half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * (width / 2, depth / 2)
    return half @ np.array([[c, s], [-s, c]]) + np.asarray(center, dtype=np.float64)


def search_detail(count_at, target, low=0.05, high=64.0, steps=40):
    """The detail level whose triangle count `count_at(detail)` is closest to `target`.

    Counts grow with detail (up to rounding), so bisection finds the crossing.
    """
    for _ in range(steps):
        middle = (low + high) / 2
        if count_at(middle) < target:
            low = middle
        else:
            high = middle
    return min((low, high), key=lambda detail: abs(count_at(detail) - target))


def principled_material(name, base_color, roughness=0.8):
    """A Principled BSDF material with a linear base colour."""
    material = bpy.data.materials.new(name)
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (*base_color, 1.0)
    principled.inputs["Roughness"].default_value = roughness
    material.diffuse_color = (*base_color, 1.0)
    return material


def add_light(scene, name, kind, location, power, color=(1.0, 1.0, 1.0), aim=None, **settings):
    """A light object; `aim` is a point (or for a sun a direction) its -Z axis faces."""
    light = bpy.data.lights.new(name, kind)
    light.energy = power
    light.color = color
    for key, value in settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    if aim is not None:
        direction = Vector(aim) if kind == "SUN" else Vector(aim) - Vector(location)
        obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)
    return obj


def replace_lights(scene, lights):
    """Remove the scene's light objects and add one for each `gpu.scene.Light`."""
    for obj in [o for o in scene.objects if o.type == "LIGHT"]:
        bpy.data.objects.remove(obj)
    for light in lights:
        settings = {"shadow_soft_size": light.radius}
        if light.kind == "SPOT":
            settings.update(spot_size=light.spot_size, spot_blend=light.spot_blend)
        elif light.kind == "AREA":
            round_shape = light.shape in ("DISK", "ELLIPSE")
            settings.update(shape="ELLIPSE" if round_shape else "RECTANGLE", size=light.size[0], size_y=light.size[1])
        elif light.kind == "SUN":
            settings = {"angle": light.angle}
        aim = tuple(light.direction) if light.kind == "SUN" else tuple(light.position + light.direction)
        add_light(scene, light.name, light.kind, tuple(light.position), light.power, tuple(light.color), aim,
                  **settings)


def add_camera(scene, location, target, lens=35.0, resolution=(640, 360), clip_end=1000.0):
    """A camera at `location` looking at `target`, made the scene camera, with the render
    resolution set."""
    camera = bpy.data.cameras.new("Camera")
    camera.lens = lens
    camera.clip_start = 0.05
    camera.clip_end = clip_end
    obj = bpy.data.objects.new("Camera", camera)
    obj.location = location
    obj.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)
    scene.camera = obj
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    return obj
