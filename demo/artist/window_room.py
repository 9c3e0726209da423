"""The classic window-lit interior: a closed room lit only by a Sun lamp (1° across)
through one window in its front wall, the world black, a rug, a bed and a wardrobe:
every light the room gets beyond the sunlit patch comes from bounces."""
from .shading import add_box, add_room, add_sun_lamp, camera_at, colour_world, cut_window, factory_scene, principled

ROOM = (4.0, 5.0, 2.7)  # inside width (x), depth (y), height (z), metres
WALL = 0.2
TOWARDS_SUN = (0.35, -0.75, 0.56)  # outside the window wall at y < 0, 34 degrees up


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    colour_world((0.0, 0.0, 0.0))
    plaster = principled("Plaster", (0.78, 0.76, 0.7), roughness=1.0)
    oak = principled("Oak", (0.42, 0.28, 0.16), roughness=0.9)
    width, depth, height = ROOM
    walls = add_room(ROOM, WALL, oak, plaster, front_wall="Window wall")
    cut_window(walls["Window wall"], "Window cutter", (0.4, -(depth + WALL) / 2, 1.45), (1.2, 1.3), WALL)
    add_box("Rug", (0.3, -0.6, 0.005), (1.6, 1.1, 0.01), principled("Rug", (0.6, 0.15, 0.12), roughness=1.0))
    add_box("Bed", (-0.9, 1.3, 0.25), (1.4, 2.0, 0.5), principled("Linen", (0.85, 0.85, 0.82), roughness=1.0))
    add_box("Wardrobe", (1.55, 1.8, 1.0), (0.6, 1.2, 2.0), oak)
    add_sun_lamp(TOWARDS_SUN, strength=5.0, angle_degrees=1.0)
    camera_at(scene, (-width / 2 + 0.4, depth / 2 - 0.4, 1.6), (0.4, -1.5, 0.6), lens=18.0)
    return scene
