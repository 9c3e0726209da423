"""The artist-scene suite (demo/artist/) builds what it promises, renders with our
engine, and `bench --artist` runs end to end on a tiny scene. The scenes lit by their
world alone are expected to fail our render until the renderer lights with the world."""
import json
import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview import demo  # noqa: E402
from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.addon.render_scene import scene_to_render  # noqa: E402
from lpv_preview.addon.world import WorldEvaluation  # noqa: E402
from lpv_preview.gpu.pipeline import render_once  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

SIZE = (64, 36)


def lamps(scene):
    return [obj for obj in scene.objects if obj.type == "LIGHT"]


def world_nodes(scene, kind):
    return [node for node in scene.world.node_tree.nodes if node.bl_idname == kind]


@pytest.mark.parametrize("name", demo.ARTIST_SCENES)
def test_scene_renders_with_our_engine(glc, name):
    scene = demo.build(name, resolution=SIZE)
    assert (scene.render.resolution_x, scene.render.resolution_y) == SIZE and scene.camera is not None
    frame = render_once(scene_to_render(scene, SIZE), Settings(width=SIZE[0], height=SIZE[1], rsm_resolution=64,
                                                               vpls_per_light=64), passes=("combined",))
    combined = frame.passes["combined"]
    assert combined.shape[:2] == SIZE[::-1] and np.all(np.isfinite(combined))


def test_default_cube_is_blenders_startup_scene():
    scene = demo.build("default_cube", resolution=SIZE)
    assert sorted((obj.name, obj.type) for obj in scene.objects) == [
        ("Camera", "CAMERA"), ("Cube", "MESH"), ("Light", "LIGHT")]
    assert scene.objects["Cube"].active_material.name == "Material"
    assert world_nodes(scene, "ShaderNodeBackground") and not world_nodes(scene, "ShaderNodeTexSky")


def test_hdri_product_has_its_world_and_objects():
    scene = demo.build("hdri_product", resolution=SIZE)
    (environment,) = world_nodes(scene, "ShaderNodeTexEnvironment")
    assert environment.image.size[0] > 0 and environment.image.has_data  # the size loads it
    assert environment.inputs["Vector"].is_linked and world_nodes(scene, "ShaderNodeMapping")
    assert not lamps(scene)
    chrome = scene.objects["Chrome sphere"].active_material.node_tree.nodes["Principled BSDF"].inputs
    assert chrome["Metallic"].default_value == 1.0 and chrome["Roughness"].default_value == pytest.approx(0.05)
    bar = scene.objects["Light bar"].active_material.node_tree.nodes["Principled BSDF"].inputs
    assert bar["Emission Strength"].default_value > 0
    card = scene.objects["Hidden card"].active_material.node_tree.nodes["Principled BSDF"].inputs
    assert card["Alpha"].default_value == 0.0
    floor_images = [node.image for node in scene.objects["Floor"].active_material.node_tree.nodes
                    if node.bl_idname == "ShaderNodeTexImage"]
    assert floor_images and floor_images[0].packed_file is not None
    assert {m.type for m in scene.objects["Product"].modifiers} == {"BEVEL", "SUBSURF"}


@pytest.mark.parametrize("name, elevation", [("sky_interior", 35.0), ("noon_exterior", 70.0)])
def test_sky_scenes_have_a_sky_texture(name, elevation):
    scene = demo.build(name, resolution=SIZE)
    (sky,) = world_nodes(scene, "ShaderNodeTexSky")
    assert sky.sky_type == "MULTIPLE_SCATTERING" and math.degrees(sky.sun_elevation) == pytest.approx(elevation)
    if name == "sky_interior":
        assert not lamps(scene)
        assert any(m.type == "BOOLEAN" for m in scene.objects["Window wall"].modifiers)
    else:
        (sun,) = lamps(scene)
        assert sun.data.type == "SUN"
        # a sun lamp shines along its -Z axis: its +Z points to the sky's sun (as Cycles places it)
        towards = WorldEvaluation().sky_model(sky).sun_direction
        np.testing.assert_allclose(np.array(sun.matrix_world.col[2].xyz), towards, atol=1e-5)


def test_world_only_is_lit_by_its_world_alone():
    scene = demo.build("world_only", resolution=SIZE)
    assert not lamps(scene) and not world_nodes(scene, "ShaderNodeTexSky")
    assert max(scene.world.node_tree.nodes["Background"].inputs["Color"].default_value[:3]) > 0.1
    for obj in scene.objects:
        if obj.type == "MESH":
            assert obj.active_material.node_tree.nodes["Principled BSDF"].inputs["Emission Strength"].default_value == 0


def test_tiny_artist_bench_writes_finite_figures(tmp_path):
    out = tmp_path / "artist"
    argv = ["bench", "--artist", "--scenes", "default_cube", "--samples", "8", "--width", "32", "--eevee-samples", "1",
            "--rsm-resolution", "32", "--vpls-per-light", "16", "--converge-sets", "2", "--out", str(out)]
    assert main(argv) == 0
    report = json.loads((out / "artist.json").read_text())
    (scene,) = report["scenes"]
    assert scene["name"] == "default_cube" and report["resolution"] == [32, 18] and report["cycles_samples"] == 8
    assert report["converge_sets"] == 2 and scene["renders"]["ours_one_frame"]["settings"]["converge_sets"] == 1
    for render, row in scene["renders"].items():
        for figure, value in row["figures"].items():
            assert value is not None and math.isfinite(value), (render, figure)
    assert set(scene["goals"]) == {"one_frame_mean", "one_frame_flip_below_eevee", "converged_flip_half_eevee",
                                   "converged_seconds", "world_ms"}
    table = (out / "artist.md").read_text()
    assert "### default_cube" in table and "python -m lpv_preview bench --artist" in table
