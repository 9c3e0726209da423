"""A closed room lit by one ceiling area light (a 1.2 m panel, 400 W) and nothing else:
walls, floor and ceiling are cubes, a glossy wooden floor, a sofa and a table with a
steel bowl; the factory world is outside and never seen."""

from .shading import add_area_light, add_box, add_modifier, add_primitive, add_room, camera_at, factory_scene, principled

ROOM = (5.0, 4.0, 2.8)  # inside width (x), depth (y), height (z), metres
WALL = 0.2


def build(resolution=(1920, 1080)):
    scene = factory_scene(resolution)
    scene.cycles.samples = 1024
    plaster = principled("Plaster", (0.8, 0.78, 0.72), roughness=0.9)
    floor = principled("Lacquered oak", (0.45, 0.3, 0.18), roughness=0.2)
    fabric = principled("Sofa fabric", (0.55, 0.2, 0.15), roughness=1.0)
    steel = principled("Steel", (0.75, 0.75, 0.75), roughness=0.25, metallic=1.0)
    width, depth, height = ROOM
    add_room(ROOM, WALL, floor, plaster)
    sofa = add_box("Sofa", (-0.5, depth / 2 - 0.55, 0.4), (2.2, 0.9, 0.8), fabric)
    add_modifier(sofa, "BEVEL", width=0.06, segments=3)
    table = add_box("Table", (0.3, 0.2, 0.225), (1.2, 0.7, 0.45), floor)
    add_modifier(table, "BEVEL", width=0.02, segments=2)
    add_primitive("uv_sphere", "Bowl", steel, smooth=True, radius=0.2, location=(0.5, 0.2, 0.58),
                  scale=(1.0, 1.0, 0.6))
    add_area_light("Ceiling panel", (0.0, 0.0, height - 0.02), (0.0, 0.0, 0.0), power=400.0, size=1.2)
    camera_at(scene, (-width / 2 + 0.4, -depth / 2 + 0.4, 1.6), (0.8, 0.8, 0.5), lens=18.0)
    return scene
