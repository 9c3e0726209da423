"""The command line's PNGs through the scene's colour management, as F12 saves them: the
same .blend rendered by F12 into a PNG and by `lpv_preview render` agree to a code value,
for Blender's default view (AgX) and others with a look, an exposure and a gamma; a dark
scene stays dark."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
oiio = pytest.importorskip("OpenImageIO")

import lpv_preview  # noqa: E402
from lpv_preview import demo  # noqa: E402
from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.addon.engine import ENGINE_ID  # noqa: E402
from lpv_preview.addon.view_transform import blender_ocio_config, scene_view_transform  # noqa: E402
from lpv_preview.gpu.colour_management import ViewTransform, display_values, look_process_space  # noqa: E402
from lpv_preview.gpu.errors import LPVError  # noqa: E402

SIZE = (48, 40)


@pytest.fixture
def cornell():
    scene = demo.build("cornell")
    lpv_preview.register()
    scene.render.engine = ENGINE_ID
    scene.render.resolution_x, scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.dither_intensity = 0.0  # F12's dither is noise of about a code value: none, to compare
    settings = scene.lpv_preview
    settings.rsm_resolution, settings.vpls_per_light, settings.lpv_resolution = 64, 256, 16
    yield scene
    lpv_preview.unregister()


def read_png(path):
    image = oiio.ImageInput.open(str(path))
    assert image is not None, oiio.geterror()
    pixels = image.read_image(0, 0, 0, image.spec().nchannels, "uint8")
    image.close()
    return pixels.astype(int)


def f12_and_command_line(scene, tmp_path):
    """The scene saved, rendered by F12 into an 8-bit RGBA PNG, and by the command line
    with the same settings (the flags' are not the scene's): (F12's PNG, our combined.png)."""
    image = scene.render.image_settings
    image.media_type, image.file_format, image.color_mode, image.color_depth = "IMAGE", "PNG", "RGBA", "8"
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    scene.render.filepath = str(tmp_path / "f12.png")
    bpy.ops.render.render(write_still=True)
    assert main(["render", str(blend), "--out", str(tmp_path / "out"), "--rsm-resolution", "64",
                 "--vpls-per-light", "256", "--lpv-resolution", "16"]) == 0
    return read_png(tmp_path / "f12.png"), read_png(tmp_path / "out" / "combined.png")


@pytest.mark.parametrize("view, look, exposure, gamma", [
    ("AgX", "None", 0.0, 1.0),                        # Blender 5.0's default
    ("Standard", "Medium High Contrast", -1.0, 1.0),
    ("AgX", "AgX - Punchy", 0.5, 1.3),
    ("False Color", "None", 0.0, 1.0),
])
def test_the_command_lines_png_is_f12s(cornell, tmp_path, view, look, exposure, gamma):
    settings = cornell.view_settings
    settings.view_transform, settings.look, settings.exposure, settings.gamma = view, look, exposure, gamma
    by_f12, ours = f12_and_command_line(cornell, tmp_path)
    assert by_f12.shape == (SIZE[1], SIZE[0], 4) and ours.shape == (SIZE[1], SIZE[0], 3)
    assert np.all(by_f12[..., 3] == 255)
    difference = np.abs(by_f12[..., :3] - ours)
    assert difference.max() <= 1, (difference.max(), difference.mean())
    assert ours.std() > 10  # a picture, not a flat colour


def test_an_image_with_alpha_keeps_it_straight_as_f12_saves_it(cornell, tmp_path):
    cornell.render.film_transparent = True
    cornell.view_settings.exposure = 1.0
    by_f12, ours = f12_and_command_line(cornell, tmp_path)
    assert ours.shape == (SIZE[1], SIZE[0], 4)
    np.testing.assert_array_equal(ours[..., 3], by_f12[..., 3])
    seen = ours[..., 3] > 0
    assert 0 < seen.mean() < 1  # the box and the sky through its open front
    assert np.abs(by_f12[seen][:, :3] - ours[seen][:, :3]).max() <= 1


def test_a_dark_scene_stays_dark(cornell, tmp_path):
    for light in bpy.data.lights:
        light.energy *= 1e-4
    by_f12, ours = f12_and_command_line(cornell, tmp_path)
    assert np.abs(by_f12[..., :3] - ours).max() <= 1
    assert ours.max() <= 12, ours.max()  # the old auto exposure showed it as a lit room


def test_the_output_override_of_colour_management_is_what_f12_uses(cornell):
    image = cornell.render.image_settings
    image.color_management = "OVERRIDE"
    image.view_settings.view_transform, image.view_settings.exposure = "Filmic", 2.0
    assert scene_view_transform(cornell) == ViewTransform(blender_ocio_config(), "sRGB", "Filmic", "None", 2.0, 1.0)
    image.color_management = "FOLLOW_SCENE"
    assert scene_view_transform(cornell).view == "AgX"


def test_the_default_without_a_config_is_blenders_standard_view(cornell):
    config = blender_ocio_config()
    assert config and config.endswith("config.ocio")
    rng = np.random.default_rng(1)
    linear = np.exp(rng.uniform(-10, 3, (16, 16, 3))).astype(np.float32)
    linear[0, :4] = 0.0
    for exposure, gamma in ((0.0, 1.0), (-1.5, 2.2)):
        plain = display_values(linear, ViewTransform(exposure=exposure, gamma=gamma))
        ocio = display_values(linear, ViewTransform(config, exposure=exposure, gamma=gamma))
        assert np.abs(plain - ocio).max() < 0.2 / 255


def test_looks_views_and_configs_that_are_not_there_fail_in_one_sentence(cornell):
    config, image = blender_ocio_config(), np.full((2, 2, 3), 0.18, np.float32)
    assert look_process_space(config, "AgX - Punchy") == "AgX Log"
    for wrong, words in ((ViewTransform(config, view="Nowhere"), "view 'Nowhere'"),
                         (ViewTransform(config, look="Sepia"), "has no look 'Sepia'"),
                         (ViewTransform(view="AgX"), "needs Blender's colour management config")):
        with pytest.raises(LPVError) as error:
            display_values(image, wrong)
        assert words in str(error.value) and "\n" not in str(error.value), str(error.value)
