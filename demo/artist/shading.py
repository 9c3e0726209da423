"""What the artist scenes share: the factory startup file to start from, primitives
added with bpy.ops as the Add menu adds them, Principled BSDF materials, and the worlds
(an HDRI, a Sky Texture, a plain colour) built from nodes as the World tab builds them."""
import math
import os

import bpy
import numpy as np

from ..builder import add_camera

STUDIO_LIGHTS = bpy.utils.system_resource("DATAFILES", path="studiolights/world")
"""Blender's bundled HDRIs (forest.exr, studio.exr, ...)."""


def factory_scene(resolution, keep_startup_objects=False):
    """Blender's factory startup file with its render resolution set, its cube, light and
    camera removed unless kept; every other setting stays Blender's default."""
    bpy.ops.wm.read_factory_settings(use_empty=False)
    scene = bpy.context.scene
    if not keep_startup_objects:
        for obj in list(scene.objects):
            data = obj.data
            bpy.data.objects.remove(obj)
            if isinstance(data, bpy.types.Light):
                bpy.data.lights.remove(data)
            elif isinstance(data, bpy.types.Camera):
                bpy.data.cameras.remove(data)
            elif isinstance(data, bpy.types.Mesh):
                bpy.data.meshes.remove(data)
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    return scene


def add_primitive(kind, name, material=None, smooth=False, **options):
    """A mesh primitive added as Add > Mesh adds it (`kind`: cube, uv_sphere, plane,
    cylinder, cone, torus, monkey), renamed, with `material` in its slot."""
    getattr(bpy.ops.mesh, f"primitive_{kind}_add")(**options)
    obj = bpy.context.active_object
    obj.name = obj.data.name = name
    if material is not None:
        obj.data.materials.append(material)
    if smooth:
        obj.data.shade_smooth()
    return obj


def add_box(name, centre, size, material):
    """A cube scaled to `size` (metres) about `centre`, its scale applied as an artist
    applies it (Ctrl-A > Scale)."""
    box = add_primitive("cube", name, material, size=1.0, location=centre)
    box.scale = size
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    return box


def add_room(size, wall, floor, walls, front_wall="Front wall"):
    """A closed room of `size` (inside width x, depth y, height z, metres) about the origin,
    its floor on z = 0: floor, ceiling and four walls `wall` thick, each a box; the floor
    of material `floor`, the rest of `walls`. Returns the boxes by name (the wall at -y is
    `front_wall`)."""
    width, depth, height = size
    slabs = {"Floor": ((0, 0, -wall / 2), (width + 2 * wall, depth + 2 * wall, wall), floor),
             "Ceiling": ((0, 0, height + wall / 2), (width + 2 * wall, depth + 2 * wall, wall), walls),
             front_wall: ((0, -(depth + wall) / 2, height / 2), (width + 2 * wall, wall, height), walls),
             "Back wall": ((0, (depth + wall) / 2, height / 2), (width + 2 * wall, wall, height), walls),
             "Left wall": ((-(width + wall) / 2, 0, height / 2), (wall, depth, height), walls),
             "Right wall": (((width + wall) / 2, 0, height / 2), (wall, depth, height), walls)}
    return {name: add_box(name, centre, extent, material) for name, (centre, extent, material) in slabs.items()}


def cut_window(wall, name, centre, size, wall_thickness):
    """Cut a window through the wall box `wall` (its thin side along y) with a Boolean
    modifier and a hidden cutter box `name` of `size` (x, z) about `centre`, as artists
    cut one."""
    cutter = add_box(name, centre, (size[0], 4 * wall_thickness, size[1]), None)
    cutter.display_type = "WIRE"
    cutter.hide_render = True
    add_modifier(wall, "BOOLEAN", operation="DIFFERENCE", object=cutter)
    return cutter


def add_sun_lamp(towards_sun, strength, angle_degrees):
    """A Sun lamp shining from the unit direction `towards_sun` (toward the sun), with its
    strength (W/m²) and angular diameter."""
    from mathutils import Vector
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = strength
    sun.angle = math.radians(angle_degrees)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = (-Vector(towards_sun)).to_track_quat("-Z", "Y").to_euler()
    sun_object.location = (0.0, 0.0, 10.0)
    bpy.context.scene.collection.objects.link(sun_object)
    return sun_object


def add_modifier(obj, kind, **settings):
    modifier = obj.modifiers.new(kind.title(), kind)
    for key, value in settings.items():
        setattr(modifier, key, value)
    return modifier


def principled(name, base_color, roughness=0.5, metallic=0.0, emission=None, emission_strength=0.0, alpha=1.0,
               image=None, image_alpha=False, transmission=0.0, ior=1.5):
    """A Principled BSDF material as the Material tab makes it, with these inputs set; with
    `image`, an Image Texture of it feeds Base Color (and with `image_alpha`, Alpha)."""
    material = bpy.data.materials.new(name)
    tree = material.node_tree
    node = tree.nodes["Principled BSDF"]
    inputs = node.inputs
    inputs["Base Color"].default_value = (*base_color, 1.0)
    inputs["Roughness"].default_value = roughness
    inputs["Metallic"].default_value = metallic
    inputs["Alpha"].default_value = alpha
    inputs["Transmission Weight"].default_value = transmission
    inputs["IOR"].default_value = ior
    if emission is not None:
        inputs["Emission Color"].default_value = (*emission, 1.0)
        inputs["Emission Strength"].default_value = emission_strength
    if image is not None:
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        tree.links.new(texture.outputs["Color"], inputs["Base Color"])
        if image_alpha:
            tree.links.new(texture.outputs["Alpha"], inputs["Alpha"])
    material.diffuse_color = (*base_color, alpha)
    return material


