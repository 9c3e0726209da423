"""Materials as Blender users make them (addon/materials.py, addon/extract.py): image
textures sampled per pixel and per texel instead of averaged, colour spaces, UV maps,
colour attributes, the Principled BSDF's diffuse part, and the materials only
approximated named in stats.json. Scenes made here with bpy."""
import json

import bpy
import numpy as np
import pytest

from lpv_preview.__main__ import main
from lpv_preview.addon.render_scene import scene_to_render

CHECKER_SRGB = (0.9, 0.1)  # the checker's two grey levels, sRGB-encoded


def srgb_to_linear(value):
    return value / 12.92 if value <= 0.04045 else ((value + 0.055) / 1.055) ** 2.4


def checker_image(name="Checker", squares=4, size=64, colorspace="sRGB", float_buffer=False):
    image = bpy.data.images.new(name, size, size, float_buffer=float_buffer)
    image.colorspace_settings.name = colorspace  # first: setting it regenerates a generated image
    cell = size // squares
    y, x = np.mgrid[0:size, 0:size]
    value = np.where(((x // cell) + (y // cell)) % 2 == 0, *CHECKER_SRGB)
    pixels = np.repeat(value[..., None], 4, axis=2).astype(np.float32)
    pixels[..., 3] = 1.0
    image.pixels.foreach_set(pixels.ravel())
    image.pack()  # a generated image is lost on save unless packed
    return image


def material_with(name, build):
    """A material whose Principled BSDF's Base Color `build(nodes, links, principled)` wires."""
    material = bpy.data.materials.new(name)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    build(nodes, links, nodes["Principled BSDF"])
    return material


def principled_with(name, inputs):
    """A material whose Principled BSDF's inputs (by name) take these values."""
    def build(nodes, links, principled):
        for socket, value in inputs.items():
            principled.inputs[socket].default_value = value
    return material_with(name, build)


def image_material(image, uv_map=None, name="Textured"):
    def build(nodes, links, principled):
        principled.inputs["Specular IOR Level"].default_value = 0.0  # diffuse alone: what these tests look at
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = image
        links.new(texture.outputs["Color"], principled.inputs["Base Color"])
        if uv_map is not None:
            uv = nodes.new("ShaderNodeUVMap")
            uv.uv_map = uv_map
            links.new(uv.outputs["UV"], texture.inputs["Vector"])
    return material_with(name, build)


def floor_scene(make_material):
    """An empty file with a 4 m plane (with its UV map) carrying the material that
    `make_material()` makes, a point light and a camera looking straight down at it."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=4)
    floor = bpy.context.active_object
    floor.data.materials.append(make_material())
    light = bpy.data.objects.new("Light", bpy.data.lights.new("Light", "POINT"))
    light.data.energy = 500
    light.location = (0, 0, 3)
    scene.collection.objects.link(light)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0, 0, 6)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = 64
    scene.render.resolution_percentage = 100
    return scene, floor


def test_an_image_texture_reaches_the_scene_with_its_uvs_and_linear_pixels():
    scene, _ = floor_scene(lambda: image_material(checker_image()))
    extracted = scene_to_render(scene)
    assert [i.name for i in extracted.images] == ["Checker"] and extracted.approximated_materials == []
    assert set(extracted.image_layers.tolist()) == {0}
    np.testing.assert_allclose(extracted.albedo, 1.0)  # the image carries the colour, not an average
    levels = sorted(np.unique(np.round(extracted.images[0].pixels, 5)))
    stored = [round(v * 255) / 255 for v in CHECKER_SRGB]  # a byte image keeps 8 bits
    np.testing.assert_allclose(levels, sorted(srgb_to_linear(v) for v in stored), atol=1e-4)
    assert extracted.uvs.min() == pytest.approx(0.0) and extracted.uvs.max() == pytest.approx(1.0)


def test_a_checker_floor_renders_as_a_checker(tmp_path):
    scene, _ = floor_scene(lambda: image_material(checker_image()))
    blend = tmp_path / "checker.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "out"
    assert main(["render", str(blend), "--out", str(out), "--rsm-resolution", "128", "--vpls-per-light", "256",
                 "--lpv-resolution", "8"]) == 0
    from lpv_preview.gpu.image_io import read_exr
    direct = read_exr(str(out / "passes.exr"))["direct"][..., 0]
    middle = direct[16:48, 16:48]  # the floor's middle: two by two checker squares
    bright, dark = np.percentile(middle, 90), np.percentile(middle, 10)
    assert bright > 5 * dark  # an average would be flat: about 1.3x from the light's falloff alone
    stats = json.loads((out / "stats.json").read_text())
    assert stats["images"] == ["Checker"] and stats["approximated_materials"] == []


def test_non_colour_images_are_read_as_they_are():
    scene, _ = floor_scene(lambda: image_material(checker_image(colorspace="Non-Color")))
    levels = sorted(np.unique(np.round(scene_to_render(scene).images[0].pixels, 4)))
    np.testing.assert_allclose(levels, sorted(CHECKER_SRGB), atol=2e-3)


def test_a_uv_map_node_picks_its_uv_map():
    scene, floor = floor_scene(lambda: image_material(checker_image(), uv_map="Shifted"))
    shifted = floor.data.uv_layers.new(name="Shifted")
    values = np.empty(len(floor.data.loops) * 2, np.float32)
    shifted.uv.foreach_get("vector", values)
    shifted.uv.foreach_set("vector", values * 0.5 + 0.25)
    extracted = scene_to_render(scene)
    assert extracted.uvs.min() == pytest.approx(0.25) and extracted.uvs.max() == pytest.approx(0.75)


def test_a_colour_attribute_colours_the_corners():
    def build(nodes, links, principled):
        attribute = nodes.new("ShaderNodeVertexColor")
        attribute.layer_name = "Paint"
        links.new(attribute.outputs["Color"], principled.inputs["Base Color"])
    scene, floor = floor_scene(lambda: material_with("Painted", build))
    paint = floor.data.color_attributes.new("Paint", "FLOAT_COLOR", "POINT")
    colours = np.tile([0.1, 0.2, 0.9, 1.0], (len(floor.data.vertices), 1)).astype(np.float32)
    colours[0] = (0.9, 0.1, 0.1, 1.0)
    paint.data.foreach_set("color", colours.ravel())
    extracted = scene_to_render(scene)
    corners = extracted.vertex_colors.reshape(-1, 3)
    assert {tuple(np.round(c.astype(float), 3).tolist()) for c in corners} == {(0.1, 0.2, 0.9), (0.9, 0.1, 0.1)}
    assert extracted.approximated_materials == []


def test_the_principled_diffuse_part_loses_what_metallic_and_transmission_take():
    def build(nodes, links, principled):
        principled.inputs["Base Color"].default_value = (0.8, 0.6, 0.4, 1.0)
        principled.inputs["Metallic"].default_value = 0.5
        principled.inputs["Transmission Weight"].default_value = 0.25
    scene, _ = floor_scene(lambda: material_with("Half metal", build))
    np.testing.assert_allclose(scene_to_render(scene).albedo[0], np.array([0.8, 0.6, 0.4]) * 0.5 * 0.75, rtol=1e-5)


def test_the_principled_glossy_part_is_f0_and_roughness():
    scene, _ = floor_scene(lambda: principled_with("Glossy", {
        "Base Color": (0.8, 0.6, 0.4, 1.0), "Metallic": 0.25, "Roughness": 0.3, "IOR": 1.5, "Specular IOR Level": 0.75,
        "Specular Tint": (1.0, 0.5, 0.5, 1.0)}))
    extracted = scene_to_render(scene)
    dielectric = 0.04 * 2 * 0.75 * np.array([1.0, 0.5, 0.5])
    np.testing.assert_allclose(extracted.specular[0, :3], 0.75 * dielectric + 0.25 * np.array([0.8, 0.6, 0.4]),
                               rtol=1e-5)
    assert extracted.specular[0, 3:] == pytest.approx((0.3, 0.25))
    assert extracted.approximated_materials == []


def test_a_linked_roughness_is_taken_at_its_value_and_named():
    def build(nodes, links, principled):
        principled.inputs["Metallic"].default_value = 1.0
        principled.inputs["Roughness"].default_value = 0.2
        links.new(nodes.new("ShaderNodeTexNoise").outputs["Fac"], principled.inputs["Roughness"])
    scene, _ = floor_scene(lambda: material_with("Noisy metal", build))
    extracted = scene_to_render(scene)
    np.testing.assert_allclose(extracted.specular[0], (0.8, 0.8, 0.8, 0.2, 1.0), rtol=1e-5)
    assert extracted.approximated_materials == ["Noisy metal"]


def test_a_mix_multiplying_an_image_by_a_colour_stays_exact():
    def build(nodes, links, principled):
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = checker_image()
        mix = nodes.new("ShaderNodeMix")
        mix.data_type, mix.blend_type = "RGBA", "MULTIPLY"
        mix.inputs["Factor"].default_value = 1.0
        mix.inputs[7].default_value = (0.5, 0.25, 1.0, 1.0)
        links.new(texture.outputs["Color"], mix.inputs[6])
        links.new(mix.outputs[2], principled.inputs["Base Color"])
    scene, _ = floor_scene(lambda: material_with("Tinted", build))
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == [] and len(extracted.images) == 1
    np.testing.assert_allclose(extracted.albedo[0], (0.5, 0.25, 1.0))


def test_procedural_textures_are_approximated_and_named(tmp_path):
    def build(nodes, links, principled):
        noise = nodes.new("ShaderNodeTexNoise")
        links.new(noise.outputs["Color"], principled.inputs["Base Color"])
    scene, _ = floor_scene(lambda: material_with("Cloudy", build))
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == ["Cloudy"] and extracted.images == []
