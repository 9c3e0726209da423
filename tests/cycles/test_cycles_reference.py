"""The Cycles reference renders real passes, gets the physics right and leaves the scene as it was.

A 2x2 m diffuse plane (albedo 0.5) seen from 3 m straight above, lit by a point light of
radius 0 at 1 m, rendered at 24x24 with 8 samples by real Cycles on the CPU.
"""
import math
import tempfile

import bpy
import numpy as np
import pytest

import addon_utils  # on the path only once bpy is imported

from lpv_preview.addon.cycles_reference import (PART_GROWTH, cycles_passes_in_parts, describe_reference_settings,
                                               render_cycles_passes, run_to_end)
from lpv_preview.gpu.errors import LPVError

ALBEDO = 0.5
LIGHT_POWER = 100.0  # W
LIGHT_HEIGHT = 1.0  # m
CAMERA_HEIGHT = 3.0  # m
SENSOR_WIDTH = 36.0  # mm
LENS = 50.0  # mm
SIZE = 24  # pixels
SAMPLES = 8


def _build_scene():
    """The test scene, with deliberately unusual render settings that must survive a reference."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("cycles", default_set=True)
    scene = bpy.context.scene

    bpy.ops.mesh.primitive_plane_add(size=2.0)
    material = bpy.data.materials.new("Albedo half")
    nodes = material.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (ALBEDO, ALBEDO, ALBEDO, 1.0)
    material.node_tree.links.new(diffuse.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    bpy.context.active_object.data.materials.append(material)

    light = bpy.data.lights.new("Point", "POINT")
    light.energy = LIGHT_POWER
    light.shadow_soft_size = 0.0
    light_object = bpy.data.objects.new("Point", light)
    light_object.location = (0.0, 0.0, LIGHT_HEIGHT)
    scene.collection.objects.link(light_object)

    camera = bpy.data.cameras.new("Camera")
    camera.lens, camera.sensor_width, camera.sensor_fit = LENS, SENSOR_WIDTH, "HORIZONTAL"
    camera_object = bpy.data.objects.new("Camera", camera)
    camera_object.location = (0.0, 0.0, CAMERA_HEIGHT)  # no rotation: looks down -Z, +Y up in the image
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object

    render = scene.render
    render.engine = "BLENDER_EEVEE"
    render.resolution_x, render.resolution_y, render.resolution_percentage = 37, 29, 50
    render.filepath = "//user_output/frame_"
    render.image_settings.file_format = "PNG"
    render.image_settings.color_depth = "16"
    scene.cycles.samples = 3
    scene.cycles.use_denoising = True
    scene.cycles.light_sampling_threshold = 0.05
    scene.cycles.max_bounces = 7
    scene.frame_current = 5
    scene.view_layers.new("Other layer")
    return scene


def _render_state(scene):
    """Every plain setting of the render, its image format, Cycles and each view layer."""
    structs = {"scene": scene, "render": scene.render, "image": scene.render.image_settings,
               "cycles": scene.cycles, **{f"layer {v.name}": v for v in scene.view_layers}}
    state = {}
    for label, struct in structs.items():
        for prop in struct.bl_rna.properties:
            if prop.type in {"POINTER", "COLLECTION"} or prop.identifier == "rna_type" or prop.is_deprecated:
                continue
            value = getattr(struct, prop.identifier)
            state[f"{label}.{prop.identifier}"] = tuple(value) if hasattr(value, "__len__") and not isinstance(
                value, str) else value
    return state


@pytest.fixture
def scene():
    return _build_scene()


@pytest.fixture
def temp_root(tmp_path, monkeypatch):
    """Temporary files of the render go here, so the test can see that they are removed."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    return tmp_path


def _pixel_centres():
    """World x (right) and y (up in the image) of each pixel centre on the plane, rows top first."""
    half_width = CAMERA_HEIGHT * SENSOR_WIDTH / LENS / 2.0
    centres = (np.arange(SIZE) + 0.5) / SIZE * 2.0 * half_width - half_width
    return np.meshgrid(centres, centres[::-1])


