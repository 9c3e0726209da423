"""What the preview cannot render is refused or named (issue 30): a panoramic camera is
refused in one sentence before any work (command line and F12), UDIM tiles are read at
their UV offsets, a missing image renders magenta with a warning, and shaders the preview
does not support are listed as approximated. Scenes made here with bpy."""
import json

import bpy
import numpy as np
import pytest

import lpv_preview
from lpv_preview.__main__ import main
from lpv_preview.addon.engine import ENGINE_ID
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.gpu.errors import LPVError

from .test_textures import floor_scene, image_material, material_with

SMALL = ["--rsm-resolution", "128", "--vpls-per-light", "256", "--lpv-resolution", "8"]


def panoramic(scene):
    camera = scene.camera.data
    camera.type, camera.panorama_type = "PANO", "EQUIRECTANGULAR"
    return scene


def test_the_command_line_refuses_a_panoramic_camera_in_one_line(tmp_path, capsys):
    panoramic(floor_scene(lambda: bpy.data.materials.new("Plain"))[0])
    blend = tmp_path / "panoramic.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    for extra in ([], ["--frames", "1-2"]):
        capsys.readouterr()
        assert main(["render", str(blend), "--out", str(tmp_path / "out"), *extra, *SMALL]) == 2
        lines = capsys.readouterr().err.strip().splitlines()
        assert lines == ["lpv_preview: The camera 'Camera' is panoramic (equirectangular), which LPV Preview cannot "
                         "render; set its Lens Type to Perspective or Orthographic, or render it with Cycles."]
        assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_f12_reports_a_panoramic_camera_in_the_status_bar():
    scene = panoramic(floor_scene(lambda: bpy.data.materials.new("Plain"))[0])
    lpv_preview.register()
    try:
        scene.render.engine = ENGINE_ID
        with pytest.raises(RuntimeError) as error:  # the engine's report, not a silent perspective view
            bpy.ops.render.render()
    finally:
        lpv_preview.unregister()
    message = str(error.value).strip()
    assert message.startswith("Error: The camera 'Camera' is panoramic") and len(message.splitlines()) == 1


def test_orthographic_cameras_still_render():
    scene, _ = floor_scene(lambda: bpy.data.materials.new("Plain"))
    scene.camera.data.type = "ORTHO"
    assert scene_to_render(scene).camera is not None
