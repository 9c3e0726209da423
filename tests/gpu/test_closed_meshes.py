"""gpu/closed_meshes.py: a closed mesh with nothing that emits inside it is a solid, shut
on the side of its faces that looks in; one that holds a lamp, a point emitter or another
mesh's emissive face is open on both sides, as is one that lets light through. One that
holds a lamp is a room: that lamp lights only what lies in it, and a side in a room no
light lies in gets none."""
import dataclasses

import numpy as np
import pytest

from lpv_preview.bench.synthetic import box_triangles
from lpv_preview.gpu.closed_meshes import BACK, BACK_ROOM_SHIFT, FRONT, FRONT_ROOM_SHIFT, OPEN, ClosedMeshes, _inside_all
from lpv_preview.gpu.pipeline import Pipeline, render_once
from lpv_preview.gpu.scene import SEEN_BY_CAMERA, SEEN_BY_LIGHTS, Camera, Light, Scene
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
    return ClosedMeshes(scene).sides_and_rooms(scene)[0]


def box_winds_outward():
    box = box_triangles((0, 0, 0), (1, 1, 1))
    return np.einsum("ij,ij->i", box[:, 0], np.cross(box[:, 1], box[:, 2])).sum() > 0


def test_a_closed_box_lit_from_outside_is_shut_on_its_inside():
    outward = FRONT if box_winds_outward() else BACK
    found = sides(floor_and_box())
    assert list(found[:2]) == [OPEN, OPEN]
    assert np.all(found[2:] == outward)
    assert np.all(sides(floor_and_box(reverse=True))[2:] == (FRONT | BACK) ^ outward)


