"""The LPV Preview render engine through real bpy: F12 renders, errors, the user's scene."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

import lpv_preview  # noqa: E402
from lpv_preview import demo  # noqa: E402
from lpv_preview.addon.engine import ENGINE_ID  # noqa: E402
from lpv_preview.addon.extract import extract_scene  # noqa: E402
from lpv_preview.addon.properties import settings_from_properties  # noqa: E402
from lpv_preview.gpu.capacity import available_host_bytes  # noqa: E402
from lpv_preview.gpu.debug_views import STATUS_COLOURS  # noqa: E402
from lpv_preview.gpu.image_io import read_exr_channels  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402


RUNTIME_STATE = {"depsgraph", "session_uid"}
"""Not settings: what Blender evaluated for a render (a render changes it) and the number
a data-block gets when a file is loaded."""


def plain(value):
    """A property value as plain Python: arrays as (nested) tuples."""
    if hasattr(value, "__len__") and not isinstance(value, str):
        return tuple(plain(item) for item in value)
    return value


def rna_tree(struct, depth=0, max_depth=6):
    """Every readable property of `struct`: plain values, nested structs (the image
    settings' colour management, Cycles' settings, a view layer's passes...) as dicts,
    collections as lists, data-blocks by name (each snapshot says which it looks into)."""
    tree = {}
    for prop in struct.bl_rna.properties:
        name = prop.identifier
        if name == "rna_type" or name in RUNTIME_STATE or prop.is_deprecated:
            continue
        try:
            value = getattr(struct, name)
        except (AttributeError, RuntimeError, TypeError):
            continue
        if prop.type == "POINTER":
            nested = value is not None and not isinstance(value, bpy.types.ID) and depth < max_depth
            tree[name] = rna_tree(value, depth + 1) if nested else getattr(value, "name", None)
        elif prop.type == "COLLECTION":
            tree[name] = [item.name if isinstance(item, bpy.types.ID) else rna_tree(item, depth + 1)
                          for item in value] if depth < max_depth else len(value)
        else:
            tree[name] = plain(value)
    return tree


def scene_snapshot(scene):
    """What a render must leave as it found it: every setting of the scene, nested ones
    included (render and output settings with their colour management, Cycles', the view
    layers and their passes, the frame, the camera), its world's, the objects, their
    transforms and data, the lights and materials, and which scenes there are."""
    return {
        "scene": rna_tree(scene),
        "world": rna_tree(scene.world) if scene.world else None,
        "objects": sorted((o.name, o.type, tuple(o.location), tuple(o.rotation_euler), tuple(o.scale),
                           o.data.name if o.data else "", o.hide_render, o.hide_viewport) for o in scene.objects),
        "lights": sorted((light.name, light.energy, tuple(light.color)) for light in bpy.data.lights),
        "materials": sorted(m.name for m in bpy.data.materials),
        "scenes": sorted(s.name for s in bpy.data.scenes),
    }


@pytest.fixture(scope="module")
def cornell():
    scene = demo.build("cornell")
    lpv_preview.register()
    scene.render.engine = ENGINE_ID
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 48, 40, 100
    settings = scene.lpv_preview
    settings.rsm_resolution, settings.vpls_per_light, settings.lpv_resolution = 64, 256, 16
    yield scene
    lpv_preview.unregister()


def test_f12_render_leaves_the_scene_untouched(cornell):
    before = scene_snapshot(cornell)
    bpy.ops.render.render()
    assert scene_snapshot(cornell) == before


def test_a_render_without_a_gpu_fails_with_one_clear_message(tmp_path):
    script = tmp_path / "render.py"
    script.write_text(textwrap.dedent(f"""
        import bpy, lpv_preview
        from lpv_preview import demo
        scene = demo.build("cornell")
        lpv_preview.register()
        scene.render.engine = "{ENGINE_ID}"
        scene.render.resolution_x = scene.render.resolution_y = 16
        try:
            bpy.ops.render.render()
        except RuntimeError as error:
            print("REPORTED:", str(error).strip())
    """))
    environment = {**os.environ, "LPV_PREVIEW_NO_GPU": "1"}
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=environment,
                            timeout=300)
    output = result.stdout + result.stderr
    reported = [line for line in output.splitlines() if line.startswith("REPORTED:")]
    assert reported == ["REPORTED: Error: No OpenGL 4.5 context is available (LPV_PREVIEW_NO_GPU is set); unset "
                        "it, or install an OpenGL 4.5 driver with EGL: your GPU vendor's, or Mesa's (Debian/Ubuntu: "
                        "apt-get install libegl1 libgl1-mesa-dri); beside X11, LPV_PREVIEW_GL_BACKEND=glx uses GLX "
                        "instead."], output
    assert "Traceback" not in output


def test_an_f12_render_larger_than_the_memory_free_reports_what_it_needs(cornell):
    if available_host_bytes() > 64 * 2 ** 30:
        pytest.skip("this machine has the memory of a 16384 x 16384 frame (about 66 GiB on llvmpipe)")
    render = cornell.render
    render.resolution_x = render.resolution_y = 16384
    try:
        with pytest.raises(RuntimeError) as error:  # the engine's report, not a silent FINISHED
            bpy.ops.render.render()
    finally:
        render.resolution_x, render.resolution_y = 48, 40
    message = str(error.value).strip()
    assert message.startswith("Error: A 16384 x 16384 frame needs about ") and "GiB" in message, message
    assert "; lower the resolution" in message and len(message.splitlines()) == 1, message


def test_f12_render_writes_our_passes_into_a_multilayer_exr(cornell, tmp_path):
    channels = render_exr(cornell, tmp_path / "f12.exr")
    expected = {f"ViewLayer.{name}.{c}" for name in ("Combined", "Direct", "Indirect", "Reflections") for c in "RGB"}
    assert expected | {"ViewLayer.Combined.A"} <= set(channels), sorted(channels)
    for name, values in channels.items():
        assert values.shape == (40, 48) and np.all(np.isfinite(values)), name
    direct = np.stack([channels[f"ViewLayer.Direct.{c}"] for c in "RGB"], axis=-1)
    indirect = np.stack([channels[f"ViewLayer.Indirect.{c}"] for c in "RGB"], axis=-1)
    reflections = np.stack([channels[f"ViewLayer.Reflections.{c}"] for c in "RGB"], axis=-1)
    combined = np.stack([channels[f"ViewLayer.Combined.{c}"] for c in "RGB"], axis=-1)
    assert direct.mean() > 0 and indirect.mean() > 0 and reflections.mean() > 0
    np.testing.assert_allclose(combined, direct + indirect + reflections, rtol=1e-4, atol=1e-6)
    # The same frame rendered by the pipeline alone (top row first, like OpenImageIO's read).
    depsgraph = bpy.context.evaluated_depsgraph_get()
    settings = settings_from_properties(cornell.lpv_preview, width=48, height=40)
    pipeline = Pipeline(settings)
    try:
        alone = pipeline.render(extract_scene(depsgraph)).passes
    finally:
        pipeline.release()
    np.testing.assert_allclose(direct, alone["direct"], rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(indirect, alone["indirect"], rtol=1e-4, atol=1e-6)


def render_exr(scene, path):
    """F12 into a 32-bit multilayer EXR at `path`; the image settings are restored."""
    image = scene.render.image_settings
    saved = image.media_type, image.file_format, image.color_depth, scene.render.filepath
    image.media_type, image.file_format, image.color_depth = "MULTI_LAYER_IMAGE", "OPEN_EXR_MULTILAYER", "32"
    scene.render.filepath = str(path)
    try:
        bpy.ops.render.render(write_still=True)
    finally:
        image.media_type, image.file_format, image.color_depth, scene.render.filepath = saved
    return read_exr_channels(path)


def test_debug_passes_are_written_only_when_asked_for(cornell, tmp_path):
    debug = {f"ViewLayer.{name}.{c}" for name in ("VPL Splats", "Warp Status") for c in "RGB"}
    assert not debug & set(render_exr(cornell, tmp_path / "plain.exr"))
    properties = cornell.lpv_preview
    properties.debug_passes, properties.method = True, "wdpm"
    try:
        channels = render_exr(cornell, tmp_path / "debug.exr")
    finally:
        properties.debug_passes, properties.method = False, "cm"
    assert debug <= set(channels), sorted(channels)
    splats = np.stack([channels[f"ViewLayer.VPL Splats.{c}"] for c in "RGB"], axis=-1)
    status = np.stack([channels[f"ViewLayer.Warp Status.{c}"] for c in "RGB"], axis=-1)
    assert np.all(np.isfinite(splats)) and splats.sum() > 0
    palette = {tuple(np.round(colour, 4)) for colour in STATUS_COLOURS}
    assert {tuple(np.round(colour, 4)) for colour in status.reshape(-1, 3)} <= palette
    assert (status.sum(axis=-1) > 0).mean() > 0.5  # the point light's warped maps see most of the box


def test_toggling_debug_passes_refreshes_the_view_layers_passes(cornell):
    """As the Cycles add-on's pass toggles do: the compositor's Render Layers node shows
    the debug passes as soon as "Debug passes" is ticked, and drops them when it is not."""
    tree = bpy.data.node_groups.new("LPV test compositor", "CompositorNodeTree")
    saved = cornell.compositing_node_group
    cornell.compositing_node_group = tree
    try:
        node = tree.nodes.new("CompositorNodeRLayers")
        node.scene = cornell
        shown = lambda: {output.name for output in node.outputs if output.enabled}
        assert {"Direct", "Indirect"} <= shown() and not {"VPL Splats", "Warp Status"} & shown()
        cornell.lpv_preview.debug_passes = True
        assert {"Direct", "Indirect", "VPL Splats", "Warp Status"} <= shown()
        cornell.lpv_preview.debug_passes = False
        assert not {"VPL Splats", "Warp Status"} & shown()
    finally:
        cornell.lpv_preview.debug_passes = False
        cornell.compositing_node_group = saved
        bpy.data.node_groups.remove(tree)


def test_the_statistics_panel_names_the_renderer_of_an_f12_render(cornell, glc):
    """After F12 the panel's statistics start with the OpenGL renderer and, for a software
    rasterizer (llvmpipe here), the warning F12's own report can give (renderer_warning)."""
    from lpv_preview.addon.frame_stats import last_stats, renderer_warning
    from lpv_preview.addon.ui import renderer_lines
    bpy.ops.render.render()
    stats = last_stats()
    assert stats["renderer"] == glc.renderer and stats["software_renderer"] == glc.is_software
    warning = renderer_warning(stats)
    assert (warning is not None) == glc.is_software
    assert renderer_lines(stats) == [(f"Renderer: {glc.renderer}", "NONE")] + ([(warning, "ERROR")] if warning else [])
    if warning:
        assert warning.startswith(f"OpenGL renders on the CPU here ({glc.renderer})") and warning.count(". ") == 0
    assert renderer_lines({}) == []  # no frame yet: the panel asks for one
