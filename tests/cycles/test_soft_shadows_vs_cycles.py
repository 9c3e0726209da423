"""A 15 degree sun's penumbra against Cycles' (issue 31): the plate's edge of
demo/shadow_edge.py, its 10-90 % width in our direct light and in Cycles' Diffuse Direct,
each the shadowed image over the unshadowed one."""
import math

import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import render_cycles_passes  # noqa: E402
from lpv_preview.addon.extract import extract_scene  # noqa: E402
from lpv_preview.demo import shadow_edge  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

WIDTH, HEIGHT, SETS, SAMPLES = 128, 8, 8, 256


def widths(kind, size):
    """(ours, Cycles') 10-90 % penumbra widths in metres."""
    shadow_edge.build(kind, size, WIDTH, HEIGHT)
    pipeline = Pipeline(Settings(width=WIDTH, height=HEIGHT, converge_sets=SETS))
    ours, cycles = [], []
    try:
        for shown in (True, False):
            shadow_edge.show_plate(shown)
            scene = extract_scene(bpy.context.evaluated_depsgraph_get())
            ours.append(pipeline.render_converged(scene, passes=("direct",)).passes["direct"])
            cycles.append(render_cycles_passes(bpy.context.scene, passes=("DiffDir",), samples=SAMPLES,
                                               pixel_filter_width=0.01, max_bounces=0)["DiffDir"])
    finally:
        pipeline.release()
    return (shadow_edge.penumbra_width(shadow_edge.edge_profile(*ours)),
            shadow_edge.penumbra_width(shadow_edge.edge_profile(*cycles)))


def test_a_15_degree_suns_penumbra_is_within_a_quarter_of_cycles():
    ours, cycles = widths("SUN", math.radians(15.0))
    print(f"\n15 degree sun: ours {ours * 100:.1f} cm, Cycles {cycles * 100:.1f} cm ({ours / cycles - 1:+.1%})")
    assert ours == pytest.approx(cycles, rel=0.25)
