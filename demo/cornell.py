"""The Cornell box: a 2 m room open towards the camera, red and green side walls, a tall
and a short white box, one point light under the ceiling.

Box footprints, heights and the camera come from the classic Cornell measurement data
(555 units across), scaled to 2 m and turned into Blender's axes: x to the right, y into
the room, z up.
"""
import math

import bpy
import numpy as np

from .builder import MeshBuilder, add_camera, add_light, principled_material

WHITE = (0.73, 0.73, 0.73)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)

CLASSIC_SCALE = 2.0 / 555.0
CLASSIC_CENTER = (277.5, 279.5)  # classic (x, z) of the room's centre line
SHORT_BOX = ([(130, 65), (82, 225), (240, 272), (290, 114)], 165)
TALL_BOX = ([(423, 247), (265, 296), (314, 456), (472, 406)], 330)


def build(subdivisions=8, light_power=60.0, light_height=1.8, resolution=(512, 512)):
    """Build the Cornell box into the current scene and return the scene.

    Each wall is a `subdivisions` x `subdivisions` grid and each box face half that, so
    the room has 10·s² + 16·ceil(s/2)² + 4 triangles (900 at the default 8).
    """
    scene = bpy.context.scene
    collection = scene.collection
    white, red, green = (principled_material(name, color) for name, color in
                         (("Cornell white", WHITE), ("Cornell red", RED), ("Cornell green", GREEN)))
    n = subdivisions
    walls = {  # origin, edge_u, edge_v: each wall faces edge_u x edge_v, into the room
        "Floor": ((-1, -1, 0), (2, 0, 0), (0, 2, 0), white),
        "Ceiling": ((-1, -1, 2), (0, 2, 0), (2, 0, 0), white),
        "Back wall": ((-1, 1, 0), (2, 0, 0), (0, 0, 2), white),
        "Left wall": ((-1, -1, 0), (0, 2, 0), (0, 0, 2), red),
        "Right wall": ((1, -1, 0), (0, 0, 2), (0, 2, 0), green),
    }
    for name, (origin, edge_u, edge_v, material) in walls.items():
        wall = MeshBuilder()
        wall.parallelogram(origin, edge_u, edge_v, n, n)
        wall.to_object(name, [material], collection)
    box_subdivisions = max(1, math.ceil(n / 2))
    for name, (corners, height) in (("Short box", SHORT_BOX), ("Tall box", TALL_BOX)):
        box = MeshBuilder()
        box.prism(_from_classic(corners), 0.0, height * CLASSIC_SCALE, box_subdivisions, box_subdivisions,
                  faces=("sides", "top"))
        box.to_object(name, [white], collection)
    add_light(scene, "Ceiling light", "POINT", (0.0, 0.0, light_height), light_power, shadow_soft_size=0.05)
    # The classic camera: 800 units in front of the opening, 39.3 degrees across.
    camera = add_camera(scene, (0.0, -(800 + CLASSIC_CENTER[1]) * CLASSIC_SCALE, 273 * CLASSIC_SCALE),
                        (0.0, 0.0, 273 * CLASSIC_SCALE), resolution=resolution, clip_end=20.0)
    camera.data.angle = math.radians(39.3)
    return scene


def _from_classic(corners):
    """Classic (x, z) floor coordinates to ours; the classic x axis points to our left."""
    corners = np.asarray(corners, dtype=np.float64)
    return np.column_stack([-(corners[:, 0] - CLASSIC_CENTER[0]), corners[:, 1] - CLASSIC_CENTER[1]]) * CLASSIC_SCALE
