"""The light grid's cut (gpu/light_grid.py NEAR_SIZES): a cell centre takes far emitters
in wide clusters and near ones in the finest, each emitter once, so its light is the one
every finest cluster gives. Real GL through llvmpipe."""
import numpy as np
import pytest

from lpv_preview.bench.synthetic import particle_room, room_scene
from lpv_preview.gpu import light_grid
from lpv_preview.gpu.metrics import image_errors
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.settings import Settings

SMALL = dict(width=64, height=48, lpv_resolution=16, bounces=1, emitter_bounce_samples=64)


def light(scene, near_sizes, monkeypatch, pass_name):
    monkeypatch.setattr(light_grid, "NEAR_SIZES", near_sizes)
    return render_once(scene, Settings(**SMALL), passes=(pass_name,)).passes[pass_name]


@pytest.mark.parametrize("scene, pass_name", [(room_scene(4), "indirect"), (particle_room(2000), "direct")],
                         ids=["a lamp's bounce", "particles' shadows"])
def test_the_cut_gives_the_light_of_every_finest_cluster(scene, pass_name, monkeypatch):
    cut = light(scene, light_grid.NEAR_SIZES, monkeypatch, pass_name)
    finest = light(scene, 1e6, monkeypatch, pass_name)  # every cluster near: the finest alone
    widest = light(scene, 0.0, monkeypatch, pass_name)  # every cluster far: the widest alone
    errors = image_errors(cut, finest)
    print(f"\n{pass_name}: cut / finest {errors['mean'] / errors['reference_mean']:.4f}, {errors['psnr']:.1f} dB; "
          f"widest / finest {widest.mean() / finest.mean():.4f}, {image_errors(widest, finest)['psnr']:.1f} dB")
    assert finest.mean() > 0
    assert abs(errors["mean"] / errors["reference_mean"] - 1) < 0.015  # each emitter counted once
    assert errors["psnr"] > 40
    assert np.isfinite(widest).all() and widest.mean() > 0  # the widest octave holds every emitter too
