"""An exterior at noon: a Sky Texture with the sun 70° up and a Sun lamp along the same
direction (as artists pair them, the lamp giving crisp shadows), a lawn, a path, a small
house with a pitched roof, a tree and a stone ball."""
import math

from .shading import (add_modifier, add_primitive, add_sun_lamp, camera_at, factory_scene, principled, sky_world,
                      towards_sky_sun)

SUN_ELEVATION, SUN_ROTATION = 70.0, 150.0


def build(resolution=(1920, 1080), sun_strength=4.0):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    sky_world(SUN_ELEVATION, SUN_ROTATION)
    add_sun_lamp(towards_sky_sun(SUN_ELEVATION, SUN_ROTATION), sun_strength, angle_degrees=0.545)  # the sun's own
    add_primitive("plane", "Lawn", principled("Grass", (0.12, 0.25, 0.05), roughness=0.9), size=60.0)
    add_primitive("plane", "Path", principled("Gravel", (0.45, 0.42, 0.38), roughness=0.95), size=1.0,
                  location=(0.0, -4.0, 0.01), scale=(1.2, 6.0, 1.0))
    house = add_primitive("cube", "House", principled("Render", (0.85, 0.8, 0.7), roughness=0.8), size=1.0,
                          location=(0.0, 2.0, 1.5), scale=(5.0, 4.0, 3.0))
    add_modifier(house, "BEVEL", width=0.03, segments=1)
    roof = add_primitive("cone", "Roof", principled("Roof tiles", (0.45, 0.12, 0.08), roughness=0.7), vertices=4,
                         radius1=3.9, depth=2.0, location=(0.0, 2.0, 4.0), rotation=(0, 0, math.radians(45)))
    roof.scale = (1.0, 0.8, 1.0)
    add_primitive("cube", "Door", principled("Door", (0.2, 0.1, 0.05), roughness=0.4), size=1.0,
                  location=(0.0, -0.02, 1.0), scale=(1.0, 0.05, 2.0))
    bark = principled("Bark", (0.2, 0.13, 0.08), roughness=0.9)
    add_primitive("cylinder", "Trunk", bark, vertices=16, radius=0.18, depth=2.4, location=(-5.0, -1.0, 1.2))
    add_primitive("ico_sphere", "Crown", principled("Leaves", (0.08, 0.22, 0.04), roughness=0.8), smooth=True,
                  subdivisions=2, radius=1.6, location=(-5.0, -1.0, 3.4))
    add_primitive("uv_sphere", "Stone ball", principled("Stone", (0.5, 0.5, 0.48), roughness=0.7), smooth=True,
                  radius=0.4, location=(2.2, -3.0, 0.4))
    camera_at(scene, (7.0, -11.0, 2.2), (-0.5, 1.0, 1.6), lens=30.0)
    return scene
