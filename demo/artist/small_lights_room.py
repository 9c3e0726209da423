"""A room lit by 60 small Point lights (2 cm, 1 W each) in a grid under its ceiling and
nothing else, with a table and a cabinet on its floor: more lights than get light maps,
so most are lit through the emitter grid."""
from .shading import add_box, add_room, camera_at, factory_scene, principled

ROOM = (6.0, 5.0, 2.8)  # inside width (x), depth (y), height (z), metres
WALL = 0.2
ROWS, COLUMNS = 6, 10


def build(resolution=(1920, 1080)):
    import bpy
    scene = factory_scene(resolution)
    plaster = principled("Plaster", (0.8, 0.78, 0.74), roughness=1.0)
    floor = principled("Concrete", (0.5, 0.48, 0.45), roughness=1.0)
    width, depth, height = ROOM
    add_room(ROOM, WALL, floor, plaster)
    add_box("Table", (-0.8, 0.3, 0.375), (1.6, 0.9, 0.75), principled("Ash", (0.65, 0.5, 0.35), roughness=0.9))
    add_box("Cabinet", (2.2, 1.8, 0.6), (1.0, 0.5, 1.2), principled("Green paint", (0.2, 0.45, 0.3), roughness=1.0))
    light = bpy.data.lights.new("Small light", "POINT")
    light.energy = 1.0
    light.shadow_soft_size = 0.02
    for row in range(ROWS):
        for column in range(COLUMNS):
            lamp = bpy.data.objects.new(f"Small light {row + 1}.{column + 1}", light)
            lamp.location = (-width / 2 + (column + 0.5) * width / COLUMNS,
                             -depth / 2 + (row + 0.5) * depth / ROWS, height - 0.3)
            scene.collection.objects.link(lamp)
    camera_at(scene, (-width / 2 + 0.4, -depth / 2 + 0.4, 1.7), (0.5, 0.8, 0.6), lens=18.0)
    return scene
