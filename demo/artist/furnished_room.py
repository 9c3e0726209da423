"""A furnished living room: a sofa, an armchair, a low table with books, a bookcase of
shelves and boxes, a floor lamp's Point light (8 cm) and a ceiling Area light, in a closed
room: many objects shading and lighting one another."""
from .shading import add_area_light, add_box, add_primitive, add_room, camera_at, factory_scene, principled

ROOM = (6.0, 5.0, 2.8)  # inside width (x), depth (y), height (z), metres
WALL = 0.2


def build(resolution=(1920, 1080)):
    import bpy
    scene = factory_scene(resolution)
    plaster = principled("Plaster", (0.8, 0.77, 0.7), roughness=1.0)
    floor = principled("Walnut", (0.3, 0.2, 0.12), roughness=0.9)
    fabric = principled("Fabric", (0.25, 0.35, 0.5), roughness=1.0)
    wood = principled("Pine", (0.6, 0.45, 0.3), roughness=0.9)
    width, depth, height = ROOM
    add_room(ROOM, WALL, floor, plaster)
    add_box("Sofa seat", (-1.0, 1.8, 0.22), (2.2, 0.9, 0.44), fabric)
    add_box("Sofa back", (-1.0, 2.2, 0.6), (2.2, 0.2, 0.6), fabric)
    add_box("Armchair", (1.6, 0.8, 0.3), (0.9, 0.9, 0.6), fabric)
    add_box("Low table", (-0.9, 0.6, 0.2), (1.2, 0.7, 0.4), wood)
    colours = ((0.7, 0.2, 0.15), (0.2, 0.5, 0.25), (0.8, 0.7, 0.3), (0.25, 0.3, 0.6))
    for index, colour in enumerate(colours):
        add_box(f"Book {index + 1}", (-1.2 + 0.18 * index, 0.6, 0.44), (0.15, 0.22, 0.08),
                principled(f"Cover {index + 1}", colour, roughness=1.0))
    for shelf in range(5):
        add_box(f"Shelf {shelf + 1}", (width / 2 - 0.2, -0.8, 0.05 + 0.45 * shelf), (0.35, 1.6, 0.03), wood)
        for slot in range(3):
            add_box(f"Box {shelf + 1}.{slot + 1}", (width / 2 - 0.2, -1.3 + 0.5 * slot, 0.2 + 0.45 * shelf),
                    (0.3, 0.3, 0.28), principled(f"Box {shelf + 1}.{slot + 1}", colours[(shelf + slot) % 4],
                                                 roughness=1.0))
    add_primitive("cylinder", "Lamp stand", wood, radius=0.03, depth=1.5, location=(0.6, 2.0, 0.75))
    bpy.ops.object.light_add(type="POINT", location=(0.6, 2.0, 1.6))
    lamp = bpy.context.active_object
    lamp.name = lamp.data.name = "Floor lamp"
    lamp.data.energy = 150.0
    lamp.data.shadow_soft_size = 0.08
    add_area_light("Ceiling panel", (0.0, 0.0, height - 0.02), (0.0, 0.0, 0.0), power=250.0, size=0.8)
    camera_at(scene, (-width / 2 + 0.4, -depth / 2 + 0.4, 1.5), (0.5, 1.0, 0.6), lens=18.0)
    return scene
