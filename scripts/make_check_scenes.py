"""Two scenes of the tests as .blend files, to compare with Cycles and look at:

    .venv/bin/python scripts/make_check_scenes.py OUT_DIR
    .venv/bin/python -m lpv_preview compare OUT_DIR/checker_room.blend --samples 128 --methods wdpm --no-noise-floor
    .venv/bin/python -m lpv_preview compare OUT_DIR/hidden.blend --samples 128 --methods wdpm --no-noise-floor

checker_room: the 8 x 8 checker floor of tests/blender/test_textures.py with a white wall and a
cube, 128²; hidden: the floor with cubes hidden eight ways of
tests/cycles/test_render_visibility.py, 192 x 128.
"""
import os
import sys

import bpy

from lpv_preview.tests.test_render_visibility import hidden_things_scene
from lpv_preview.tests.test_textures import checker_image, floor_scene, image_material

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
scene, _ = floor_scene(lambda: image_material(checker_image(squares=8)))
bpy.ops.mesh.primitive_plane_add(size=4, location=(0, 2, 2), rotation=(1.5708, 0, 0))
bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.6, 0.3, 0.4))
scene.camera.location, scene.camera.rotation_euler = (0, -5, 3.5), (1.1, 0, 0)
scene.render.resolution_x = scene.render.resolution_y = 128
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "checker_room.blend"))
scene = hidden_things_scene()
scene.render.resolution_x, scene.render.resolution_y = 192, 128
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "hidden.blend"))
