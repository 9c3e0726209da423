"""Emissive surfaces light a scene (issue 17, first step): their radiance is extracted
from the material, sampled into point emitters, and gathered by every pixel with
visibility as direct light, against Cycles' direct light. Real bpy, Cycles and GL."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import cycles_reference  # noqa: E402
from lpv_preview.addon.render_scene import scene_to_render  # noqa: E402
from lpv_preview.gpu.errors import LPVError  # noqa: E402
from lpv_preview.gpu.pipeline import render_once  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402
from lpv_preview.gpu.surface_emitters import sample_surface_emitters  # noqa: E402

from ..leak_scenes import box, camera, diffuse, empty_scene, quad, room_shell  # noqa: E402

SIZE = (64, 48)


def emissive(name, colour, strength, node="principled"):
    """A material that emits `colour` × `strength` through a Principled BSDF's emission
    or an Emission shader."""
    material = bpy.data.materials.new(name)
    tree = material.node_tree
    principled = tree.nodes["Principled BSDF"]
    if node == "principled":
        principled.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        principled.inputs["Emission Color"].default_value = (*colour, 1.0)
        principled.inputs["Emission Strength"].default_value = strength
        return material
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*colour, 1.0)
    emission.inputs["Strength"].default_value = strength
    tree.links.new(emission.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    return material


def room_lit_by_a_panel(node="principled"):
    """A closed 4 × 4 × 3 m room with a table, lit only by an emissive 1 m ceiling panel."""
    scene = empty_scene(SIZE)
    walls = diffuse("walls", (0.8, 0.8, 0.8))
    room_shell(2.0, 2.0, 3.0, walls, walls)
    box("Table", (-0.6, -0.4, 0.7), (0.6, 0.4, 0.8), diffuse("table", (0.6, 0.4, 0.3)))
    quad("Panel", 0.5, 2.95, emissive("glow", (1.0, 0.9, 0.7), 10.0, node))
    scene.camera = camera("Inside", (1.7, -1.7, 1.6), (0.0, 0.3, 0.6), lens=20)
    return scene


@pytest.mark.parametrize("node", ["principled", "emission"])
def test_emissive_materials_become_the_radiance_of_their_triangles(node):
    content = scene_to_render(room_lit_by_a_panel(node), SIZE)
    emitting = np.max(content.emission, axis=1) > 0
    assert emitting.sum() == 2  # the panel's two triangles
    np.testing.assert_allclose(content.emission[emitting], [[10.0, 9.0, 7.0]] * 2, rtol=1e-6)
    assert not content.lights


def test_a_scene_lit_only_by_emission_renders_its_direct_light_as_cycles_does():
    built = room_lit_by_a_panel()
    frame = render_once(scene_to_render(built, SIZE), Settings(width=SIZE[0], height=SIZE[1]))
    reference = cycles_reference(built, "one_bounce", 64)
    assert frame.stats["emission_ms"] > 0
    ratio = frame.passes["direct"].mean() / reference.direct.mean()
    assert abs(ratio - 1.0) < 0.02, ratio  # measured: 0.9998
    table = (slice(28, 40), slice(24, 40))  # under the table its shadow, as in Cycles
    assert frame.passes["direct"][table].mean() < 0.5 * frame.passes["direct"].mean()


def test_a_scene_without_lights_or_emission_is_refused_in_one_sentence():
    built = room_lit_by_a_panel()
    bpy.data.objects["Panel"].hide_render = True
    built.world = None  # a world lights a scene too
    with pytest.raises(LPVError, match="no lights; add a point, spot, area or sun light, an emissive material, or "
                                       "a world that emits light"):
        render_once(scene_to_render(built, SIZE), Settings(width=SIZE[0], height=SIZE[1]))


def test_emitters_carry_the_surfaces_power_from_both_sides():
    triangles = np.array([[[0, 0, 0], [2, 0, 0], [0, 1, 0]], [[0, 0, 1], [1, 0, 1], [0, 1, 1]],
                          [[5, 5, 5], [6, 5, 5], [5, 6, 5]]], dtype=np.float32)
    emission = np.array([[1.0, 2.0, 3.0], [4.0, 0.5, 0.0], [0.0, 0.0, 0.0]], dtype=np.float32)
    rows = sample_surface_emitters(triangles, emission, 4096, pattern=3)
    assert rows.shape == (8192, 3, 4)
    areas = np.array([1.0, 0.5])
    power = 2 * np.pi * (emission[:2] * areas[:, None]).sum(axis=0)  # both sides of each triangle
    np.testing.assert_allclose(rows[:, 2, :3].sum(axis=0), power, rtol=0.03)
    assert np.all(rows[:, 0, 2] <= 1.0) and np.all(rows[:, 0, 3] == 1.0)  # none on the black triangle
    np.testing.assert_allclose(np.abs(rows[:, 1, 2]), 1.0)  # normals ±z
    np.testing.assert_array_equal(rows, sample_surface_emitters(triangles, emission, 4096, pattern=3))
    assert not np.array_equal(rows, sample_surface_emitters(triangles, emission, 4096, pattern=4))


def test_an_emissive_surface_glows_in_the_combined_image_not_in_the_direct_light():
    built = room_lit_by_a_panel()
    built.camera = camera("Up", (0.0, -1.2, 1.0), (0.0, 0.0, 2.95))  # looking up at the panel
    frame = render_once(scene_to_render(built, SIZE), Settings(width=SIZE[0], height=SIZE[1]))
    brightest = frame.passes["combined"].reshape(-1, 3)[np.argmax(frame.passes["combined"].sum(axis=2))]
    np.testing.assert_allclose(brightest, [10.0, 9.0, 7.0], rtol=0.05)  # the panel's radiance (black albedo)
    assert frame.passes["direct"].max() < 2.0 and frame.passes["indirect"].max() < 2.0
