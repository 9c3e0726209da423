"""Scenes made of arrays, for measurements and tests that need no Blender."""
import dataclasses

import numpy as np

from ..gpu.scene import Camera, Light, Scene
from ..gpu.scene_file import load_scene


def room_scene(quads_per_side, scale=1.0, light_position=(0.4, -0.3, 2.0), offset=(0.0, 0.0, 0.0)):
    """A closed 4 x 4 x 3 m room (times `scale`, moved by `offset` in float64) around a
    point light, each of its six sides n x n quads; the light's power scales with scale²
    so irradiance stays the same. Sanitized."""
    offset = np.asarray(offset, dtype=np.float64)
    corners = np.array([[x, y, z] for x in (-2, 2) for y in (-2, 2) for z in (0, 3)], dtype=np.float64) * scale
    sides = [(0, 2, 6, 4), (1, 5, 7, 3), (0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6)]
    steps = np.linspace(0, 1, quads_per_side + 1)
    triangles = []
    for a, b, c, d in sides:
        def point(u, v):
            return (1 - v) * ((1 - u) * corners[a] + u * corners[b]) + v * ((1 - u) * corners[d] + u * corners[c])
        for u0, u1 in zip(steps[:-1], steps[1:]):
            for v0, v1 in zip(steps[:-1], steps[1:]):
                triangles += [[point(u0, v0), point(u1, v0), point(u1, v1)], [point(u0, v0), point(u1, v1), point(u0, v1)]]
    triangles = np.array(triangles, dtype=np.float64) + offset
    light = Light("POINT", np.array(light_position) * scale + offset, (0, 0, -1), (0, 1, 0), (1, 1, 1),
                  100.0 * scale ** 2)
    camera = Camera.look_at(np.array((0, -1.9, 1.5)) * scale + offset, np.array((0, 0, 1)) * scale + offset,
                            near=0.01 * scale, far=20 * scale)
    return Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.6), [light], camera).sanitize()


def particle_room(count, quads_per_side=4, total_flux=200.0, seed=0, scale=1.0):
    """The room lit only by `count` emissive particles (together `total_flux` W, warm
    white, each of 79 mm² surface: a sphere 5 mm across) in a swirl over the floor, times
    `scale` (the flux by scale²: the same irradiance). Sanitized."""
    rng = np.random.default_rng(seed)
    room = room_scene(quads_per_side, scale)
    turn = rng.random(count) * 6 * np.pi
    radius = 1.6 * np.sqrt(rng.random(count))
    height = 0.2 + 2.4 * rng.random(count)
    emitters = np.zeros((count, 7), dtype=np.float64)
    emitters[:, 0], emitters[:, 1], emitters[:, 2] = radius * np.cos(turn), radius * np.sin(turn), height
    emitters[:, :3] *= scale
    emitters[:, 3:6] = np.array([1.0, 0.8, 0.6]) * total_flux / count * scale ** 2
    emitters[:, 6] = np.pi * (0.005 * scale) ** 2
    return Scene(room.triangles, room.normals, room.albedo, [], room.camera, point_emitters=emitters).sanitize()


def lamps_over_floor(count, quads_per_side=4, total_power=400.0, seed=0):
    """The room lit by `count` point lights (together `total_power` W, random colours)
    scattered 0.3-0.8 m over its floor. Sanitized."""
    rng = np.random.default_rng(seed)
    room = room_scene(quads_per_side)
    lights = [Light("POINT", (rng.uniform(-1.8, 1.8), rng.uniform(-1.8, 1.8), rng.uniform(0.3, 0.8)), (0, 0, -1),
                    (0, 1, 0), 0.5 + 0.5 * rng.random(3), total_power / count, radius=0.05, name=f"lamp{i}")
              for i in range(count)]
    return Scene(room.triangles, room.normals, room.albedo, lights, room.camera).sanitize()


def box_triangles(low, high):
    """The 12 triangles of a closed axis-aligned box."""
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
    sides = [(0, 2, 6, 4), (1, 5, 7, 3), (0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6)]
    return np.array([[corners[a], corners[b], corners[c]] for a, b, c, d in sides] +
                    [[corners[a], corners[c], corners[d]] for a, b, c, d in sides])


def particles_in_a_box(count=2000, seed=0):
    """The room with its particles (`particle_room`) shut inside a closed 1 m box on the
    floor: none of their light may reach the room. Sanitized."""
    room = particle_room(count, seed=seed)
    rng = np.random.default_rng(seed)
    emitters = np.array(room.point_emitters, dtype=np.float64)
    emitters[:, :3] = rng.uniform((-0.4, -0.4, 0.1), (0.4, 0.4, 0.9), (count, 3))
    walls = box_triangles((-0.5, -0.5, 0.0), (0.5, 0.5, 1.0))
    triangles = np.concatenate([room.triangles, walls])
    albedo = np.concatenate([room.albedo, np.full((len(walls), 3), 0.6, np.float32)])
    return Scene(triangles, np.zeros_like(triangles), albedo, [], room.camera, point_emitters=emitters).sanitize()


def glossy(scene):
    """`scene` with the Principled BSDF's default glossy layer on every surface (F0 0.04,
    roughness 0.5), as an artist's scene has it."""
    return dataclasses.replace(scene, specular=np.tile(np.float32([0.04, 0.04, 0.04, 0.5, 0.0]),
                                                       (len(scene.triangles), 1)))


def boxed_lamp(scene, rooms=True):
    """`scene` with a closed 1 m box standing 1 cm over its floor, a second point light shut
    inside it; with `rooms`, the box known to be closed (Scene.solids), so that it is a room
    (gpu/closed_meshes.py); without, the same triangles and lights with no rooms. Sanitized."""
    walls = box_triangles((-0.5, 0.2, 0.01), (0.5, 1.2, 1.01))
    triangles = np.concatenate([scene.triangles, walls])
    albedo = np.concatenate([scene.albedo, np.full((len(walls), 3), 0.6, np.float32)])
    solids = np.concatenate([np.full(len(scene.triangles), -1), np.zeros(len(walls))]).astype(np.int32)
    lamp = Light("POINT", (0.0, 0.7, 0.5), (0, 0, -1), (0, 1, 0), (1, 0.8, 0.6), 50.0, name="boxed")
    return Scene(triangles, np.zeros_like(triangles), albedo, [*scene.lights, lamp], scene.camera,
                 solids=solids if rooms else None).sanitize()


NAMED_SCENES = {"room1200k": lambda: room_scene(320), "room1200k_glossy": lambda: glossy(room_scene(320)),
                "room1200k_boxed_lamp": lambda: boxed_lamp(room_scene(320)),
                "room1200k_boxed_lamp_no_rooms": lambda: boxed_lamp(room_scene(320), rooms=False)}
"""The scenes the GPU timing scripts make by name: a closed room of 1,228,800 triangles
around a point light, the same with a glossy layer everywhere, and the same with a lamp
shut in a closed box on its floor, a room or (no_rooms) not."""


def scene_by_name(folder, name):
    """NAMED_SCENES' scene `name`, else the export `folder`/`name`.npz."""
    return NAMED_SCENES[name]() if name in NAMED_SCENES else load_scene(f"{folder}/{name}.npz")
