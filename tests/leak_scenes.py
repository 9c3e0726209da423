"""Scenes where light must not leak, built with bpy, to measure against Cycles' one bounce.

Each builder empties the session (`read_factory_settings`), builds its scene with a
camera, diffuse Principled materials (Roughness 1, Specular IOR Level 0: what the
renderer models) and point, spot or sun lights of no size (Cycles' direct light has no
noise then), and returns a `LeakScene`. Walls are closed boxes, as a modeller makes
them; a wall with an opening is cut into boxes around it.
"""
import math
from dataclasses import dataclass

import bpy
import numpy as np
from mathutils import Vector

from lpv_preview.addon.render_scene import scene_to_render

from .blender.test_extract import mesh_object

GREY = (0.8, 0.8, 0.8)
WARM = (0.8, 0.6, 0.4)
COOL = (0.4, 0.6, 0.8)


@dataclass
class LeakScene:
    """A built scene: its name, the Blender scene, and the objects that hold the light in
    where the view shows no direct light at all (the closed box): without them the view
    gets the light they keep from it, which gives a leak its scale."""

    name: str
    scene: object
    occluders: tuple = ()


def unblocked_scene(built):
    """The gpu Scene of the view with the occluders hidden in renders; None when the
    scene has none."""
    if not built.occluders:
        return None
    for obj in built.occluders:
        obj.hide_render = True
    try:
        return scene_to_render(built.scene)
    finally:
        for obj in built.occluders:
            obj.hide_render = False


def diffuse(name, albedo):
    material = bpy.data.materials.new(name)
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (*albedo, 1.0)
    principled.inputs["Roughness"].default_value = 1.0
    principled.inputs["Specular IOR Level"].default_value = 0.0
    return material


