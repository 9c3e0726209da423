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


def test_grids_of_more_cells_than_a_row_of_workgroups_gather_their_light(glc):
    """41³ cells are more than the 65,535 workgroups GL promises along x (one a cell): the
    gather runs them in rows, and lights the room as 32³ does."""
    scene = room_scene(4)
    fine, finer = (render_once(scene, SMALL.with_changes(lpv_resolution=n), glc).passes["indirect"].mean()
                   for n in (32, 41))
    assert fine > 0 and abs(finer / fine - 1) < 0.1, (fine, finer)