def test_passes_are_plausible_and_settings_survive(scene, temp_root):
    before = _render_state(scene)
    result = render_cycles_passes(scene, samples=SAMPLES, resolution=(SIZE, SIZE))
    assert _render_state(scene) == before
    assert list(temp_root.iterdir()) == []

    for name in ("Combined", "DiffDir", "DiffCol"):
        assert result[name].shape == (SIZE, SIZE, 3) and result[name].dtype == np.float32
        assert np.isfinite(result[name]).all()
    x, y = _pixel_centres()
    on_plane = (np.abs(x) < 0.9) & (np.abs(y) < 0.9)
    assert np.allclose(result["DiffCol"][on_plane], ALBEDO, atol=0.01)
    assert (result["DiffDir"][on_plane] > 0).all()
    brightest_row, brightest_column = np.unravel_index(result["DiffDir"][..., 1].argmax(), (SIZE, SIZE))
    assert {brightest_row, brightest_column} <= {SIZE // 2 - 1, SIZE // 2}

    settings = result["settings"]
    assert settings["samples"] == SAMPLES and settings["resolution"] == (SIZE, SIZE)
    assert settings["max_bounces"] == 7  # the scene's own, since none was asked for
    print("\n" + describe_reference_settings(settings))


def test_a_render_whose_samples_cost_little_goes_in_few_parts(scene, temp_root):
    """Each part pays the scene's synchronisation again. Under load (a second process
    busy on both cores) that alone took more than PART_SECONDS, and a 32-sample render
    of the forest world went in 32 parts of one sample, 44.7 s where 3.6 s sufficed."""
    parts = []
    result = run_to_end(cycles_passes_in_parts(scene, ("Combined",), 256, (SIZE, SIZE)), parts.append)
    print(f"\n256 samples at {SIZE}x{SIZE} in {len(parts)} parts: {[done for done, _ in parts]}")
    assert parts[-1][0] == 256 and result["Combined"].shape == (SIZE, SIZE, 3)
    assert len(parts) <= 2 + math.ceil(math.log(256, PART_GROWTH))


def test_point_light_irradiance_matches_physics(scene, temp_root):
    """Diffuse direct = E/pi with E = P h / (4 pi d^3): the point light's irradiance on the plane."""
    result = render_cycles_passes(scene, samples=SAMPLES, resolution=(SIZE, SIZE), max_bounces=0,
                                  pixel_filter_width=0.01)
    x, y = _pixel_centres()
    distance = np.sqrt(x * x + y * y + LIGHT_HEIGHT ** 2)
    expected = LIGHT_POWER * LIGHT_HEIGHT / (4.0 * math.pi * distance ** 3) / math.pi
    centre = slice(SIZE // 2 - 1, SIZE // 2 + 1)
    measured = result["DiffDir"][centre, centre].mean()
    straight_below = LIGHT_POWER / (4.0 * math.pi * LIGHT_HEIGHT ** 2) / math.pi
    print(f"\nDiffDir at the centre {measured:.4f}, P/(4 pi h^2)/pi = {straight_below:.4f}, "
          f"ratio {measured / straight_below:.4f}; with the pixels' offset from the axis "
          f"{expected[centre, centre].mean():.4f}")
    assert measured == pytest.approx(expected[centre, centre].mean(), rel=0.01)
    assert measured == pytest.approx(straight_below, rel=0.02)
    on_plane = (np.abs(x) < 0.9) & (np.abs(y) < 0.9)
    assert np.allclose(result["DiffDir"][on_plane], expected[on_plane, None], rtol=0.02)
    assert np.allclose(result["Combined"][on_plane], (expected * ALBEDO)[on_plane, None], rtol=0.02)


def test_rows_run_top_down_and_columns_left_to_right(scene, temp_root):
    """A light moved to world +X, +Y lights the top right of the picture, as the Image Editor shows it."""
    bpy.data.objects["Point"].location = (0.5, 0.5, LIGHT_HEIGHT)
    diffuse_direct = render_cycles_passes(scene, passes=("DiffDir",), samples=SAMPLES, resolution=(SIZE, SIZE),
                                          max_bounces=0)["DiffDir"][..., 0]
    row, column = np.unravel_index(diffuse_direct.argmax(), diffuse_direct.shape)
    assert row < SIZE // 2 <= column


def test_unknown_pass_raises_and_settings_survive(scene, temp_root):
    before = _render_state(scene)
    with pytest.raises(LPVError, match="'Shininess'"):
        render_cycles_passes(scene, passes=("DiffDir", "Shininess"), samples=1, resolution=(4, 4))
    assert _render_state(scene) == before
    assert list(temp_root.iterdir()) == []


def test_failed_render_raises_and_settings_survive(scene, temp_root):
    scene.camera = None
    bpy.data.objects.remove(bpy.data.objects["Camera"])
    before = _render_state(scene)
    with pytest.raises(LPVError, match="no camera"):
        render_cycles_passes(scene, samples=1, resolution=(4, 4))
    assert _render_state(scene) == before
    assert list(temp_root.iterdir()) == []


def test_unwritable_temporary_location_raises(scene, tmp_path, monkeypatch):
    not_a_folder = tmp_path / "a file"
    not_a_folder.write_text("")
    monkeypatch.setattr(tempfile, "tempdir", str(not_a_folder / "inside"))
    before = _render_state(scene)
    with pytest.raises(LPVError, match="temporary folder"):
        render_cycles_passes(scene, samples=1, resolution=(4, 4))
    assert _render_state(scene) == before


# ----------------------------------------------------------------------------- F12's reference

REFERENCE_SIZE = (32, 24)
WORLD_GREY = 0.25


def _grey_world(scene, grey=WORLD_GREY):
    scene.world = bpy.data.worlds.new("Grey sky")
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (grey, grey, grey, 1.0)
    return scene.world


def test_the_f12_reference_keeps_the_scenes_own_settings_and_shows_the_world(scene, temp_root):
    """F12's Combined: the scene's bounces, clamping and pixel filter, the world seen past
    the plane; only the samples (plain ones), seed and size are the reference's. The
    diffuse reference of the same scene has no world in its combined image."""
    from lpv_preview.addon.cycles_reference import F12, cycles_reference
    _grey_world(scene)
    scene.cycles.sample_clamp_indirect, scene.cycles.filter_width = 3.0, 1.2
    before = _render_state(scene)
    f12 = cycles_reference(scene, F12, 2, resolution=REFERENCE_SIZE)
    diffuse = cycles_reference(scene, "full_gi", 2, resolution=REFERENCE_SIZE)
    assert _render_state(scene) == before
    assert list(temp_root.iterdir()) == []
    settings = f12.settings
    assert (settings["samples"], settings["seed"], settings["resolution"]) == (2, 0, REFERENCE_SIZE)
    assert (settings["max_bounces"], settings["clamp_indirect"]) == (7, 3.0)
    assert settings["pixel_filter_width"] == pytest.approx(1.2)
    assert settings["denoiser"] is None and settings["world"] == "Grey sky"
    assert f12.combined.shape == (24, 32, 3)
    corner = f12.combined[0, 0]  # past the plane's edge: the world
    np.testing.assert_allclose(corner, WORLD_GREY, rtol=1e-3)
    assert diffuse.combined[0, 0].max() == 0.0 and diffuse.settings["max_bounces"] == 12
    print("\n" + describe_reference_settings(settings))


def particles_scene():
    """Under a black sky an unrendered emitter plane whose hair particles are glowing
    cubes (their source far out of view), seen from above: black with the particle
    system hidden in renders, lit with it shown."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("cycles", default_set=True)
    scene = bpy.context.scene
    _grey_world(scene, 0.0)
    bpy.ops.mesh.primitive_plane_add(size=2.0)
    emitter = bpy.context.active_object
    emitter.show_instancer_for_render = False
    bpy.ops.mesh.primitive_cube_add(size=0.2, location=(0.0, 0.0, -50.0))
    grain = bpy.context.active_object
    glow = bpy.data.materials.new("Glow")
    emission = glow.node_tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 5.0
    glow.node_tree.links.new(emission.outputs[0], glow.node_tree.nodes["Material Output"].inputs["Surface"])
    grain.data.materials.append(glow)
    particles = emitter.modifiers.new("Particles", "PARTICLE_SYSTEM")
    settings = particles.particle_system.settings
    settings.type, settings.count, settings.hair_length, settings.particle_size = "HAIR", 50, 0.2, 1.0
    settings.render_type, settings.instance_object = "OBJECT", grain
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, 0.0, 4.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return scene, particles


def test_particles_shown_get_a_new_reference_that_is_not_black(tmp_path):
    from lpv_preview.addon.cycles_reference import F12, ReferenceCache, cycles_reference
    from lpv_preview.addon.render_scene import scene_and_signature_to_render
    scene, particles = particles_scene()
    cache = ReferenceCache(str(tmp_path / "cache"))
    particles.show_render = False
    hidden = cycles_reference(scene, F12, 2, resolution=REFERENCE_SIZE, cache=cache)
    assert hidden.combined.max() == 0.0
    particles.show_render = True
    shown = cycles_reference(scene, F12, 2, resolution=REFERENCE_SIZE, cache=cache)
    assert shown.settings["key"] != hidden.settings["key"] and not shown.settings["cached"]
    assert shown.combined.mean() > 0.01
    # Rendered again, the same instances hash the same: from the cache.
    assert scene_and_signature_to_render(scene, REFERENCE_SIZE)[1] == scene_and_signature_to_render(
        scene, REFERENCE_SIZE)[1]
    assert cycles_reference(scene, F12, 2, resolution=REFERENCE_SIZE, cache=cache).settings["cached"]


def test_the_key_follows_what_f12_renders_and_not_the_selection():
    """The world's colour, film transparency, an object's render visibility and a
    particle's count change the key; selecting another object, the viewport's display and
    the colour management do not."""
    from lpv_preview.addon.render_scene import scene_and_signature_to_render
    scene, particles = particles_scene()
    signature = lambda: scene_and_signature_to_render(scene, REFERENCE_SIZE)[1]
    first = signature()
    bpy.data.objects["Camera"].select_set(True)
    bpy.context.view_layer.objects.active = bpy.data.objects["Camera"]
    bpy.data.objects["Plane"].display_type = "WIRE"
    scene.view_settings.view_transform = "Standard"
    assert signature() == first
    changes = [lambda: scene.world.node_tree.nodes["Background"].inputs["Color"].default_value.__setitem__(0, 0.5),
               lambda: setattr(scene.render, "film_transparent", True),
               lambda: setattr(particles.particle_system.settings, "count", 40),
               lambda: setattr(bpy.data.objects["Cube"], "hide_render", True),
               lambda: setattr(bpy.data.materials["Glow"].node_tree.nodes["Emission"].inputs["Strength"],
                               "default_value", 4.0)]
    seen = {first}
    for change in changes:
        change()
        key = signature()
        assert key not in seen, change
        seen.add(key)
