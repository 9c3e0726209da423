"""Objects on a floor lit by a plain-colour world alone: no lamps and no emitters, so
every bit of light comes from the world (its ambient light and occlusion)."""
import math

from .shading import add_modifier, add_primitive, camera_at, colour_world, factory_scene, principled

SKY_COLOUR = (0.55, 0.65, 0.8)


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    colour_world(SKY_COLOUR, strength=1.0)
    add_primitive("plane", "Floor", principled("Concrete", (0.5, 0.5, 0.5), roughness=0.8), size=12.0)
    monkey = add_primitive("monkey", "Suzanne", principled("Clay", (0.8, 0.45, 0.3), roughness=0.6), smooth=True,
                           location=(0.0, 0.0, 0.75), rotation=(math.radians(-15), 0.0, math.radians(20)))
    add_modifier(monkey, "SUBSURF", levels=1, render_levels=2)
    add_primitive("torus", "Torus", principled("Teal plastic", (0.1, 0.5, 0.45), roughness=0.3),
                  major_radius=0.5, minor_radius=0.18, location=(1.6, 0.6, 0.18))
    add_primitive("cylinder", "Pillar", principled("White plastic", (0.85, 0.85, 0.82), roughness=0.4),
                  radius=0.3, depth=1.6, location=(-1.5, 0.9, 0.8))
    add_primitive("cube", "Crate", principled("Yellow paint", (0.8, 0.6, 0.1), roughness=0.5), size=0.7,
                  location=(-0.9, -0.9, 0.35), rotation=(0, 0, math.radians(30)))
    camera_at(scene, (0.5, -5.5, 2.4), (0.0, 0.0, 0.6), lens=35.0)
    return scene
