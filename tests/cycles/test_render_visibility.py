"""What the command line, the comparison and the Cycles cache key render is what F12
renders (addon/render_scene.py): object and collection render visibility, collections
excluded from the view layer, instancers hidden in renders, objects hidden only in the
viewport; one scene made here, every entry point checked against F12's statistics."""
import json

import bpy
import numpy as np
import pytest

import lpv_preview
from lpv_preview.__main__ import main
from lpv_preview.addon import frame_stats
from lpv_preview.addon.engine import ENGINE_ID
from lpv_preview.addon.extract import extract_scene
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.gpu.errors import LPVError

from ..blender.test_engine import scene_snapshot
from ..blender.test_extract import cube_object, mesh_object

QUAD = 2  # triangles of a quad
CUBE = 12


def quad(name, size, location, collection):
    s = size / 2
    return mesh_object(name, [(-s, -s, 0), (s, -s, 0), (s, s, 0), (-s, s, 0)], [(0, 1, 2, 3)], location, collection)


def cube(name, location, collection, size=0.4):
    return cube_object(name, location, size, collection)


def hidden_things_scene():
    """A floor, a light and a camera, with one cube each way of hiding or showing it:
    RENDERED counts the triangles F12 draws."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    root = scene.collection
    quad("Floor", 6, (0, 0, 0), root)
    cube("Shown", (-1.5, 0, 0.2), root)
    cube("Hidden in renders", (0, 0, 0.2), root).hide_render = True
    hidden_in_viewport = cube("Hidden in the viewport", (1.5, 0, 0.2), root)
    hidden_in_viewport.hide_viewport = True  # the monitor icon: renders still show it
    eye = cube("Eye icon off", (1.5, 1.5, 0.2), root)
    off_for_renders = bpy.data.collections.new("Off for renders")
    root.children.link(off_for_renders)
    off_for_renders.hide_render = True
    cube("In a collection off for renders", (0, 1.5, 0.2), off_for_renders)
    excluded = bpy.data.collections.new("Excluded")
    root.children.link(excluded)
    cube("In an excluded collection", (-1.5, 1.5, 0.2), excluded)
    scene.view_layers[0].layer_collection.children["Excluded"].exclude = True
    instancer = quad("Instancer", 0.5, (0, -1.5, 0.5), root)  # instances a cube at each of its 4 corners
    instancer.instance_type = "VERTS"
    instancer.show_instancer_for_render = False
    cube("Instanced", (0, 0, 0), root, size=0.1).parent = instancer
    light = bpy.data.objects.new("Light", bpy.data.lights.new("Light", "POINT"))
    light.data.energy = 200
    light.location = (0, 0, 3)
    root.objects.link(light)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0, -7, 5)
    camera.rotation_euler = (0.95, 0, 0)
    root.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 48, 32, 100
    bpy.context.view_layer.update()
    eye.hide_set(True)  # hidden in this view layer's viewport only
    return scene


# Floor, Shown, Hidden in the viewport, Eye icon off, and the instancer's cube: the
# parented cube itself plus its four instances (a VERTS instancer shows its child only as
# instances in renders, but the child object is an instance of itself too).
RENDERED = QUAD + 3 * CUBE


@pytest.fixture
def scene():
    scene = hidden_things_scene()
    lpv_preview.register()
    scene.render.engine = ENGINE_ID
    properties = scene.lpv_preview
    properties.rsm_resolution, properties.vpls_per_light, properties.lpv_resolution = 64, 128, 8
    yield scene
    lpv_preview.unregister()


def f12_triangles(scene):
    frame_stats.forget()
    bpy.ops.render.render()
    return frame_stats.last_stats()["triangles"]


def test_the_scene_to_render_is_what_f12_renders_and_not_the_viewports(scene):
    f12 = f12_triangles(scene)
    instances = 4 * CUBE
    assert f12 == RENDERED + instances
    assert scene_to_render(scene).triangle_count == f12
    viewport = bpy.context.evaluated_depsgraph_get()
    assert extract_scene(viewport).triangle_count != f12  # what the pitfall was


def test_the_command_line_renders_what_f12_renders(scene, tmp_path, capsys):
    f12 = f12_triangles(scene)
    lpv_preview.unregister()  # the command line runs without the add-on registered
    try:
        blend = tmp_path / "hidden.blend"
        bpy.ops.wm.save_as_mainfile(filepath=str(blend))
        argv = ["render", str(blend), "--out", str(tmp_path / "out"), "--rsm-resolution", "64",
                "--vpls-per-light", "128", "--lpv-resolution", "8"]
        assert main(argv) == 0
    finally:
        lpv_preview.register()
    stats = json.loads((tmp_path / "out" / "stats.json").read_text())
    assert stats["triangles"] == f12
    assert bpy.context.scene.render.engine == ENGINE_ID  # given back as the file had it


def test_scene_to_render_gives_the_engine_back_and_changes_nothing_else(scene):
    scene.render.engine = "CYCLES"
    before = scene_snapshot(scene)
    scene_to_render(scene)
    assert scene_snapshot(scene) == before and scene.render.engine == "CYCLES"


def test_a_scene_without_a_camera_is_one_clear_error(scene):
    scene.camera = None
    with pytest.raises(LPVError, match="The scene has no camera"):
        scene_to_render(scene)


def test_the_render_shows_the_viewport_hidden_cubes_and_not_the_render_hidden_ones(scene):
    centres = scene_to_render(scene).triangles.mean(axis=1)
    raised = centres[centres[:, 2] > 0.05]  # the cubes' triangles, not the floor's

    def cube_at(x, y):
        return bool(np.any(np.linalg.norm(raised[:, :2] - (x, y), axis=1) < 0.25))

    assert cube_at(-1.5, 0) and cube_at(1.5, 0) and cube_at(1.5, 1.5)  # shown, viewport-hidden, eye off
    assert not cube_at(0, 0) and not cube_at(0, 1.5) and not cube_at(-1.5, 1.5)  # render-hidden three


def test_ray_visibility_reaches_the_scene_per_triangle(scene):
    from lpv_preview.gpu.scene import SEEN_BY_ALL, SEEN_BY_CAMERA, SEEN_BY_LIGHTS
    root = scene.collection
    cube("Shadow only", (-2.5, -1.5, 0.2), root).visible_camera = False
    cube("Camera only", (2.5, -1.5, 0.2), root).visible_shadow = False
    neither = cube("Neither", (2.5, 1.5, 0.2), root)
    neither.visible_camera = neither.visible_shadow = False
    bpy.data.objects["Instancer"].visible_camera = False  # its instances inherit it, as in Cycles
    rendered = scene_to_render(scene)
    centres = rendered.triangles.mean(axis=1)

    def seen_at(x, y, radius=0.25):
        near = np.linalg.norm(centres[:, :2] - (x, y), axis=1) < radius
        return set(np.unique(rendered.visibility[near & (centres[:, 2] > 0.05)]).tolist())

    assert seen_at(-2.5, -1.5) == {SEEN_BY_LIGHTS} and seen_at(2.5, -1.5) == {SEEN_BY_CAMERA}
    assert seen_at(2.5, 1.5) == set() and seen_at(-1.5, 0) == {SEEN_BY_ALL}
    assert seen_at(0, -1.5, radius=0.5) == {SEEN_BY_LIGHTS}
    assert rendered.triangle_count == RENDERED + 4 * CUBE + 2 * CUBE
