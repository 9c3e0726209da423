"""Scenes made of arrays, for measurements and tests that need no Blender."""
import numpy as np

from ..gpu.scene import Camera, Light, Scene


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
