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

from .test_textures import floor_scene, image_material, material_with, principled_with

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


def shader_material(name, node_type, output_socket="Surface"):
    """A material whose output's `output_socket` a new `node_type` shader feeds (the
    Principled BSDF stays, unlinked, when the Volume is fed)."""
    material = bpy.data.materials.new(name)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    shader = nodes.new(node_type)
    links.new(shader.outputs[0], nodes["Material Output"].inputs[output_socket])
    return material


@pytest.mark.parametrize("name, node_type, output_socket, named", [
    ("Smoke", "ShaderNodeVolumePrincipled", "Volume", "Smoke: volume (rendered as an opaque surface)"),
    ("Fog", "ShaderNodeVolumeScatter", "Volume", "Fog: volume (rendered as an opaque surface)"),
    ("Ink", "ShaderNodeVolumeAbsorption", "Volume", "Ink: volume (rendered as an opaque surface)"),
    ("Paper", "ShaderNodeBsdfTranslucent", "Surface",
     "Paper: translucency (rendered as an opaque diffuse surface in the display colour)"),
    ("Skin", "ShaderNodeSubsurfaceScattering", "Surface",
     "Skin: subsurface scattering (rendered as an opaque diffuse surface in the display colour)"),
    ("Fur", "ShaderNodeBsdfHairPrincipled", "Surface",
     "Fur: hair (rendered as an opaque diffuse surface in the display colour)"),
    ("Cartoon", "ShaderNodeBsdfToon", "Surface",
     "Cartoon: toon (rendered as an opaque diffuse surface in the display colour)"),
    ("Cutout", "ShaderNodeHoldout", "Surface", "Cutout: holdout (rendered as an opaque black surface, not cut out)"),
])
def test_unsupported_shaders_are_listed_with_what_the_preview_does(name, node_type, output_socket, named):
    scene, _ = floor_scene(lambda: shader_material(name, node_type, output_socket))
    assert scene_to_render(scene).approximated_materials == [named]


@pytest.mark.parametrize("name, node_type, named", [
    ("Window", "ShaderNodeBsdfGlass",
     ["Window: glass (seen and lit through as a thin tinted sheet: no refraction, reflection or caustics)"]),
    ("Lens", "ShaderNodeBsdfRefraction",
     ["Lens: refraction (seen and lit through as a thin tinted sheet: no refraction, reflection or caustics)"]),
    ("Filter", "ShaderNodeBsdfTransparent", []),
])
def test_glass_refraction_and_transparent_shaders_are_thin_tinted_sheets(name, node_type, named):
    def make():
        material = shader_material(name, node_type)
        next(node for node in material.node_tree.nodes if node.bl_idname == node_type).inputs["Color"].default_value = (
            0.5, 0.25, 1.0, 1.0)
        return material
    scene, _ = floor_scene(make)
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == named
    np.testing.assert_allclose(extracted.transmission[0], (0.5, 0.25, 1.0, 1.0))  # the tint at each crossing, all passing
    np.testing.assert_allclose(extracted.albedo[0], 0.0)


def test_a_clear_transparent_shader_leaves_nothing_to_render():
    scene, _ = floor_scene(lambda: shader_material("Invisible", "ShaderNodeBsdfTransparent"))
    with pytest.raises(LPVError, match="no renderable triangles"):
        scene_to_render(scene)


def test_principled_transmission_and_alpha_are_read_and_subsurface_named():
    scene, _ = floor_scene(lambda: principled_with("Jelly", {
        "Base Color": (0.5, 0.5, 0.5, 1.0), "Transmission Weight": 0.5, "Subsurface Weight": 0.2, "Alpha": 0.5}))
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == [
        "Jelly: transmission (seen and lit through as a thin tinted sheet: no refraction, reflection or caustics); "
        "subsurface scattering (rendered as plain diffuse)"]
    np.testing.assert_allclose(extracted.albedo[0], 0.25, rtol=1e-5)  # Base Color x (1 - transmission), as before
    np.testing.assert_allclose(extracted.alpha[0], 0.5)
    np.testing.assert_allclose(extracted.transmission[0], (*[np.sqrt(0.5)] * 3, 0.5), rtol=1e-5)


