"""The light grid's cut (gpu/light_grid.py NEAR_SIZES): a cell centre of a grid of
CUT_GRID_CELLS takes far emitters in wide clusters and near ones in the finest, each
emitter once, so its light is the one every finest cluster gives. Real GL through llvmpipe."""
from lpv_preview.bench.synthetic import room_scene
from lpv_preview.gpu import context, light_grid
from lpv_preview.gpu.metrics import image_errors
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.settings import Settings

SMALL = dict(width=48, height=36, lpv_resolution=light_grid.CUT_GRID_CELLS, grid_levels=1, grid_phases=1, bounces=1)


def indirect_light(near_sizes, monkeypatch):
    monkeypatch.setattr(light_grid, "NEAR_SIZES", near_sizes)
    return render_once(room_scene(4), Settings(**SMALL), passes=("indirect",)).passes["indirect"]


def test_the_cut_gives_the_light_of_every_finest_cluster(monkeypatch):
    cut = indirect_light(light_grid.NEAR_SIZES, monkeypatch)
    finest = indirect_light(1e6, monkeypatch)  # every cluster near: the finest alone
    widest = indirect_light(0.0, monkeypatch)  # every cluster far: the widest alone
    errors, widest_errors = image_errors(cut, finest), image_errors(widest, finest)
    print(f"\ncut / finest {errors['mean'] / errors['reference_mean']:.4f}, {errors['psnr']:.1f} dB; "
          f"widest / finest {widest.mean() / finest.mean():.4f}, {widest_errors['psnr']:.1f} dB")
    assert finest.mean() > 0
    assert abs(errors["mean"] / errors["reference_mean"] - 1) < 0.015  # each emitter counted once
    assert errors["psnr"] > 38
    assert widest_errors["psnr"] < errors["psnr"] - 5  # the cut is not the widest clusters alone


def test_emitters_clustered_in_rows_of_dispatches_give_the_same_light(monkeypatch):
    """GL promises 65,535 workgroups a dispatch: more emitters than 4,194,240 (a million
    particles' shadows, several times over) go in rows. Rows of 128 here split the VPLs
    and the octaves' clusters into many dispatches, and the light is the same to float
    rounding (two frames of the same settings differ by as much: the gather's threads add
    in no set order)."""
    whole = render_once(room_scene(4), Settings(**SMALL), passes=("indirect",)).passes["indirect"]
    monkeypatch.setattr(context, "ROW_INVOCATIONS", 128)
    rows = render_once(room_scene(4), Settings(**SMALL), passes=("indirect",)).passes["indirect"]
    assert whole.mean() > 0
    assert abs(rows - whole).max() < 1e-6 * whole.max()
