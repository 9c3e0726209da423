"""Each later bounce carries the light Cycles' does (issue 32): in the Cornell box the
light the second bounce adds, and the third and fourth together, against what Cycles'
Diffuse Indirect gains from Max Bounces 1 to 2 and 2 to 4, with the default light grid
(VPL gathering draws and lights the same points). Real bpy, Cycles and GL."""
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview import demo  # noqa: E402
from lpv_preview.addon.cycles_reference import render_cycles_passes  # noqa: E402
from lpv_preview.addon.render_scene import scene_to_render  # noqa: E402
from lpv_preview.gpu.pipeline import render_once  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

SIZE = (64, 64)
BOUNCES = (1, 2, 4)


@pytest.fixture(scope="module")
def cornell():
    built = demo.build("cornell")
    cycles = {}
    for bounces in BOUNCES:
        images = render_cycles_passes(built, ("DiffInd", "DiffCol"), samples=64, resolution=SIZE,
                                      max_bounces=bounces)
        cycles[bounces] = float((images["DiffInd"] * images["DiffCol"]).mean())
    return scene_to_render(built, SIZE), cycles


def test_each_later_bounce_carries_the_light_of_cycles(cornell):
    # Measured: the second bounce 0.989 of Cycles', the third and fourth 0.897 (VPL
    # gathering: 0.975 and 0.892; with the points drawn on the CPU, other random numbers,
    # 0.975 and 0.888, and 0.974 and 0.905). While the later bounces' points grew r² by their area
    # over pi rather than held it there, and the light grid's later bounces marched its own
    # coarser occupancy, 0.856 and 0.702 (VPL gathering: 0.941 and 0.815).
    scene, cycles = cornell
    ours = {bounces: float(render_once(scene, Settings(width=SIZE[0], height=SIZE[1], bounces=bounces,
                                                       converge_sets=2)).passes["indirect"].mean())
            for bounces in BOUNCES}
    second = (ours[2] - ours[1]) / (cycles[2] - cycles[1])
    later = (ours[4] - ours[2]) / (cycles[4] - cycles[2])
    print(f"\nfirst bounce {ours[1] / cycles[1]:.3f}, second {second:.3f}, third and fourth {later:.3f} "
          "of Cycles'")
    assert 0.9 < second < 1.1
    assert 0.82 < later < 1.1
