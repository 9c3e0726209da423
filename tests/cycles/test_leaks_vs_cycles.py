"""No leaks: the light grid's indirect light against Cycles' one bounce in the scenes of
tests/leak_scenes.py.

Light in a closed box stays in it, a wall thinner than a cell keeps the room behind it at
Cycles' level, a lone plane does not light itself, a huge plane near or far does not
make the cells around the room the camera sees coarse, and a scene a thousand times
smaller or a hundred thousand times larger gives the same picture with cells scaled
alike. Cheap settings (64 x 48, 16³ cells, 1024 VPLs, Cycles 32 samples); the bounds
have a margin over what these settings measured (in each test's comment) and the LPV
fails most of them (scripts/leak_figures.py prints both methods' figures).
"""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import cycles_reference  # noqa: E402
from lpv_preview.addon.render_scene import scene_to_render  # noqa: E402
from lpv_preview.gpu.metrics import image_errors, psnr  # noqa: E402
from lpv_preview.gpu.pipeline import render_once  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

from ..leak_scenes import BUILDERS, unblocked_scene  # noqa: E402

SIZE = (64, 48)
SAMPLES = 32
SETTINGS = Settings(width=SIZE[0], height=SIZE[1], rsm_resolution=256, vpls_per_light=1024, lpv_resolution=16,
                    indirect_method="light_grid", bounces=1)  # against Cycles' one bounce


class Measured:
    """One scene's Cycles reference and our frame, and the direct light of the view
    without its occluders (None where it has none)."""

    def __init__(self, name):
        built = BUILDERS[name](SIZE)
        self.frame = render_once(scene_to_render(built.scene), SETTINGS)
        self.reference = cycles_reference(built.scene, "one_bounce", SAMPLES)
        unblocked = unblocked_scene(built)
        self.unblocked_direct = None if unblocked is None else render_once(unblocked, SETTINGS).passes["direct"]

    @property
    def indirect(self):
        return self.frame.passes["indirect"]

    @property
    def direct(self):
        return self.frame.passes["direct"]

    def errors(self):
        return image_errors(self.indirect, self.reference.indirect)


@pytest.fixture(scope="module")
def measured():
    """Each scene measured once, when a test first asks for it."""
    cache = {}

    def measure(name):
        if name not in cache:
            cache[name] = Measured(name)
        return cache[name]
    return measure


def test_light_in_a_closed_box_stays_in_it(measured):
    # Measured: outside exactly 0 against 0.133 without the box (the box is a room, and
    # nothing lights the room outside it, gpu/closed_meshes.py; 0.02 % before, 0.82 % while
    # a lookup point in the box's wall voxels read the lit cells inside: a line along the
    # box's foot, scripts/leak_figures.py's PNG); the LPV 0.080 (60 %).
    box = measured("closed_box")
    assert box.reference.indirect.mean() < 1e-6 and box.reference.direct.mean() < 1e-6
    without_box = float(box.unblocked_direct.mean())
    share = float(box.indirect.mean()) / without_box
    print(f"\nclosed box: outside indirect {box.indirect.mean():.4g}, {share * 100:.2f} % of the direct light "
          f"without the box ({without_box:.4g})")
    assert without_box > 0.05
    assert share < 0.001


@pytest.mark.parametrize("name", ["camera_in_box", "lamp_in_box_on_floor"])
def test_nothing_is_lit_where_cycles_is_black(measured, name):
    # Measured: the inside of a closed box seen from a camera in it, a sun outside, 0.040 %
    # (two pixels of the floor the box stands on, met by the box's bottom in the depth
    # test; 0.62 % while the G-buffer showed a solid's inside lit, 13.9 % without the
    # occupancy's outer grid); the floor at the foot of a box with a lamp inside, exactly
    # 0 (the box is a room: its lamp lights nothing outside it, and nothing else lights the
    # floor; before, 0.24 % indirect and 0.48 % direct light in dots along the foot, within
    # the shadow map's bias). Both of the light each view gets without the box; the goal
    # (issue 32) is under 0.1 %.
    scene = measured(name)
    assert scene.reference.indirect.mean() < 1e-6 and scene.reference.direct.mean() < 1e-6
    without_box = float(scene.unblocked_direct.mean())
    share = float((scene.indirect + scene.direct).mean()) / without_box
    print(f"\n{name}: {share * 100:.3f} % of the light without the box ({without_box:.4g})")
    assert without_box > 0.05
    assert share < 0.001


def test_a_closed_room_keeps_the_sun_and_the_sky_out(measured):
    # Measured: the sun and the sky change the room's light by 0.003 % of its direct light
    # (0.344 % before the rooms kept bounced light and the world in them); its indirect
    # light 19.9 dB against Cycles' one bounce at 32 samples, ours/Cycles 1.064.
    room = measured("sunlit_cube_room")
    errors = room.errors()
    ratio = errors["mean"] / errors["reference_mean"]
    built = BUILDERS["sunlit_cube_room"](SIZE)
    built.scene.objects["sun"].hide_render = True
    built.scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    lamp_only = render_once(scene_to_render(built.scene), SETTINGS).passes
    changed = sum(float(np.abs(room.frame.passes[name] - lamp_only[name]).mean()) for name in ("direct", "indirect"))
    share = changed / float(lamp_only["direct"].mean())
    print(f"\nsunlit cube room: the sun and the sky change its light by {share * 100:.3f} % of its direct light; "
          f"indirect PSNR {errors['psnr']:.1f} dB, ours/Cycles {ratio:.3f}")
    assert share < 0.001
    assert errors["psnr"] > 17.0
    assert 0.85 < ratio < 1.25


