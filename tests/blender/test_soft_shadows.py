"""Soft shadows from a light's size (issue 31): the penumbra of a plate's straight edge
(demo/shadow_edge.py) widens with the light's size as the light's geometry says, and a
light of no size keeps a hard edge."""
import functools
import math

import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.extract import extract_scene  # noqa: E402
from lpv_preview.demo import shadow_edge  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

WIDTH, HEIGHT, SETS = 128, 8, 8
RSM_RESOLUTION = 256


@functools.lru_cache(maxsize=None)
def penumbra(kind, size, shape="SQUARE"):
    """The 10-90 % width of the edge's penumbra in metres, and the edge profile (rendered
    once per light in a test process)."""
    shadow_edge.build(kind, size, WIDTH, HEIGHT, shape)
    # the shadows are direct light: one bounce of few VPLs over a coarse grid, from maps
    # of RSM_RESOLUTION (each set assigns their texels to its VPLs' cells again)
    pipeline = Pipeline(Settings(width=WIDTH, height=HEIGHT, converge_sets=SETS, bounces=1, vpls_per_light=64,
                                 lpv_resolution=8, rsm_resolution=RSM_RESOLUTION))
    try:
        images = []
        for shown in (True, False):
            shadow_edge.show_plate(shown)
            scene = extract_scene(bpy.context.evaluated_depsgraph_get())
            images.append(pipeline.render_converged(scene, passes=("direct",)).passes["direct"])
    finally:
        pipeline.release()
    profile = shadow_edge.edge_profile(*images)
    return shadow_edge.penumbra_width(profile), profile


def light_spread(size):
    """The full width of a light of `size`'s penumbra on the floor: size x (d - d_b) / d_b."""
    blocker = shadow_edge.LIGHT_HEIGHT - shadow_edge.PLATE_HEIGHT
    return size * (shadow_edge.LIGHT_HEIGHT - blocker) / blocker


def test_the_penumbra_grows_with_an_area_lights_size():
    small, _ = penumbra("AREA", 0.5)
    large, _ = penumbra("AREA", 1.0)
    print(f"\nsquare area light 0.5 m: {small:.3f} m, 1.0 m: {large:.3f} m (10-90 %; a square's ramp: "
          f"{0.8 * light_spread(0.5):.3f}, {0.8 * light_spread(1.0):.3f})")
    assert large > 1.7 * small
    for width, size in ((small, 0.5), (large, 1.0)):  # a square light's edge ramps linearly
        assert width == pytest.approx(0.8 * light_spread(size), rel=0.15)


def test_a_disk_lights_penumbra_follows_its_diameter():
    width, profile = penumbra("AREA", 1.0, shape="DISK")
    square, _ = penumbra("AREA", 1.0)
    print(f"\ndisk area light 1.0 m: {width:.3f} m, square {square:.3f} m")
    assert width < square  # a disk's light thins toward its edges: a steeper middle
    assert profile[:WIDTH // 4].max() < 0.01 and profile[-WIDTH // 4:].min() > 0.99


@pytest.mark.parametrize("kind", ["POINT", "SPOT", "SUN", "AREA"])
def test_a_light_of_no_size_keeps_a_hard_edge(kind):
    width, profile = penumbra(kind, 0.0)
    print(f"\n{kind} of no size: {width * 1000:.1f} mm")
    assert width < 3 * shadow_edge.VIEW_WIDTH / WIDTH
    assert profile[:WIDTH // 2 - 4].max() < 0.01 and profile[WIDTH // 2 + 4:].min() > 0.99


def test_a_sphere_lights_radius_softens_its_shadow():
    width, _ = penumbra("POINT", 0.25)
    disc = 1.374 * light_spread(0.25)  # a uniform disc's 10-90 % across a straight edge: 1.374 radii
    print(f"\npoint light of radius 0.25 m: {width:.3f} m (a disc's: {disc:.3f} m)")
    assert width == pytest.approx(disc, rel=0.15)
