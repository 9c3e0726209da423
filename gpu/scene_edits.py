"""Edits of a Scene that the benchmarks and the demo exports share: the lights replaced by
a set of one kind or by one point light, a light turned about its own axis, a camera
path.

They change the Scene's arrays only, never Blender's scene: `demo.export_npz` writes
lights made here back into Blender so that Cycles renders the same ones.
"""
import dataclasses
import math

import numpy as np

from .scene import LIGHT_KINDS, Camera, Light

LIGHT_KIND_NAMES = {kind.lower(): kind for kind in LIGHT_KINDS}
"""The light kinds by the names a command line or a sweep gives ("point" -> "POINT")."""


def with_lights(scene, count, kind):
    """The scene with its lights replaced by `count` lights of `kind` ("point", "spot",
    "area", "sun") on a square grid a quarter of the height under the top of its bounds,
    pointing down; their powers add up to the power that gives the floor about 1 W/m²
    from one light (a sun: 1 W/m² in all)."""
    low, high = scene.bounds()
    side = math.ceil(math.sqrt(count))
    height = 0.75 * (high[2] - low[2])
    lights = []
    for i in range(count):
        u, v = (i % side + 0.5) / side, (i // side + 0.5) / side
        position = np.array([low[0] + (0.25 + 0.5 * u) * (high[0] - low[0]),
                             low[1] + (0.25 + 0.5 * v) * (high[1] - low[1]), low[2] + height])
        blender_kind = LIGHT_KIND_NAMES[kind]
        power = 1.0 / count if blender_kind == "SUN" else 4 * math.pi * max(height, 1e-3) ** 2 / count
        direction = (0.3 * (u - 0.5), 0.3 * (v - 0.5), -1.0) if blender_kind == "SUN" else (0.0, 0.0, -1.0)
        lights.append(Light(blender_kind, position, direction, (0, 1, 0), (1, 1, 1), power, spot_size=math.radians(90),
                            size=(0.5, 0.5), name=f"sweep {kind} {i}"))
    scene.lights = lights
    return scene


def with_point_light(scene):
    """The thesis measures one point light. A scene without a point light gets one at the
    centre of its bounds, a quarter of the height below the top, of a power that gives
    the bounds' floor about 1 W/m² (the scene's own lights are replaced)."""
    if any(light.kind == "POINT" for light in scene.lights):
        scene.lights = [next(light for light in scene.lights if light.kind == "POINT")]
        return scene
    low, high = scene.bounds()
    position = (low + high) / 2
    position[2] = high[2] - 0.25 * (high[2] - low[2])
    height = position[2] - low[2]
    power = 4 * math.pi * max(height, 1e-3) ** 2
    scene.lights = [Light("POINT", position, (0, 0, -1), (0, 1, 0), (1, 1, 1), power, name="bench point light")]
    return scene


def turned_about_its_axis(light, degrees=45.0):
    """The light with its frame (its up vector) turned about its direction."""
    a, d, up = math.radians(degrees), light.direction, light.up
    turned = up * math.cos(a) + np.cross(d, up) * math.sin(a) + d * np.dot(d, up) * (1 - math.cos(a))
    return dataclasses.replace(light, up=turned)


def camera_path(camera, frames, degrees=10.0):
    """The scene camera turned about its own vertical axis from -degrees to +degrees."""
    cameras = []
    for angle in np.linspace(-degrees, degrees, frames) if frames > 1 else [0.0]:
        a = math.radians(angle)
        turn = np.array([[math.cos(a), 0, math.sin(a), 0], [0, 1, 0, 0], [-math.sin(a), 0, math.cos(a), 0], [0, 0, 0, 1]])
        cameras.append(Camera(turn @ camera.view, camera.projection))
    return cameras
