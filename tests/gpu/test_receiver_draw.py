"""The bounces' points drawn on the GPU (gpu/emitter_bounce.py Receivers,
shaders/receiver_draw.comp): stratified over the surfaces the lights see in proportion
to area, on their triangles, with their triangle's normal, colour and the sides light
reaches, each standing for its share of the area. Real GL through llvmpipe."""
import numpy as np

from lpv_preview.gpu.closed_meshes import BACK, FRONT
from lpv_preview.gpu.emitter_bounce import Receivers
from lpv_preview.gpu.mesh_buffer import MeshBuffer
from lpv_preview.gpu.scene import Camera, Light, Scene

SUN = Light("SUN", (0.0, 0.0, 10.0), (0.3, 0.2, -1.0), (0, 1, 0), (1, 1, 1), 3.0)
COLOURS = np.array([(0.2, 0.4, 0.6), (0.9, 0.5, 0.1)])


def two_triangles():
    """A triangle of 0.5 m² on the floor and one of 1.5 m² on a wall, each its own colour."""
    floor = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    wall = [(0, 2, 0), (3, 2, 0), (0, 2, 1)]
    triangles = np.array([floor, wall], dtype=np.float64)
    return Scene(triangles, np.zeros_like(triangles), COLOURS, [SUN],
                 Camera.look_at((0.5, -3.0, 1.5), (0.5, 1.0, 0.3))).sanitize()


def drawn(glc, scene, count, pattern, sides=None):
    mesh = MeshBuffer(glc, scene)
    mesh.show_open_sides(sides)
    receivers = Receivers(glc, scene, mesh)
    buffer, n = receivers.draw(count, pattern)
    rows = np.frombuffer(buffer.read(), dtype=np.float32).reshape(n, 3, 4).copy()
    buffer.release()
    receivers.release()
    mesh.release()
    return rows


def test_points_fall_on_each_triangle_in_proportion_to_its_area(glc):
    scene = two_triangles()
    rows = drawn(glc, scene, 4096, 7)
    on_wall = np.abs(rows[:, 0, 1] - 2.0) < 1e-5
    # stratified: the wall's 3/4 of the area gets 3/4 of the points to within one
    assert abs(on_wall.sum() - 3072) <= 1
    floor, wall = rows[~on_wall], rows[on_wall]
    assert np.all(np.abs(floor[:, 0, 2]) < 1e-6) and np.all(floor[:, 0, 0] + floor[:, 0, 1] <= 1.0 + 1e-5)
    assert np.all(wall[:, 0, 0] >= -1e-6) and np.all(wall[:, 0, 0] / 3 + wall[:, 0, 2] <= 1.0 + 1e-5)
    assert np.allclose(np.abs(floor[:, 1, :3]), (0, 0, 1)) and np.allclose(np.abs(wall[:, 1, :3]), (0, 1, 0))
    assert np.allclose(floor[:, 2, :3], COLOURS[0]) and np.allclose(wall[:, 2, :3], COLOURS[1])
    assert np.allclose(rows[:, 1, 3], 2.0 / 4096) and np.all(rows[:, 0, 3] == 1.0)
    # uniform within a triangle: the floor's points' mean is its centroid
    assert np.allclose(floor[:, 0, :2].mean(axis=0), (1 / 3, 1 / 3), atol=0.02)


def test_each_pattern_draws_other_points_and_the_sides_come_from_the_mesh(glc):
    scene = two_triangles()
    first, second = drawn(glc, scene, 256, 1), drawn(glc, scene, 256, 2)
    assert not np.allclose(first[:, 0, :3], second[:, 0, :3])
    assert np.all(first[:, 2, 3] == FRONT | BACK)  # no sides known: every side open
    shut = drawn(glc, scene, 256, 1, sides=np.array([FRONT, BACK], dtype=np.uint8))
    on_wall = np.abs(shut[:, 0, 1] - 2.0) < 1e-5
    assert np.all(shut[~on_wall, 2, 3] == FRONT) and np.all(shut[on_wall, 2, 3] == BACK)
