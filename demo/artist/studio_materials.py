"""A product shot of materials under studio.exr and one area light: a chrome sphere, a
rough gold torus, a clear glass cylinder, a potted plant of alpha-masked leaf cards (a
packed numpy image whose alpha feeds Alpha) and a glossy lacquered box on a satin
floor."""
import math

from .shading import (add_area_light, add_modifier, add_primitive, camera_at, factory_scene, hdri_world,
                      packed_leaf_image, principled)


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    hdri_world("studio.exr", rotation_degrees=120.0)
    add_primitive("plane", "Floor", principled("Satin floor", (0.55, 0.55, 0.55), roughness=0.3), size=8.0)
    chrome = principled("Chrome", (0.95, 0.95, 0.95), roughness=0.03, metallic=1.0)
    add_primitive("uv_sphere", "Chrome sphere", chrome, smooth=True, radius=0.4, location=(-0.9, 0.3, 0.4))
    gold = principled("Brushed gold", (1.0, 0.77, 0.34), roughness=0.3, metallic=1.0)
    add_primitive("torus", "Gold ring", gold, smooth=True, major_radius=0.35, minor_radius=0.1,
                  location=(0.2, 0.6, 0.1))
    glass = principled("Clear glass", (0.9, 0.95, 0.92), roughness=0.0, transmission=1.0, ior=1.45)
    add_primitive("cylinder", "Glass", glass, smooth=True, radius=0.25, depth=0.7, location=(0.75, -0.35, 0.35))
    lacquer = principled("Red lacquer", (0.6, 0.05, 0.04), roughness=0.15)
    box = add_primitive("cube", "Box", lacquer, size=0.5, location=(-0.2, -0.5, 0.25),
                        rotation=(0.0, 0.0, math.radians(30)))
    add_modifier(box, "BEVEL", width=0.03, segments=3)
    pot = add_primitive("cylinder", "Pot", principled("Clay", (0.55, 0.3, 0.2), roughness=0.8), radius=0.18,
                        depth=0.3, location=(1.3, 0.7, 0.15))
    add_modifier(pot, "BEVEL", width=0.02, segments=2)
    leaf = principled("Leaf", (0.12, 0.35, 0.08), roughness=0.5, image=packed_leaf_image("Leaf"), image_alpha=True)
    for index in range(6):
        angle = index * 60.0
        add_primitive("plane", f"Leaf {index + 1}", leaf, size=0.45,
                      location=(1.3 + 0.15 * math.cos(math.radians(angle)), 0.7 + 0.15 * math.sin(math.radians(angle)),
                                0.5 + 0.05 * (index % 3)),
                      rotation=(math.radians(60), 0.0, math.radians(angle + 90)))
    add_area_light("Softbox", (-1.5, -2.0, 2.5), (50.0, 0.0, -35.0), power=300.0, size=1.5)
    camera_at(scene, (0.4, -4.2, 1.8), (0.2, 0.1, 0.35), lens=45.0)
    return scene