LAMP = Light("POINT", (0.1, 0.2, 0.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0)


def test_a_closed_box_with_a_lamp_inside_is_a_room():
    outside = Light("POINT", (2.0, 0.0, 0.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0)
    inward_shift = BACK_ROOM_SHIFT if box_winds_outward() else FRONT_ROOM_SHIFT
    for reverse in (False, True):
        scene = floor_and_box([SUN, LAMP], reverse=reverse)
        found, rooms = ClosedMeshes(scene).sides_and_rooms(scene)
        assert np.all(found & OPEN == OPEN)  # the sun lights the outside, the lamp the inside
        assert list(found[:2] >> FRONT_ROOM_SHIFT) == [0, 0]  # the floor is outside
        shift = inward_shift if not reverse else BACK_ROOM_SHIFT + FRONT_ROOM_SHIFT - inward_shift
        assert np.all(found[2:] >> shift & 7 == 1) and np.all(found[2:] >> (BACK_ROOM_SHIFT + FRONT_ROOM_SHIFT - shift)
                                                              & 7 == 0)
        assert rooms.room_of(LAMP) == 1 and rooms.room_of(outside) == 0 and rooms.room_of(SUN) == 0
    assert sides(floor_and_box([SUN, outside])) is not None


def test_a_closed_box_that_casts_no_shadow_is_neither_a_solid_nor_a_room():
    # Its ray visibility "Shadow" off: Cycles' light passes through it.
    visibility = np.full(14, SEEN_BY_CAMERA | SEEN_BY_LIGHTS, np.uint8)
    visibility[2:] = SEEN_BY_CAMERA
    assert sides(floor_and_box(visibility=visibility)) is None
    assert sides(floor_and_box([LAMP], visibility=visibility)) is None


def test_a_room_no_light_lies_in_is_dark():
    # The lamp in the box lights nothing outside it, and nothing else lights the outside.
    found = sides(floor_and_box([LAMP]))
    inward = BACK if box_winds_outward() else FRONT
    assert list(found[:2] & OPEN) == [0, 0]
    assert np.all(found[2:] & OPEN == inward)


def test_a_lamp_shut_in_a_closed_box_lights_nothing_outside_it():
    # The box floats 1 cm over the floor: the floor around its foot is within the bias of
    # the lamp's shadow map, and a sun lights it too. With the lamp or without, the floor
    # and the box's outside get the same light.
    settings = Settings(width=48, height=32, rsm_resolution=128, vpls_per_light=256, lpv_resolution=16, bounces=1)
    foot = Camera.look_at((0.9, -0.9, 0.3), (0.5, -0.5, 0.0), fov_y=0.9, aspect=1.5)
    sun_only = render_once(dataclasses.replace(floor_and_box([SUN]), camera=foot), settings).passes["direct"]
    both = render_once(dataclasses.replace(floor_and_box([SUN, LAMP]), camera=foot), settings).passes["direct"]
    assert sun_only.mean() > 0.05
    np.testing.assert_allclose(both, sun_only, rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize("method, bounces", [("light_grid", 1), ("light_grid", 3), ("vpl_gather", 3)])
def test_a_lamp_shut_in_a_closed_box_adds_no_bounced_light_outside_it(method, bounces):
    """Cycles' floor outside a closed box gets the same light with its lamp on or off; ours
    may take at most 0.1 % of the direct light more (issue 32's goal). Before rooms kept
    the grids' light apart the light grid's one bounce added 0.346 % in specks along the
    box's foot."""
    settings = Settings(width=96, height=64, rsm_resolution=128, vpls_per_light=256, lpv_resolution=16,
                        bounces=bounces, indirect_method=method)
    foot = Camera.look_at((0.9, -0.9, 0.3), (0.5, -0.5, 0.0), fov_y=0.9, aspect=1.5)
    passes = ("direct", "indirect")
    sun_only = render_once(dataclasses.replace(floor_and_box([SUN]), camera=foot), settings, passes=passes).passes
    both = render_once(dataclasses.replace(floor_and_box([SUN, LAMP]), camera=foot), settings, passes=passes).passes
    assert sun_only["indirect"].mean() > 0.0
    added = np.clip(both["indirect"] - sun_only["indirect"], 0.0, None).mean() / sun_only["direct"].mean()
    print(f"\n{method}, {bounces} bounce(s): bounced light the lamp in the box adds outside it: "
          f"{100 * added:.3f} % of the direct light")
    assert added < 0.001


def test_a_lights_vpls_and_the_points_it_bounces_onto_carry_their_rooms(glc):
    """The lamp's VPLs lie in the box (room 1), the sun's outside it (room 0); a later
    bounce's point takes the room of the side it faces (shaders/emitter_bounce.comp)."""
    scene = dataclasses.replace(floor_and_box([SUN, LAMP]), camera=Camera.look_at((1.5, -1.5, 1.0), (0, 0, 0.4)))
    settings = Settings(width=48, height=32, rsm_resolution=64, vpls_per_light=64, lpv_resolution=16, bounces=2)
    pipeline = Pipeline(settings, glc)
    try:
        assert pipeline.render(scene, passes=("indirect",)).stats["rooms"] == 1
        rooms = {maps.rsm.light.kind: maps.vpls.read() for maps in pipeline._lights.values()}
        assert set(rooms["POINT"]["room"][rooms["POINT"]["valid"]]) == {1.0}
        assert set(rooms["SUN"]["room"][rooms["SUN"]["valid"]]) == {0.0}
        second = pipeline._indirect.value.generations.made[0]
        rows = np.frombuffer(second.buffer.read(), np.float32).reshape(second.count, 3, 4)
        on_floor = rows[:, 0, 2] < 0.005
        lit = rows[:, 2, :3].max(axis=1) > 0
        assert on_floor.any() and np.all(rows[on_floor, 0, 3] == 1.0)  # room 0, lit or not
        on_box = lit & ~on_floor  # each facing its brighter side: in, the box's room (1); out, room 0
        facing_in = np.einsum("ij,ij->i", rows[:, 1, :3], np.array([0.0, 0.0, 0.51]) - rows[:, 0, :3]) > 0
        assert (on_box & facing_in).any()
        np.testing.assert_array_equal(rows[on_box, 0, 3], np.where(facing_in[on_box], 2.0, 1.0))
    finally:
        pipeline.release()


@pytest.mark.parametrize("method", ["light_grid", "vpl_gather"])
def test_a_glowing_floor_outside_adds_no_light_inside_a_closed_box(method):
    """An emissive surface's samples lie in the rooms its sides look into: the floor's
    glow lights the box's outside, not its inside, directly or bounced."""
    settings = Settings(width=64, height=48, rsm_resolution=128, vpls_per_light=256, lpv_resolution=16, bounces=3,
                        indirect_method=method)
    inside = Camera.look_at((0.3, -0.35, 0.8), (-0.3, 0.3, 0.05), fov_y=1.4, aspect=4 / 3)
    glowing = np.zeros((14, 3), np.float32)
    glowing[:2] = 2.0
    passes = ("direct", "indirect")
    lamp_only = render_once(dataclasses.replace(floor_and_box([LAMP]), camera=inside), settings, passes=passes).passes
    both = render_once(dataclasses.replace(floor_and_box([LAMP], emission=glowing), camera=inside), settings,
                       passes=passes).passes
    added = sum(np.abs(both[name] - lamp_only[name]).mean() for name in passes) / lamp_only["direct"].mean()
    print(f"\n{method}: the glowing floor outside changes the box's light by {100 * added:.3f} % of its direct light")
    assert added < 0.001


@pytest.mark.xfail(strict=True, reason="a bounced point faces its brighter side alone (shaders/emitter_bounce.comp): "
                                      "the sunlit walls bounce nothing into the room (docs/method.md, \"The emitters' "
                                      "bounce\")")
def test_a_wall_lit_on_both_sides_bounces_both_sides_light():
    """A closed room (a 4 x 4 x 2.5 m box) with a lamp, a sun outside: the sun lights the
    walls' outside, and the room's bounced light should stay what it is without the sun.
    Measured: -2.82 % of the direct light (8 sets). Drawing each point's side in proportion
    to each side's light made it -0.47 %, but one set's noise then rose to 0.13-0.38 % of
    the direct light in the leak tests above."""
    room = box_triangles((-2.0, -2.0, 0.01), (2.0, 2.0, 2.5))
    floor = np.array([[(-5, -5, 0), (5, -5, 0), (5, 5, 0)], [(-5, -5, 0), (5, 5, 0), (-5, 5, 0)]], dtype=np.float64)
    triangles = np.concatenate([floor, room])
    lamp = Light("POINT", (-1.2, -1.2, 1.5), (0, 0, -1), (0, 1, 0), (0.2, 0.5, 1.0), 100.0)
    inside = Camera.look_at((-1.7, -1.7, 1.8), (0.4, 0.4, 0.3), fov_y=1.2, aspect=4 / 3)
    settings = Settings(width=64, height=48, rsm_resolution=128, vpls_per_light=256, lpv_resolution=16, bounces=3,
                        converge_sets=8)

    def frame(lights):
        scene = Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.6), lights, inside,
                      solids=np.array([-1, -1] + [0] * 12, np.int32)).sanitize()
        return render_once(scene, settings, passes=("direct", "indirect")).passes

    lamp_only, both = frame([lamp]), frame([SUN, lamp])
    change = (both["indirect"].mean() - lamp_only["indirect"].mean()) / lamp_only["direct"].mean()
    print(f"\nthe sun outside changes the room's bounced light by {100 * change:.3f} % of its direct light")
    assert abs(change) < 0.01


def test_the_light_grid_cells_take_the_room_their_centre_lies_in(glc):
    """shaders/light_grid_rooms.comp's parity on the GPU against gpu/closed_meshes.py's on
    the host, at every cell a lookup can read (1 + its room; 0: not read)."""
    scene = dataclasses.replace(floor_and_box([SUN, LAMP]), camera=Camera.look_at((1.5, -1.5, 1.0), (0, 0, 0.4)))
    settings = Settings(width=48, height=32, rsm_resolution=64, vpls_per_light=64, lpv_resolution=16, bounces=1)
    pipeline = Pipeline(settings, glc)
    try:
        pipeline.render(scene, passes=("indirect",))
        indirect = pipeline._indirect.value
        grid = indirect.volumes[0]
        assert indirect.cell_rooms() is grid.receiving
        n = grid.grids[0].size
        marks = np.frombuffer(grid.receiving.read(), np.uint8).reshape(len(grid.grids), n, n, n)
        box = scene.triangles[2:].astype(np.float64)
        inside_cells = 0
        for layer, g in enumerate(grid.grids):
            z, y, x = np.nonzero(marks[layer])
            centres = np.asarray(g.origin) + (np.stack([x, y, z], axis=1) + 0.5) * g.cell_size
            expected = 1 + _inside_all(centres, box).astype(np.uint8)
            np.testing.assert_array_equal(marks[layer][z, y, x], expected)
            inside_cells += int(np.count_nonzero(expected == 2))
        assert inside_cells > 0
    finally:
        pipeline.release()


@pytest.mark.parametrize("method", ["light_grid", "vpl_gather"])
def test_a_sun_outside_adds_no_bounced_light_inside_a_closed_box(method):
    """The other way: inside the box the lamp's light alone, the sun on or off."""
    settings = Settings(width=64, height=48, rsm_resolution=128, vpls_per_light=256, lpv_resolution=16, bounces=3,
                        indirect_method=method)
    inside = Camera.look_at((0.3, -0.35, 0.8), (-0.3, 0.3, 0.05), fov_y=1.4, aspect=4 / 3)
    passes = ("direct", "indirect")
    lamp_only = render_once(dataclasses.replace(floor_and_box([LAMP]), camera=inside), settings, passes=passes).passes
    both = render_once(dataclasses.replace(floor_and_box([SUN, LAMP]), camera=inside), settings, passes=passes).passes
    assert lamp_only["indirect"].mean() > 0.0
    added = np.abs(both["indirect"] - lamp_only["indirect"]).mean() / lamp_only["direct"].mean()
    print(f"\n{method}: the sun outside changes the box's bounced light by {100 * added:.3f} % of its direct light")
    assert added < 0.001


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


def test_a_colour_edit_keeps_the_closed_meshes_and_new_emission_sorts_them_again(glc):
    scene = dataclasses.replace(floor_and_box([SUN, LAMP]), camera=Camera.look_at((1.5, -1.5, 1.0), (0, 0, 0.4)))
    recoloured = dataclasses.replace(scene, albedo=scene.albedo * np.float32(0.5), _content_keys=None)
    glowing = np.zeros((len(scene.triangles), 3), np.float32)
    glowing[0] = 1.0
    lit = dataclasses.replace(scene, emission=glowing, _content_keys=None)
    assert recoloured.geometry_key() != scene.geometry_key()
    assert recoloured.enclosure_key() == scene.enclosure_key()
    assert lit.enclosure_key() != scene.enclosure_key()
    brighter = dataclasses.replace(lit, emission=lit.emission * np.float32(3.0), _content_keys=None)
    assert brighter.enclosure_key() == lit.enclosure_key() and brighter.geometry_key() != lit.geometry_key()
    pipeline = Pipeline(Settings(width=32, height=24, rsm_resolution=64, vpls_per_light=64, lpv_resolution=8), glc)
    try:
        pipeline.render(scene, passes=("combined",))
        closed = pipeline._closed_meshes.value
        pipeline.render(recoloured, passes=("combined",))
        assert pipeline._closed_meshes.value is closed
        pipeline.render(lit, passes=("combined",))
        assert pipeline._closed_meshes.value is not closed
    finally:
        pipeline.release()
