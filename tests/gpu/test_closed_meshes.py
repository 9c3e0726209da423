"""gpu/closed_meshes.py: a closed mesh with nothing that emits inside it is a solid, shut
on the side of its faces that looks in; one that holds a lamp, a point emitter or another
mesh's emissive face is a room, open on both sides, as is one that lets light through."""
import dataclasses

import numpy as np

from lpv_preview.bench.synthetic import box_triangles
from lpv_preview.gpu.closed_meshes import BACK, FRONT, OPEN, ClosedMeshes
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.scene import Camera, Light, Scene
from lpv_preview.gpu.settings import Settings

SUN = Light("SUN", (0.0, 0.0, 10.0), (0.3, 0.2, -1.0), (0, 1, 0), (1, 1, 1), 3.0)
CAMERA = Camera.look_at((0.0, -6.0, 2.0), (0.0, 0.0, 0.5))


def floor_and_box(lights=(SUN,), reverse=False, **surfaces):
    """A 10 m floor (an open mesh) and a closed 1 m box standing over it."""
    floor = np.array([[(-5, -5, 0), (5, -5, 0), (5, 5, 0)], [(-5, -5, 0), (5, 5, 0), (-5, 5, 0)]], dtype=np.float64)
    box = box_triangles((-0.5, -0.5, 0.01), (0.5, 0.5, 1.01))
    if reverse:
        box = box[:, ::-1]
    triangles = np.concatenate([floor, box])
    solids = np.array([-1, -1] + [0] * len(box), dtype=np.int32)
    return Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.5), list(lights), CAMERA,
                 solids=solids, **surfaces).sanitize()


def sides(scene):
    return ClosedMeshes(scene).open_sides(scene)


def box_winds_outward():
    box = box_triangles((0, 0, 0), (1, 1, 1))
    return np.einsum("ij,ij->i", box[:, 0], np.cross(box[:, 1], box[:, 2])).sum() > 0


def test_a_closed_box_lit_from_outside_is_shut_on_its_inside():
    outward = FRONT if box_winds_outward() else BACK
    found = sides(floor_and_box())
    assert list(found[:2]) == [OPEN, OPEN]
    assert np.all(found[2:] == outward)
    assert np.all(sides(floor_and_box(reverse=True))[2:] == (FRONT | BACK) ^ outward)


def test_a_closed_box_with_a_lamp_inside_is_a_room():
    lamp = Light("POINT", (0.1, 0.2, 0.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0)
    outside = Light("POINT", (2.0, 0.0, 0.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0)
    assert sides(floor_and_box([SUN, lamp])) is None
    assert sides(floor_and_box([SUN, outside])) is not None


def test_a_closed_box_with_a_point_emitter_inside_is_a_room():
    inside = np.array([[0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1e-4]])
    assert sides(floor_and_box(point_emitters=inside)) is None
    assert sides(floor_and_box(point_emitters=inside + [3.0, 0, 0, 0, 0, 0, 0])) is not None


def test_only_another_meshs_emissive_face_inside_makes_a_room():
    glowing_box = np.zeros((14, 3), np.float32)
    glowing_box[2:] = 5.0
    assert sides(floor_and_box(emission=glowing_box)) is not None  # its own glow is on its surface
    scene = floor_and_box()
    panel = np.array([[(-0.2, -0.2, 0.5), (0.2, -0.2, 0.5), (0.2, 0.2, 0.5)]], dtype=np.float64)
    triangles = np.concatenate([scene.triangles, panel])
    emission = np.zeros((len(triangles), 3), np.float32)
    emission[-1] = 5.0
    with_panel = Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.5), [SUN], CAMERA,
                       solids=np.append(scene.solids, -1), emission=emission).sanitize()
    assert sides(with_panel) is None


def test_a_closed_box_that_lets_light_through_is_open():
    alpha = np.ones(14, np.float32)
    alpha[5] = 0.5
    assert sides(floor_and_box(alpha=alpha)) is None
    transmission = np.zeros((14, 4), np.float32)
    transmission[6] = (1.0, 1.0, 1.0, 0.9)
    assert sides(floor_and_box(transmission=transmission)) is None


def test_a_closed_box_that_loses_a_face_is_open():
    alpha = np.ones(14, np.float32)
    alpha[4] = 0.0  # dropped as clear: the box has a hole
    scene = floor_and_box(alpha=alpha)
    assert scene.solids is None and sides(scene) is None


def test_a_camera_inside_a_solid_sees_it_black_and_one_outside_sees_it_lit():
    # Either winding: the side that looks in is the one the solid's volume says. The box
    # stands 1 cm over the floor, so the inside view sees none of the sunlit floor.
    settings = Settings(width=48, height=32, rsm_resolution=128, vpls_per_light=256, lpv_resolution=16)
    inside = Camera.look_at((0.2, -0.3, 0.5), (0.0, 0.4, 0.4), fov_y=1.6, aspect=1.5)
    for reverse in (False, True):
        seen_in = render_once(dataclasses.replace(floor_and_box(reverse=reverse), camera=inside), settings)
        assert seen_in.passes["combined"].max() == 0.0
        seen_out = render_once(floor_and_box(reverse=reverse), settings)
        box_pixels = seen_out.passes["combined"][8:24, 20:28]  # the box, in the view's middle
        assert box_pixels.mean() > 0.05