def packed_tile_image(name, size=256, tiles=8, colours=((0.55, 0.42, 0.3), (0.32, 0.22, 0.14)), grout=0.06):
    """A floor-tile texture made with numpy and packed into the file (it needs no file on
    disk): `tiles` x `tiles` tiles of two alternating colours with dark grout lines."""
    image = bpy.data.images.new(name, size, size, alpha=False)
    t = (np.arange(size) + 0.5) / size * tiles
    u, v = np.meshgrid(t, t)
    checker = ((np.floor(u) + np.floor(v)) % 2).astype(bool)
    rgb = np.where(checker[..., None], colours[0], colours[1])
    edge = np.minimum(np.minimum(u % 1, 1 - u % 1), np.minimum(v % 1, 1 - v % 1)) < grout / 2
    rgb[edge] = 0.05
    pixels = np.concatenate([rgb, np.ones((size, size, 1))], axis=2).astype(np.float32)
    image.pixels.foreach_set(pixels.ravel())
    image.pack()
    return image


def packed_leaf_image(name, size=128, colour=(0.12, 0.35, 0.08)):
    """A leaf texture with alpha, made with numpy and packed into the file: an elliptic
    leaf with a paler midrib on a transparent ground, as a foliage card's image."""
    image = bpy.data.images.new(name, size, size, alpha=True)
    t = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    u, v = np.meshgrid(t, t)
    inside = (u / 0.45) ** 2 + v ** 2 < 0.9 * (1.0 - 0.3 * v)
    rgb = np.broadcast_to(np.asarray(colour), (size, size, 3)).copy()
    rgb[np.abs(u) < 0.03] = np.asarray(colour) * 1.8
    pixels = np.concatenate([rgb, inside[..., None].astype(float)], axis=2).astype(np.float32)
    image.pixels.foreach_set(pixels.ravel())
    image.pack()
    return image


def add_area_light(name, location, rotation_degrees, power, size, shape="SQUARE", size_y=None):
    """An Area light as Add > Light > Area adds it, with its power (W), shape and size."""
    bpy.ops.object.light_add(type="AREA", location=location,
                             rotation=tuple(math.radians(a) for a in rotation_degrees))
    light = bpy.context.active_object
    light.name = light.data.name = name
    light.data.energy = power
    light.data.shape = shape
    light.data.size = size
    if size_y is not None:
        light.data.size_y = size_y
    return light


def _world(name):
    """The scene's world, named `name`, with its node tree's Background node."""
    world = bpy.context.scene.world or bpy.data.worlds.new(name)
    bpy.context.scene.world = world
    world.name = name
    return world, world.node_tree.nodes["Background"]


def hdri_world(file_name="forest.exr", rotation_degrees=0.0, strength=1.0):
    """World > Color > Environment Texture of a bundled HDRI, turned about Z by a Mapping node."""
    world, background = _world(f"HDRI {file_name}")
    tree = world.node_tree
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(os.path.join(STUDIO_LIGHTS, file_name), check_existing=True)
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(rotation_degrees))
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    tree.links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    tree.links.new(texture.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = strength
    return world


def sky_world(sun_elevation_degrees, sun_rotation_degrees=0.0, strength=1.0):
    """World > Color > Sky Texture of Blender's default sky type with its sun where asked."""
    world, background = _world("Sky")
    sky = world.node_tree.nodes.new("ShaderNodeTexSky")
    sky.sun_elevation = math.radians(sun_elevation_degrees)
    sky.sun_rotation = math.radians(sun_rotation_degrees)
    world.node_tree.links.new(sky.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = strength
    return world


def colour_world(colour, strength=1.0):
    """A world of one colour: the Background node's Color set, as the World tab shows it."""
    world, background = _world("Plain colour")
    background.inputs["Color"].default_value = (*colour, 1.0)
    background.inputs["Strength"].default_value = strength
    world.color = colour
    return world


def towards_sky_sun(sun_elevation_degrees, sun_rotation_degrees):
    """The unit direction from the ground to the Sky Texture's sun: rotation 0 puts it
    along +Y, rotation turns it clockwise seen from above (Cycles turns the rotation
    around, 2π - rotation, and takes geographical_to_direction of elevation and that
    + 90°: addon/sky_models.py sun_direction)."""
    elevation, rotation = math.radians(sun_elevation_degrees), math.radians(sun_rotation_degrees)
    return (math.sin(rotation) * math.cos(elevation), math.cos(rotation) * math.cos(elevation),
            math.sin(elevation))


def camera_at(scene, location, target, lens=35.0):
    """The scene camera at `location` looking at `target`, at the scene's resolution."""
    return add_camera(scene, location, target, lens=lens,
                      resolution=(scene.render.resolution_x, scene.render.resolution_y), clip_end=500.0)
