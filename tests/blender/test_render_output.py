"""What a render writes of its frame, as Cycles' F12 writes it: a render region (Ctrl-B),
cropped or not, holds the whole frame's pixels there and nothing else, and Film
Transparent makes the background's alpha 0; through F12 and through the command line."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

import lpv_preview  # noqa: E402
from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.addon.engine import ENGINE_ID  # noqa: E402
from lpv_preview.gpu.image_io import read_exr_channels  # noqa: E402

from ..leak_scenes import closed_box  # noqa: E402

SIZE = (64, 48)
BORDER = (0.255, 0.749, 0.4, 0.95)
"""min x, max x, min y, max y as Blender stores them (y from the bottom)."""
REGION = (16, 48 - 45, 47, 48 - 19)
"""BORDER's pixels in a 64 x 48 frame, truncated as Blender does (x0, y0, x1, y1, row 0 at the
top): sky and surfaces."""


@pytest.fixture
def scene():
    """The closed box on its floor, seen from above the horizon: background at the top."""
    scene = closed_box(SIZE).scene
    lpv_preview.register()
    scene.render.engine = ENGINE_ID
    settings = scene.lpv_preview
    settings.rsm_resolution, settings.vpls_per_light, settings.lpv_resolution = 64, 256, 16
    yield scene
    lpv_preview.unregister()


def f12(scene, path):
    """F12 into a 32-bit EXR; its Combined pass as (height, width, 4), top row first."""
    image = scene.render.image_settings
    image.media_type, image.file_format, image.color_depth = "MULTI_LAYER_IMAGE", "OPEN_EXR_MULTILAYER", "32"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    channels = read_exr_channels(path)
    return np.stack([channels[f"ViewLayer.Combined.{c}"] for c in "RGBA"], axis=-1)


def set_border(scene, crop):
    render = scene.render
    render.use_border, render.use_crop_to_border = True, crop
    render.border_min_x, render.border_max_x, render.border_min_y, render.border_max_y = BORDER


def test_f12_of_a_render_region_holds_the_whole_frames_pixels_there(scene, tmp_path):
    whole = f12(scene, tmp_path / "whole.exr")
    x0, y0, x1, y1 = REGION
    set_border(scene, crop=True)
    cropped = f12(scene, tmp_path / "cropped.exr")
    assert cropped.shape == (y1 - y0, x1 - x0, 4)
    np.testing.assert_allclose(cropped, whole[y0:y1, x0:x1], rtol=1e-4, atol=1e-6)
    set_border(scene, crop=False)
    placed = f12(scene, tmp_path / "placed.exr")
    assert placed.shape == whole.shape
    np.testing.assert_allclose(placed[y0:y1, x0:x1], whole[y0:y1, x0:x1], rtol=1e-4, atol=1e-6)
    outside = np.ones(SIZE[::-1], bool)
    outside[y0:y1, x0:x1] = False
    assert np.all(placed[outside] == 0)  # colour and alpha, as Blender leaves what a region does not cover


def test_f12_with_film_transparent_gives_the_background_alpha_0(scene, tmp_path):
    opaque = f12(scene, tmp_path / "opaque.exr")
    scene.render.film_transparent = True
    transparent = f12(scene, tmp_path / "transparent.exr")
    assert np.all(opaque[..., 3] == 1)
    alpha = transparent[..., 3]
    assert set(np.unique(alpha)) == {0.0, 1.0}
    assert alpha[0].mean() == 0 and alpha[-1].mean() == 1  # the sky above, the floor below
    np.testing.assert_allclose(transparent[..., :3], opaque[..., :3], rtol=1e-4, atol=1e-6)
    assert np.all(transparent[alpha == 0][:, :3] == 0)


def test_the_command_line_writes_the_region_with_alpha_as_f12_does(scene, tmp_path):
    set_border(scene, crop=True)
    scene.render.film_transparent = True
    by_f12 = f12(scene, tmp_path / "f12.exr")
    blend = tmp_path / "region.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "out"
    assert main(["render", str(blend), "--out", str(out), "--rsm-resolution", "64", "--vpls-per-light", "256",
                 "--lpv-resolution", "16"]) == 0
    channels = read_exr_channels(out / "passes.exr")
    combined = np.stack([channels[f"combined.{c}"] for c in "RGBA"], axis=-1)
    x0, y0, x1, y1 = REGION
    assert combined.shape == (y1 - y0, x1 - x0, 4)
    np.testing.assert_allclose(combined, by_f12, rtol=1e-4, atol=1e-6)
    assert set(np.unique(combined[..., 3])) == {0.0, 1.0}  # the region holds sky and surfaces
    import OpenImageIO as oiio
    png = oiio.ImageInput.open(str(out / "combined.png"))
    assert (png.spec().width, png.spec().height, png.spec().nchannels) == (x1 - x0, y1 - y0, 4)
    png.close()


def test_a_render_region_narrower_than_a_pixel_is_refused_in_one_sentence(scene, tmp_path, capsys):
    set_border(scene, crop=True)
    scene.render.border_max_x = scene.render.border_min_x + 0.001
    blend = tmp_path / "thin.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    assert main(["render", str(blend), "--out", str(tmp_path / "out")]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "render region is narrower than a pixel" in error[0]
