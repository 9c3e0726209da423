"""The extension zip: built by scripts/build_extension.py with Blender's own builder,
installed into a fresh Blender user folder through the extensions API, enabled, and an
F12 render of the Cornell box through the installed copy writes our passes."""
import json
import os
import subprocess
import sys
import textwrap
import tomllib
import zipfile

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview import demo  # noqa: E402
from lpv_preview.gpu.image_io import read_exr_channels  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

INSTALL_AND_RENDER = """
import json, os, sys
import bpy
zip_path, blend, exr = sys.argv[-3:]
report = {}
report["install"] = sorted(bpy.ops.extensions.package_install_files(
    filepath=zip_path, repo="user_default", enable_on_install=True))
report["enabled"] = sorted(name for name in bpy.context.preferences.addons.keys() if "lpv_preview" in name)
bpy.ops.wm.open_mainfile(filepath=blend)
scene = bpy.context.scene
scene.render.engine = "LPV_PREVIEW"
report["engine"] = scene.render.engine
settings = scene.lpv_preview
settings.rsm_resolution, settings.vpls_per_light, settings.lpv_resolution = 64, 256, 16
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 32, 32, 100
image = scene.render.image_settings
image.media_type, image.file_format, image.color_depth = "MULTI_LAYER_IMAGE", "OPEN_EXR_MULTILAYER", "32"
scene.render.filepath = exr
bpy.ops.render.render(write_still=True)
import moderngl
report["moderngl"] = moderngl.__file__
report["engine_module"] = sys.modules["bl_ext.user_default.lpv_preview"].__file__
report["cache"] = sys.modules["bl_ext.user_default.lpv_preview.addon.cycles_reference"].default_cache_folder()
report["empty_cache"] = sorted(bpy.ops.lpv_preview.empty_cycles_cache())
import importlib, pkgutil
package = sys.modules["bl_ext.user_default.lpv_preview"]
report["unimportable"] = []
for module in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
    try:
        importlib.import_module(module.name)
    except Exception as error:
        report["unimportable"].append(f"{module.name}: {error!r}")
print("REPORT " + json.dumps(report))
"""


@pytest.fixture(scope="module")
def extension_zip(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    result = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "build_extension.py"), "--out", str(out)],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    return result.stdout.strip().splitlines()[-1]


PLATFORM_TAGS = {"linux-x64": "manylinux", "windows-x64": "win_amd64"}
"""The platforms with OpenGL 4.5 and compute shaders (Apple's OpenGL stops at 4.1: no
macOS) and the platform tag of their wheels."""


def test_the_zip_lists_and_bundles_only_the_platforms_it_runs_on(extension_zip):
    archive = zipfile.ZipFile(extension_zip)
    names = archive.namelist()
    assert tomllib.loads(archive.read("blender_manifest.toml").decode())["platforms"] == list(PLATFORM_TAGS)
    wheels = sorted(name.split("/")[-1] for name in names if name.endswith(".whl"))
    for platform, tag in PLATFORM_TAGS.items():
        bundled = sorted(wheel.split("-")[0] for wheel in wheels if tag in wheel)
        assert bundled == ["flip_evaluator", "glcontext", "moderngl"], (platform, wheels)
    assert len(wheels) == 3 * len(PLATFORM_TAGS), wheels
    assert "gpu/shaders/warp.comp" in names
    assert not any(name.startswith(("tests/", ".venv/", ".git/", "bench/", "cli/", "docs/", ".hypothesis/"))
                   for name in names)
    assert "__main__.py" not in names  # the command line needs bench/, which the zip leaves out


def test_the_installed_extension_renders_f12_with_our_passes(extension_zip, tmp_path):
    demo.build("cornell")
    blend = tmp_path / "cornell.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    script = tmp_path / "install_and_render.py"
    script.write_text(textwrap.dedent(INSTALL_AND_RENDER))
    user = tmp_path / "blender_user"
    exr = tmp_path / "f12.exr"
    environment = {**{k: v for k, v in os.environ.items() if k != "LPV_PREVIEW_CACHE"},
                   "BLENDER_USER_RESOURCES": str(user)}
    result = subprocess.run([sys.executable, str(script), extension_zip, str(blend), str(exr)],
                            capture_output=True, text=True, env=environment, timeout=600)
    lines = [line for line in result.stdout.splitlines() if line.startswith("REPORT ")]
    assert lines, result.stdout + result.stderr
    report = json.loads(lines[-1][len("REPORT "):])
    assert report["install"] == ["FINISHED"] and report["enabled"] == ["bl_ext.user_default.lpv_preview"]
    assert report["engine"] == "LPV_PREVIEW"
    assert report["engine_module"].startswith(str(user))
    # The extension keeps its Cycles references in its own user folder, as the platform asks.
    assert report["cache"] == str(user / "extensions" / ".user" / "user_default" / "lpv_preview" / "cycles")
    assert report["empty_cache"] == ["FINISHED"]
    assert report["unimportable"] == []  # every module the zip keeps runs without what it leaves out
    installed_wheels = user / "extensions" / ".local" / "lib" / "python3.11" / "site-packages"
    assert all((installed_wheels / name).is_dir() for name in ("moderngl", "glcontext", "flip_evaluator"))
    channels = read_exr_channels(exr)
    for name in ("Combined", "Direct", "Indirect"):
        for c in "RGB":
            values = channels[f"ViewLayer.{name}.{c}"]
            assert values.shape == (32, 32) and np.all(np.isfinite(values))
    assert channels["ViewLayer.Indirect.R"].mean() > 0
