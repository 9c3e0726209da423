"""A render of more than one VPL set gathers them at the finer grids of
converged_lpv_resolution; one set, another indirect method or the automatic setting on a
software rasterizer keep lpv_resolution."""
from lpv_preview.bench.synthetic import room_scene
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.settings import Settings

SMALL = Settings(width=32, height=24, rsm_resolution=64, vpls_per_light=128, lpv_resolution=8)


def test_a_converged_render_gathers_its_sets_at_the_finer_grids(glc):
    scene = room_scene(4)
    one = render_once(scene, SMALL.with_changes(converged_lpv_resolution=12), glc)
    both = render_once(scene, SMALL.with_changes(converged_lpv_resolution=12, converge_sets=2), glc)
    assert one.stats["lpv_resolution"] == 8 and (both.stats["lpv_resolution"], both.stats["vpl_sets"]) == (12, 2)
    lpv = render_once(scene, SMALL.with_changes(converged_lpv_resolution=12, converge_sets=2, indirect_method="lpv"),
                      glc)
    assert lpv.stats["lpv_resolution"] == 8  # an LPV's propagation steps are counted in its cells


def test_the_automatic_resolution_is_32_on_a_gpu_and_the_coarser_one_in_software():
    assert Settings().refined(software=False).lpv_resolution == 32
    assert Settings().refined(software=True) == Settings()
    assert Settings(lpv_resolution=64).refined(software=False).lpv_resolution == 64  # never coarser
