"""A closed room lit only by the sky through two windows: walls, floor and ceiling are
cubes, the windows cut from one wall by Boolean modifiers with hidden cutters, no lamps;
the world is a Sky Texture of Blender's default type with the sun 35° up, in front of
the windows."""
from .shading import add_box, add_modifier, add_room, camera_at, cut_window, factory_scene, principled, sky_world

ROOM = (6.0, 5.0, 3.0)  # inside width (x), depth (y), height (z), metres
WALL = 0.2
SUN_ELEVATION, SUN_ROTATION = 35.0, 200.0  # the sun stands outside the window wall at y < 0, off to one side


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    sky_world(SUN_ELEVATION, SUN_ROTATION)
    plaster = principled("Plaster", (0.8, 0.78, 0.72), roughness=0.9)
    wood = principled("Oak floor", (0.45, 0.3, 0.18), roughness=0.5)
    fabric = principled("Sofa fabric", (0.15, 0.3, 0.45), roughness=1.0)
    width, depth, height = ROOM
    walls = add_room(ROOM, WALL, wood, plaster, front_wall="Window wall")
    for index, x in enumerate((-1.4, 1.4)):
        cut_window(walls["Window wall"], f"Window cutter {index + 1}", (x, -(depth + WALL) / 2, 1.6), (1.4, 1.6), WALL)
    sofa = add_box("Sofa", (0.0, depth / 2 - 0.6, 0.4), (2.2, 0.9, 0.8), fabric)
    add_modifier(sofa, "BEVEL", width=0.06, segments=3)
    table = add_box("Table", (0.6, 0.3, 0.225), (1.2, 0.7, 0.45), wood)
    add_modifier(table, "BEVEL", width=0.02, segments=2)
    camera_at(scene, (-width / 2 + 0.5, depth / 2 - 0.4, 1.7), (0.8, -depth / 2, 0.9), lens=20.0)
    return scene