def test_an_approximated_colour_with_alpha_is_named_alone():
    def build(nodes, links, principled):
        principled.inputs["Alpha"].default_value = 0.5
        noise = nodes.new("ShaderNodeTexNoise")
        links.new(noise.outputs["Color"], principled.inputs["Base Color"])
    scene, _ = floor_scene(lambda: material_with("Cloudy glass", build))
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == ["Cloudy glass"]
    np.testing.assert_allclose(extracted.alpha[0], 0.5)


def test_a_volume_is_listed_in_stats_json(tmp_path):
    scene, _ = floor_scene(lambda: shader_material("Smoke", "ShaderNodeVolumePrincipled", "Volume"))
    blend = tmp_path / "smoke.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "out"
    assert main(["render", str(blend), "--out", str(out), *SMALL]) == 0
    stats = json.loads((out / "stats.json").read_text())
    assert stats["approximated_materials"] == ["Smoke: volume (rendered as an opaque surface)"]


def render_direct(scene, tmp_path, capsys=None):
    """The direct pass and stats.json of `scene` rendered by the command line (and its
    stderr, when `capsys` is given)."""
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "out"
    if capsys is not None:
        capsys.readouterr()
    assert main(["render", str(blend), "--out", str(out), *SMALL]) == 0
    from lpv_preview.gpu.image_io import read_exr
    stderr = capsys.readouterr().err if capsys is not None else ""
    return read_exr(str(out / "passes.exr"))["direct"], json.loads((out / "stats.json").read_text()), stderr


def missing_image():
    image = bpy.data.images.new("Brick", 4, 4)
    image.source, image.filepath = "FILE", "//textures/no_such_brick.png"
    image.reload()
    return image


def test_a_missing_image_renders_magenta_with_a_warning(tmp_path, capsys):
    scene, _ = floor_scene(lambda: image_material(missing_image()))
    extracted = scene_to_render(scene)
    assert extracted.missing_images == ["Brick"] and extracted.approximated_materials == []
    np.testing.assert_allclose(extracted.images[0].pixels.reshape(-1, 3), [[1.0, 0.0, 1.0]])
    direct, stats, stderr = render_direct(scene, tmp_path, capsys)
    middle = direct[16:48, 16:48]
    assert middle[..., 0].min() > 0 and middle[..., 1].max() == 0
    np.testing.assert_allclose(middle[..., 2], middle[..., 0], rtol=1e-3)  # magenta: red and blue alike
    warning = ("Image 'Brick' is missing and renders magenta; find its file with File > External Data > Find "
               "Missing Files.")
    assert stats["missing_images"] == ["Brick"] and stats["missing_images_warning"] == warning
    assert [line for line in stderr.splitlines() if "missing" in line] == [f"lpv_preview: warning: {warning}"]


def test_f12_keeps_the_missing_image_warning_for_the_statistics_panel():
    from lpv_preview.addon.frame_stats import last_stats, missing_images_warning
    scene, _ = floor_scene(lambda: image_material(missing_image()))
    lpv_preview.register()
    try:
        scene.render.engine = ENGINE_ID
        scene.lpv_preview.rsm_resolution, scene.lpv_preview.vpls_per_light = 64, 256
        bpy.ops.render.render()
        stats = dict(last_stats())  # unregistering forgets them
    finally:
        lpv_preview.unregister()
    assert stats["missing_images"] == ["Brick"] and "'Brick' is missing" in missing_images_warning(stats)


TILE_COLOURS = {1001: (1.0, 0.0, 0.0), 1002: (0.0, 0.0, 1.0)}


def udim_image(folder, packed):
    """A tiled image of TILE_COLOURS' tiles, each a 4 x 4 PNG written with bpy in `folder`
    (`packed`: packed into the file, the PNGs removed)."""
    for number, colour in TILE_COLOURS.items():
        tile = bpy.data.images.new(f"tile {number}", 4, 4)
        tile.pixels.foreach_set(np.tile(np.array([*colour, 1.0], np.float32), 16))
        tile.filepath_raw, tile.file_format = str(folder / f"tiles.{number}.png"), "PNG"
        tile.save()
        bpy.data.images.remove(tile)
    image = bpy.data.images.load(str(folder / "tiles.1001.png"))
    image.name, image.source, image.filepath = "Tiles", "TILED", str(folder / "tiles.<UDIM>.png")
    image.reload()
    assert [tile.number for tile in image.tiles] == list(TILE_COLOURS)
    if packed:
        image.pack()
        for number in TILE_COLOURS:
            (folder / f"tiles.{number}.png").unlink()
    return image