def test_a_lone_plane_does_not_light_itself(measured):
    # Measured: exactly 0; the LPV 18 % of the direct light.
    floor = measured("lone_floor")
    assert floor.reference.indirect.mean() < 1e-6
    share = float(floor.indirect.mean() / floor.direct.mean())
    print(f"\nlone floor: indirect {floor.indirect.mean():.4g}, {share * 100:.2f} % of the direct light")
    assert share < 0.02


def test_a_thin_wall_keeps_the_room_behind_it_at_cycles_level(measured):
    # Measured: 31.5 dB (Cycles' 32 samples are most of the error), ours/Cycles 0.77;
    # the LPV 21 dB, 1.8.
    room = measured("thin_wall")
    errors = room.errors()
    ratio = errors["mean"] / errors["reference_mean"]
    print(f"\nthin wall: indirect PSNR {errors['psnr']:.1f} dB, ours/Cycles {ratio:.3f}")
    assert errors["psnr"] > 25.0
    assert 0.7 < ratio < 1.3


@pytest.mark.parametrize("name, room_size", [("big_ground_house", 6.0), ("room_under_plane", 4.0)])
def test_a_huge_plane_leaves_cells_that_resolve_the_room(measured, name, room_size):
    # Measured: 0.84 m cells at the house (3 levels), 0.35 m in the room; without the
    # camera's placement the 200 m ground and the 1000 m plane would make them 14 m and 70 m.
    # At 32³ they halve.
    cell = measured(name).frame.stats["lpv_cell_size"]
    print(f"\n{name}: finest cell {cell:.3g} m, {room_size / cell:.1f} cells across the {room_size:g} m room")
    assert room_size / cell >= 6.0


@pytest.mark.parametrize("name, least_psnr, ratios", [
    # Measured: 25.0 dB, ours/Cycles 1.006; the LPV 12.5 dB, 0.44.
    ("room_under_plane", 21.0, (0.8, 1.25)),
    pytest.param("big_ground_house", 20.0, (0.67, 1.5), marks=pytest.mark.xfail(
        strict=True, reason="17.0 dB, ours/Cycles 0.65: the ground's broad glow from the sunlit walls comes out "
                            "too weak, and the ground's far VPLs, marched through the coarser levels where the "
                            "ground fills a voxel a metre thick, light the walls too little (18.0 dB, 0.75 before "
                            "the light grid marched every level; 7.7 dB before the sun's VPLs came from a map of "
                            "the region the camera sees)")),
])
def test_a_room_under_a_huge_plane_matches_cycles(measured, name, least_psnr, ratios):
    errors = measured(name).errors()
    ratio = errors["mean"] / errors["reference_mean"]
    print(f"\n{name}: indirect PSNR {errors['psnr']:.1f} dB, ours/Cycles {ratio:.3f}")
    assert errors["psnr"] > least_psnr
    assert ratios[0] < ratio < ratios[1]


@pytest.mark.parametrize("name, scale", [("thin_wall_x0.001", 1e-3), ("thin_wall_x100000", 1e5)])
def test_a_scaled_scene_scales_its_cells_and_keeps_its_picture(measured, name, scale):
    # Measured: cells 2^-10 and 0.93e5 times the unscaled 0.25 m (quarter octaves); indirect
    # 37.2 and 34.0 dB against the unscaled picture, direct 110 dB.
    unscaled, scaled = measured("thin_wall"), measured(name)
    cell_ratio = scaled.frame.stats["lpv_cell_size"] / unscaled.frame.stats["lpv_cell_size"]
    same = psnr(scaled.indirect, unscaled.indirect)
    print(f"\n{name}: cells {cell_ratio:.4g} times the unscaled ones, indirect PSNR {same:.1f} dB against them, "
          f"direct {psnr(scaled.direct, unscaled.direct):.1f} dB")
    assert 2 ** -0.25 < cell_ratio / scale < 2 ** 0.25
    assert same > 30.0
    assert psnr(scaled.direct, unscaled.direct) > 60.0


GATHER = SETTINGS.with_changes(indirect_method="vpl_gather")


def test_the_vpl_gather_keeps_the_room_behind_a_thin_wall_at_cycles_level(measured):
    """Issue 16's per-pixel gather marches through the same occupancy as the light grid.
    Measured: 32.1 dB, ours/Cycles 0.87 (the light grid: 31.8 dB, 0.79)."""
    built = BUILDERS["thin_wall"](SIZE)
    errors = image_errors(render_once(scene_to_render(built.scene), GATHER).passes["indirect"],
                          measured("thin_wall").reference.indirect)
    print(f"\nVPL gather, thin wall: {errors['psnr']:.1f} dB, ours/Cycles {errors['mean'] / errors['reference_mean']:.3f}")
    assert errors["psnr"] > 25.0
    assert 0.7 < errors["mean"] / errors["reference_mean"] < 1.3


def test_the_vpl_gather_keeps_light_in_a_closed_box(measured):
    """Measured: 1.1 % (the light grid 1.0 %; 3.5 % when the gather marched through the
    coarsest level's voxels alone, 0.4 m against the box's 1 m)."""
    built = BUILDERS["closed_box"](SIZE)
    indirect = render_once(scene_to_render(built.scene), GATHER).passes["indirect"]
    leak = indirect.mean() / measured("closed_box").unblocked_direct.mean()
    print(f"\nVPL gather, closed box: leak {leak:.4f}")
    assert leak < 0.025
