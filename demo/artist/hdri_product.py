"""A product shot lit by an HDRI alone: forest.exr as the world, turned by a Mapping node,
over a tiled floor (a packed numpy image texture), a bevelled and subdivided product, a
chrome sphere, an emissive bar and a card with Alpha 0 (in the file, invisible in the
render: what a user hides by its material)."""
import math

from .shading import add_modifier, add_primitive, camera_at, factory_scene, hdri_world, packed_tile_image, principled


def build(resolution=(1920, 1080), hdri="forest.exr", hdri_rotation_degrees=60.0):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    hdri_world(hdri, hdri_rotation_degrees)
    floor = principled("Tiled floor", (0.5, 0.4, 0.3), roughness=0.6, image=packed_tile_image("Floor tiles"))
    add_primitive("plane", "Floor", floor, size=6.0)
    product = add_primitive("cube", "Product", principled("Product paint", (0.7, 0.08, 0.05), roughness=0.35),
                            size=0.8, location=(0.0, 0.0, 0.4), rotation=(0.0, 0.0, math.radians(25)))
    add_modifier(product, "BEVEL", width=0.08, segments=4)
    add_modifier(product, "SUBSURF", levels=1, render_levels=2)
    chrome = principled("Chrome", (0.9, 0.9, 0.9), roughness=0.05, metallic=1.0)
    add_primitive("uv_sphere", "Chrome sphere", chrome, smooth=True, radius=0.35, location=(0.95, -0.35, 0.35))
    bar = add_primitive("cube", "Light bar", principled("Light bar", (1.0, 1.0, 1.0), emission=(1.0, 0.85, 0.6),
                                                        emission_strength=8.0),
                        size=1.0, location=(-1.0, 0.6, 0.05), scale=(0.8, 0.05, 0.05))
    bar.rotation_euler.z = math.radians(-20)
    add_primitive("plane", "Hidden card", principled("Hidden card", (0.2, 0.4, 0.8), alpha=0.0), size=0.6,
                  location=(-0.6, -0.5, 0.3), rotation=(math.radians(90), 0.0, math.radians(15)))
    camera_at(scene, (1.6, -3.6, 1.5), (0.0, 0.0, 0.35), lens=50.0)
    return scene
