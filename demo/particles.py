"""A closed 4 × 4 × 3 m grey room lit only by emissive particles: geometry nodes place
copies of a small glowing icosphere on the vertices of a point mesh, a swirl over the
floor (as in bench/synthetic.py `particle_room`, the flux given as luminance here), so
Cycles' light tree and the emitter grid light the same scene.
"""
import bpy
import numpy as np

from ..gpu.colour import LUMINANCE_WEIGHTS
from .builder import MeshBuilder, add_camera, principled_material

GREY = (0.6, 0.6, 0.6)
GLOW = (1.0, 0.8, 0.6)


def build(particles=4096, total_flux=200.0, radius=0.002, seed=0, resolution=(320, 240)):
    """Build the room with `particles` icospheres of `radius` m that together send
    `total_flux` W, and return the scene. Spheres of a centimetre would shade one another
    and the room in Cycles, which point emitters do not: small ones compare the light
    alone (docs/method.md)."""
    scene = bpy.context.scene
    collection = scene.collection
    grey = principled_material("Room grey", GREY)
    room = MeshBuilder()
    corners = {"Floor": ((-2, -2, 0), (0, 4, 0), (4, 0, 0)), "Ceiling": ((-2, -2, 3), (4, 0, 0), (0, 4, 0)),
               "Wall -x": ((-2, -2, 0), (0, 0, 3), (0, 4, 0)), "Wall +x": ((2, -2, 0), (0, 4, 0), (0, 0, 3)),
               "Wall -y": ((-2, -2, 0), (4, 0, 0), (0, 0, 3)), "Wall +y": ((-2, 2, 0), (0, 0, 3), (4, 0, 0))}
    for origin, edge_u, edge_v in corners.values():
        room.parallelogram(origin, edge_u, edge_v, 4, 4)
    room.to_object("Room", [grey], collection)
    sphere = _glowing_sphere(radius, total_flux / particles, collection)
    rng = np.random.default_rng(seed)
    turn = rng.random(particles) * 6 * np.pi
    distance = 1.6 * np.sqrt(rng.random(particles))
    points = np.column_stack([distance * np.cos(turn), distance * np.sin(turn), 0.2 + 2.4 * rng.random(particles)])
    mesh = bpy.data.meshes.new("Swirl")
    mesh.vertices.add(particles)
    mesh.vertices.foreach_set("co", points.ravel())
    swirl = bpy.data.objects.new("Swirl", mesh)
    collection.objects.link(swirl)
    swirl.modifiers.new("Particles", "NODES").node_group = instance_on_points(sphere)
    add_camera(scene, (0.0, -1.9, 1.5), (0.0, 0.0, 1.0), lens=18.0, resolution=resolution, clip_end=20.0)
    scene.world = None
    return scene


def _glowing_sphere(radius, flux, collection):
    """An icosphere just under the floor (inside the scene's bounds, out of the room's
    light), hidden from renders, whose emission sends `flux` W from its surface."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=radius, location=(0.0, 0.0, -0.05))
    sphere = bpy.context.object
    sphere.name = "Particle"
    areas = np.empty(len(sphere.data.polygons))
    sphere.data.polygons.foreach_get("area", areas)
    glow = principled_material("Particle glow", (0.0, 0.0, 0.0))
    principled = glow.node_tree.nodes["Principled BSDF"]
    principled.inputs["Emission Color"].default_value = (*GLOW, 1.0)
    principled.inputs["Emission Strength"].default_value = flux / (np.pi * areas.sum() * np.dot(GLOW, LUMINANCE_WEIGHTS))
    sphere.data.materials.append(glow)
    sphere.hide_render = True  # the copies render, not the original
    return sphere


def instance_on_points(source):
    """A geometry-nodes tree that places a copy of `source` (an object or a collection) on
    every point of the mesh it modifies."""
    tree = bpy.data.node_groups.new("Instance on points", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes = tree.nodes
    given, result = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    points, place = nodes.new("GeometryNodeMeshToPoints"), nodes.new("GeometryNodeInstanceOnPoints")
    if isinstance(source, bpy.types.Collection):
        info = nodes.new("GeometryNodeCollectionInfo")
        info.inputs["Collection"].default_value = source
    else:
        info = nodes.new("GeometryNodeObjectInfo")
        info.inputs["Object"].default_value = source
    tree.links.new(given.outputs[0], points.inputs["Mesh"])
    tree.links.new(points.outputs[0], place.inputs["Points"])
    tree.links.new(info.outputs[0] if isinstance(source, bpy.types.Collection) else info.outputs["Geometry"],
                   place.inputs["Instance"])
    tree.links.new(place.outputs[0], result.inputs[0])
    return tree
