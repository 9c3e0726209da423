"""A room lit by a Sun lamp (3° across) and the sky through a wide open window, with a
potted plant of alpha-masked leaf cards standing in the sunbeam and a glossy tiled floor:
the leaves' cut-outs shape the shadow on the floor. (No pane: Cycles lets a sun through
glass only as a caustic, which a few hundred samples cannot show.)"""
import math

from .shading import (add_modifier, add_primitive, add_room, add_sun_lamp, camera_at, cut_window, factory_scene,
                      packed_leaf_image, packed_tile_image, principled, sky_world, towards_sky_sun)

ROOM = (5.0, 4.0, 2.8)  # inside width (x), depth (y), height (z), metres
WALL = 0.2
SUN_ELEVATION, SUN_ROTATION = 40.0, 190.0  # outside the window wall at y < 0


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    sky_world(SUN_ELEVATION, SUN_ROTATION, strength=0.3)
    plaster = principled("Plaster", (0.8, 0.78, 0.72), roughness=0.9)
    tiles = principled("Glazed tiles", (0.6, 0.6, 0.6), roughness=0.25, image=packed_tile_image("Tiles"))
    width, depth, height = ROOM
    walls = add_room(ROOM, WALL, tiles, plaster, front_wall="Window wall")
    cut_window(walls["Window wall"], "Window cutter", (0.0, -(depth + WALL) / 2, 1.5), (2.4, 1.6), WALL)
    pot = add_primitive("cylinder", "Pot", principled("Terracotta", (0.6, 0.3, 0.18), roughness=0.8), radius=0.22,
                        depth=0.4, location=(0.3, -0.4, 0.2))
    add_modifier(pot, "BEVEL", width=0.02, segments=2)
    leaf = principled("Leaf", (0.12, 0.35, 0.08), roughness=0.5, image=packed_leaf_image("Leaf"), image_alpha=True)
    for index in range(10):
        angle = index * 36.0
        radius = 0.12 + 0.05 * (index % 2)
        add_primitive("plane", f"Leaf {index + 1}", leaf, size=0.5,
                      location=(0.3 + radius * math.cos(math.radians(angle)),
                                -0.4 + radius * math.sin(math.radians(angle)), 0.65 + 0.12 * (index % 3)),
                      rotation=(math.radians(55 + 10 * (index % 2)), 0.0, math.radians(angle + 90)))
    add_sun_lamp(towards_sky_sun(SUN_ELEVATION, SUN_ROTATION), strength=4.0, angle_degrees=3.0)
    camera_at(scene, (width / 2 - 0.4, depth / 2 - 0.4, 1.7), (-0.3, -0.8, 0.4), lens=20.0)
    return scene