def two_tile_floor(folder, packed):
    """floor_scene's camera and light over a 4 m floor of two quads textured by
    udim_image, x < 0 at UV u 0-1 (tile 1001) and x > 0 at u 1-2 (tile 1002)."""
    scene, plane = floor_scene(lambda: image_material(udim_image(folder, packed)))
    mesh = bpy.data.meshes.new("Two tiles")
    mesh.from_pydata([(x, y, 0) for x in (-2, 0, 2) for y in (-2, 2)], [], [(0, 2, 3, 1), (2, 4, 5, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        x, y, _ = mesh.vertices[loop.vertex_index].co
        uv.uv[loop.index].vector = ((x + 2) / 2, (y + 2) / 4)
    mesh.materials.append(plane.data.materials[0])
    plane.data = mesh
    return scene


@pytest.mark.parametrize("packed", [False, True])
def test_udim_tiles_are_read_at_their_uv_offsets(tmp_path, packed):
    scene = two_tile_floor(tmp_path, packed)
    extracted = scene_to_render(scene)
    assert sorted(i.name for i in extracted.images) == ["Tiles.1001", "Tiles.1002"]
    assert extracted.missing_images == [] and extracted.approximated_materials == []
    for surface_image in extracted.images:
        colour = TILE_COLOURS[int(surface_image.name.split(".")[-1])]
        np.testing.assert_allclose(surface_image.pixels.reshape(-1, 3), [colour] * 16, atol=1e-6)
    direct, stats, _ = render_direct(scene, tmp_path)
    left, right = direct[20:44, 8:28].reshape(-1, 3), direct[20:44, 36:56].reshape(-1, 3)
    assert left[:, 0].min() > 0 and left[:, 1:].max() == 0  # tile 1001: red
    assert right[:, 2].min() > 0 and right[:, :2].max() == 0  # tile 1002: blue


def test_a_transparent_mix_by_an_image_alpha_cuts_the_surface_out():
    """The usual cut-out set-up: a Mix Shader of a Transparent BSDF and the surface, its
    factor an Image Texture's alpha; the image keeps its alpha channel in the array."""
    def make():
        image = bpy.data.images.new("Leaf", 2, 2, alpha=True)
        image.pixels.foreach_set(np.array([[0.2, 0.6, 0.2, a] for a in (1, 0, 0, 1)], np.float32).ravel())
        material = bpy.data.materials.new("Leaf")
        nodes, links = material.node_tree.nodes, material.node_tree.links
        texture, mix = nodes.new("ShaderNodeTexImage"), nodes.new("ShaderNodeMixShader")
        texture.image = image
        transparent = nodes.new("ShaderNodeBsdfTransparent")
        links.new(texture.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
        links.new(texture.outputs["Alpha"], mix.inputs["Fac"])
        links.new(transparent.outputs[0], mix.inputs[1])
        links.new(nodes["Principled BSDF"].outputs[0], mix.inputs[2])
        links.new(mix.outputs[0], nodes["Material Output"].inputs["Surface"])
        return material
    scene, _ = floor_scene(make)
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == []
    assert extracted.alpha is None and extracted.transmission is None
    np.testing.assert_array_equal(extracted.alpha_layers, extracted.image_layers)
    np.testing.assert_array_equal(extracted.images[0].pixels[..., 3], [[0, 1], [1, 0]])  # top row first


def test_a_coat_is_folded_into_the_glossy_lobe_and_sheen_named():
    scene, _ = floor_scene(lambda: principled_with("Car paint", {
        "Roughness": 0.6, "Coat Weight": 1.0, "Coat Roughness": 0.1, "Sheen Weight": 0.5}))
    extracted = scene_to_render(scene)
    assert extracted.approximated_materials == [
        "Car paint: coat (folded into the one glossy lobe; its tint and normal left out); sheen (left out)"]
    f0, roughness = extracted.specular[0, :3], extracted.specular[0, 3]
    np.testing.assert_allclose(f0, 0.04 + 0.04 * 0.96, rtol=1e-4)  # the base's F0 and the coat's (IOR 1.5)
    assert roughness == pytest.approx(0.35, rel=1e-4)  # their roughnesses weighted by their equal F0s
