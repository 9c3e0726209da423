"""A courtyard open to the sky: four 6 m walls around a 10 x 8 m paved floor, an arcade
of pillars along one side and a fountain basin, under a Sky Texture and its sun: the
shaded walls are lit by the sunlit ones and the floor."""
from .shading import (add_box, add_primitive, add_sun_lamp, camera_at, factory_scene, principled, sky_world,
                      towards_sky_sun)

YARD = (10.0, 8.0, 6.0)  # inside width (x), depth (y), wall height (z), metres
WALL = 0.4
SUN_ELEVATION, SUN_ROTATION = 50.0, 150.0


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    sky_world(SUN_ELEVATION, SUN_ROTATION, strength=0.3)
    stone = principled("Sandstone", (0.72, 0.6, 0.45), roughness=0.9)
    paving = principled("Paving", (0.55, 0.52, 0.48), roughness=0.8)
    width, depth, height = YARD
    add_box("Ground", (0.0, 0.0, -0.1), (width + 2 * WALL, depth + 2 * WALL, 0.2), paving)
    for name, centre, size in (("North wall", (0, (depth + WALL) / 2, height / 2), (width + 2 * WALL, WALL, height)),
                               ("South wall", (0, -(depth + WALL) / 2, height / 2), (width + 2 * WALL, WALL, height)),
                               ("West wall", (-(width + WALL) / 2, 0, height / 2), (WALL, depth, height)),
                               ("East wall", ((width + WALL) / 2, 0, height / 2), (WALL, depth, height))):
        add_box(name, centre, size, stone)
    for index in range(5):
        add_primitive("cylinder", f"Pillar {index + 1}", stone, radius=0.2, depth=3.0,
                      location=(-4.0 + 2.0 * index, depth / 2 - 1.5, 1.5))
    add_box("Arcade roof", (0.0, depth / 2 - 0.75, 3.1), (width, 1.5, 0.2), stone)
    add_primitive("cylinder", "Basin", stone, radius=1.2, depth=0.5, location=(0.5, -0.8, 0.25))
    add_sun_lamp(towards_sky_sun(SUN_ELEVATION, SUN_ROTATION), strength=3.0, angle_degrees=0.5)
    camera_at(scene, (-width / 2 + 0.8, -depth / 2 + 0.8, 1.7), (1.5, 1.0, 2.0), lens=18.0)
    return scene