def box(name, low, high, material):
    """A closed box (six faces) between the corners `low` and `high`."""
    corners = [(x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return mesh_object(name, corners, faces, materials=(material,))


def room_shell(half_x, half_y, height, walls, floor, thickness=0.1, front_window=None):
    """A closed room's floor, ceiling and four walls, each a closed box `thickness` thick,
    around [-half_x, half_x] x [-half_y, half_y] x [0, height]; with `front_window` ((x, z)
    low and high corners) the front wall (at -half_y) has that opening through it."""
    x, y, t = half_x, half_y, thickness
    box("Floor", (-x - t, -y - t, -t), (x + t, y + t, 0.0), floor)
    box("Ceiling", (-x - t, -y - t, height), (x + t, y + t, height + t), walls)
    box("Left wall", (-x - t, -y, 0.0), (-x, y, height), walls)
    box("Right wall", (x, -y, 0.0), (x + t, y, height), walls)
    box("Back wall", (-x - t, y, 0.0), (x + t, y + t, height), walls)
    if front_window is None:
        box("Front wall", (-x - t, -y - t, 0.0), (x + t, -y, height), walls)
    else:
        (low_x, low_z), (high_x, high_z) = front_window
        wall_with_opening("Front wall", (-x - t, -y - t, 0.0), (x + t, -y, height), (low_x, -y - t, low_z),
                          (high_x, -y, high_z), walls)


def wall_with_opening(name, low, high, opening_low, opening_high, material):
    """The box `low`-`high` less the box `opening_low`-`opening_high` that runs through it
    along its thinnest axis: the closed boxes below, above and beside the opening."""
    low, high = np.asarray(low, float), np.asarray(high, float)
    o_low, o_high = np.asarray(opening_low, float), np.asarray(opening_high, float)
    thin = int(np.argmin(high - low))
    across, up = [axis for axis in range(3) if axis != thin]
    pieces = []
    # (axis cut, from, to, the axis held to the opening's span): below, above, either side
    for axis, start, end, limited in ((up, low[up], o_low[up], None), (up, o_high[up], high[up], None),
                                      (across, low[across], o_low[across], up),
                                      (across, o_high[across], high[across], up)):
        if end - start <= 1e-9:
            continue
        piece_low, piece_high = low.copy(), high.copy()
        piece_low[axis], piece_high[axis] = start, end
        if limited is not None:
            piece_low[limited], piece_high[limited] = o_low[limited], o_high[limited]
        pieces.append(box(f"{name} {len(pieces)}", piece_low, piece_high, material))
    return pieces


def quad(name, half_size, height, material):
    """A square floor or ceiling of side 2 * `half_size` at `height`."""
    s = half_size
    return mesh_object(name, [(-s, -s, height), (s, -s, height), (s, s, height), (-s, s, height)], [(0, 1, 2, 3)],
                       materials=(material,))


def light(kind, location, rotation=(0.0, 0.0, 0.0), **settings):
    data = bpy.data.lights.new(kind.lower(), kind)
    if kind != "SUN":
        data.shadow_soft_size = 0.0
    else:
        data.angle = 0.0
    for key, value in settings.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(kind.lower(), data)
    obj.location, obj.rotation_euler = location, rotation
    bpy.context.scene.collection.objects.link(obj)
    return obj


def camera(name, location, target, lens=24.0):
    obj = bpy.data.objects.new(name, bpy.data.cameras.new(name))
    obj.location = location
    obj.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    obj.data.lens = lens
    obj.data.clip_start, obj.data.clip_end = 0.01, 5000.0
    bpy.context.scene.collection.objects.link(obj)
    return obj


def empty_scene(size):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    return scene


def closed_box(size=(64, 48)):
    """A point light inside a closed 1 m cube on a 10 m floor, seen from outside: nothing
    outside is lit, directly or indirectly. The cube floats 5 mm above the floor so that
    its bottom face and the floor do not overlap."""
    scene = empty_scene(size)
    quad("Floor", 5.0, 0.0, diffuse("floor", WARM))
    closed = box("Box", (-0.5, -0.5, 0.005), (0.5, 0.5, 1.005), diffuse("box", GREY))
    light("POINT", (0.0, 0.0, 0.5), energy=100.0)
    scene.camera = camera("Outside", (2.5, -3.0, 2.0), (0.0, 0.0, 0.4))
    return LeakScene("closed_box", scene, (closed,))


def thin_wall(size=(64, 48), scale=1.0):
    """Two 3 x 3 x 2.5 m rooms side by side, their shared wall 2 cm thick (a fifth of the
    0.1 m cells of 32³, a twelfth of those of 16³) with a small door (0.5 x 1 m) at one
    end; a point light in the left room, the camera in the right one looking at the
    shared wall and the floor. Only the light through the door reaches the right room.
    `scale` scales the objects (their scale and place), the light's power by its square
    (the same radiance) and the camera's clipping range."""
    scene = empty_scene(size)
    room_shell(3.0, 1.5, 2.5, diffuse("walls", GREY), diffuse("floor", WARM))
    wall_with_opening("Shared wall", (-0.01, -1.5, 0.0), (0.01, 1.5, 2.5), (-0.01, 0.8, 0.0), (0.01, 1.3, 1.0),
                      diffuse("shared", COOL))
    light("POINT", (-1.5, -0.5, 1.8), energy=300.0)
    scene.camera = camera("Unlit room", (2.8, -1.3, 1.6), (0.0, 0.3, 0.5))
    if scale != 1.0:
        scale_objects(scene, scale)
    return LeakScene("thin_wall" if scale == 1.0 else f"thin_wall_x{scale:g}", scene)


def scale_objects(scene, factor):
    """Every object `factor` times larger about the origin, lights `factor`^2 times as
    powerful (a point light's watts spread over an area), cameras clipping as far."""
    for obj in scene.objects:
        obj.location = obj.location * factor
        if obj.type == "MESH":
            obj.scale = obj.scale * factor
        elif obj.type == "LIGHT":
            obj.data.energy *= factor * factor
        elif obj.type == "CAMERA":
            obj.data.clip_start *= factor
            obj.data.clip_end *= factor


def lone_floor(size=(64, 48)):
    """A 4 m floor under a spot light, nothing else: a plane cannot light itself, so
    Cycles' indirect light is zero."""
    scene = empty_scene(size)
    quad("Floor", 2.0, 0.0, diffuse("floor", WARM))
    light("SPOT", (0.3, -0.2, 1.6), (0.25, -0.15, 0.0), energy=300.0, spot_size=math.radians(80), spot_blend=0.3)
    scene.camera = camera("Above", (0.0, -3.0, 2.5), (0.0, 0.0, 0.0), lens=30.0)
    return LeakScene("lone_floor", scene)


def big_ground_house(size=(64, 48)):
    """A 6 x 6 x 3 m house with an open door (1 x 2 m) on a 200 m ground, lit by a low
    sun shining into the door; the camera 8 m off looks at the house: one far-reaching
    plane must not decide the cells around the house."""
    scene = empty_scene(size)
    walls = diffuse("walls", GREY)
    quad("Ground", 100.0, 0.0, diffuse("ground", WARM))
    t = 0.2
    box("Roof", (-3 - t, -3 - t, 3.0), (3 + t, 3 + t, 3 + t), walls)
    box("Back wall", (-3 - t, 3.0, 0.0), (3 + t, 3 + t, 3.0), walls)
    box("Left wall", (-3 - t, -3.0, 0.0), (-3.0, 3.0, 3.0), walls)
    box("Right wall", (3.0, -3.0, 0.0), (3 + t, 3.0, 3.0), walls)
    wall_with_opening("Front wall", (-3 - t, -3 - t, 0.0), (3 + t, -3.0, 3.0), (-0.5, -3 - t, 0.0), (0.5, -3.0, 2.0),
                      walls)
    light("SUN", (0.0, 0.0, 10.0), (math.radians(55), 0.0, math.radians(20)), energy=3.0)
    scene.camera = camera("Outside", (4.0, -9.0, 2.0), (0.0, -2.0, 1.2), lens=24.0)
    return LeakScene("big_ground_house", scene)


def room_under_plane(size=(64, 48)):
    """A 4 x 4 x 3 m room with one window (1 x 1 m) and a point light inside, under a
    1000 m plane 50 m up; the camera is in the room: the far plane must not decide the
    cells in the room."""
    scene = empty_scene(size)
    walls = diffuse("walls", GREY)
    t = 0.15
    box("Floor", (-2 - t, -2 - t, -t), (2 + t, 2 + t, 0.0), diffuse("floor", WARM))
    box("Ceiling", (-2 - t, -2 - t, 3.0), (2 + t, 2 + t, 3 + t), walls)
    box("Back wall", (-2 - t, 2.0, 0.0), (2 + t, 2 + t, 3.0), walls)
    box("Left wall", (-2 - t, -2.0, 0.0), (-2.0, 2.0, 3.0), walls)
    box("Front wall", (-2 - t, -2 - t, 0.0), (2 + t, -2.0, 3.0), walls)
    wall_with_opening("Window wall", (2.0, -2.0, 0.0), (2 + t, 2.0, 3.0), (2.0, -0.5, 1.0), (2 + t, 0.5, 2.0),
                      diffuse("window wall", COOL))
    quad("Sky plane", 500.0, 50.0, walls)
    light("POINT", (-0.8, 0.5, 2.2), energy=400.0)
    scene.camera = camera("Inside", (-1.8, -1.8, 1.6), (1.0, 0.8, 0.8), lens=18.0)
    return LeakScene("room_under_plane", scene)


def camera_in_box(size=(64, 48)):
    """A camera inside a closed 2 m box standing on a 10 m floor, a sun outside: Cycles
    shows the box's inside black. The walls behind the camera lie outside what it sees."""
    scene = empty_scene(size)
    quad("Floor", 5.0, 0.0, diffuse("floor", WARM))
    closed = box("Box", (-1.0, -1.0, 0.0), (1.0, 1.0, 2.0), diffuse("box", GREY))
    light("SUN", (0.0, 0.0, 5.0), (math.radians(40), 0.0, math.radians(30)), energy=3.0)
    scene.camera = camera("Inside", (0.5, -0.8, 1.0), (0.0, 1.0, 0.8), lens=18.0)
    return LeakScene("camera_in_box", scene, (closed,))


def lamp_in_box_on_floor(size=(64, 48)):
    """closed_box seen up close at its foot: the box floats 5 mm over the floor, and
    nothing of the light inside reaches the floor around it."""
    scene = empty_scene(size)
    quad("Floor", 5.0, 0.0, diffuse("floor", WARM))
    closed = box("Box", (-0.5, -0.5, 0.005), (0.5, 0.5, 1.005), diffuse("box", GREY))
    light("POINT", (0.0, 0.0, 0.5), energy=100.0)
    scene.camera = camera("At its foot", (1.2, -1.5, 0.4), (0.4, -0.4, 0.0))
    return LeakScene("lamp_in_box_on_floor", scene, (closed,))


def lamp_on_wall(size=(64, 48)):
    """A point light 1 cm from the back wall of a closed 4 x 4 x 2.7 m room: the wall
    next to it is lit hundreds of times more than the rest, which must not carry over
    into more indirect light than Cycles'."""
    scene = empty_scene(size)
    room_shell(2.0, 2.0, 2.7, diffuse("walls", GREY), diffuse("floor", WARM))
    light("POINT", (0.0, 1.99, 1.5), energy=100.0)
    scene.camera = camera("Facing the lamp", (0.0, -1.8, 1.4), (0.0, 2.0, 1.2), lens=18.0)
    return LeakScene("lamp_on_wall", scene)


def sunlit_cube_room(size=(64, 48)):
    """A room made as artists make one quickly: a cube scaled to 4 x 5 x 2.7 m that the
    camera stands in, a table inside and a lamp, and outside a sun, a sky-blue world and
    the ground. Cycles shows the lamp's light alone inside: nothing of the sun or the sky
    gets in."""
    scene = empty_scene(size)
    box("Room", (-2.0, -2.5, 0.0), (2.0, 2.5, 2.7), diffuse("walls", GREY))
    box("Table", (0.2, 0.6, 0.0), (1.4, 1.4, 0.8), diffuse("table", WARM))
    quad("Ground", 20.0, -0.01, diffuse("ground", COOL))
    light("POINT", (-0.5, -0.5, 2.2), energy=300.0)
    light("SUN", (0.0, 0.0, 10.0), (math.radians(40), 0.0, math.radians(30)), energy=5.0)
    scene.world = bpy.data.worlds.new("Sky")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.6, 0.7, 1.0, 1.0)
    scene.camera = camera("Inside", (1.6, -2.2, 1.5), (-0.5, 1.0, 0.8), lens=18.0)
    return LeakScene("sunlit_cube_room", scene)


BUILDERS = {
    "closed_box": closed_box,
    "thin_wall": thin_wall,
    "lone_floor": lone_floor,
    "big_ground_house": big_ground_house,
    "room_under_plane": room_under_plane,
    "thin_wall_x0.001": lambda size=(64, 48): thin_wall(size, 1e-3),
    "thin_wall_x100000": lambda size=(64, 48): thin_wall(size, 1e5),
    "camera_in_box": camera_in_box,
    "lamp_in_box_on_floor": lamp_in_box_on_floor,
    "lamp_on_wall": lamp_on_wall,
    "sunlit_cube_room": sunlit_cube_room,
}
"""Every leak scene by name, each built at an image size."""
