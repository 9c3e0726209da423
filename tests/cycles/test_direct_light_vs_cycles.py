"""Direct light of each light type against Cycles' Diffuse Direct x Diffuse Color.

One light over a diffuse plane, rendered by real Cycles and by our pipeline from the same
camera: this pins Blender's light units. Point, spot and sun lights have no size, so
Cycles' estimate has no noise; the small area light is the one noisy case.
"""
import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import render_cycles_passes  # noqa: E402
from lpv_preview.addon.extract import extract_scene  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

SIZE = 48
SAMPLES = 32
ALBEDO = (0.8, 0.6, 0.4)
LIGHTS = {
    "POINT": dict(energy=150.0, location=(0.3, -0.2, 1.5), shadow_soft_size=0.0),
    "SPOT": dict(energy=300.0, location=(-0.2, 0.1, 1.6), rotation=(0.25, -0.15, 0.0), shadow_soft_size=0.0,
                 spot_size=math.radians(80), spot_blend=0.3),
    "AREA": dict(energy=80.0, location=(0.1, 0.2, 1.4), rotation=(0.3, 0.2, 0.0), size=0.15),
    "SUN": dict(energy=3.0, rotation=(0.5, 0.3, 0.0), angle=0.0),
}


def build_plane_scene(kind):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("plane")
    mesh.from_pydata([(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], [], [(0, 1, 2, 3)])
    material = bpy.data.materials.new("diffuse")
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (*ALBEDO, 1.0)
    principled.inputs["Roughness"].default_value = 1.0
    principled.inputs["Specular IOR Level"].default_value = 0.0  # purely diffuse, as the LPV models
    mesh.materials.append(material)
    plane = bpy.data.objects.new("plane", mesh)
    scene.collection.objects.link(plane)
    params = dict(LIGHTS[kind])
    location, rotation = params.pop("location", (0, 0, 2)), params.pop("rotation", (0, 0, 0))
    light_data = bpy.data.lights.new(kind.lower(), kind)
    for name, value in params.items():
        setattr(light_data, name, value)
    light = bpy.data.objects.new("light", light_data)
    light.location, light.rotation_euler = location, rotation
    scene.collection.objects.link(light)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location = (0, 0, 5)
    camera.data.lens = 60
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    return scene


@pytest.fixture(scope="module")
def pipeline():
    p = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=256))
    yield p
    p.release()


@pytest.mark.parametrize("kind", list(LIGHTS))
def test_direct_light_matches_cycles(kind, pipeline):
    scene = build_plane_scene(kind)
    reference = render_cycles_passes(scene, passes=("DiffDir", "DiffCol"), samples=SAMPLES,
                                     pixel_filter_width=0.01, max_bounces=0)
    cycles = reference["DiffDir"] * reference["DiffCol"]
    ours = pipeline.render(extract_scene(bpy.context.evaluated_depsgraph_get())).passes["direct"]
    luminance = cycles.mean(axis=2)
    lit = luminance > 0.2 * luminance.max()
    relative = np.abs(ours - cycles)[lit] / np.maximum(cycles[lit], 1e-9)
    error = float(relative.mean())
    ratio = float(ours[lit].sum() / cycles[lit].sum())
    print(f"\n{kind}: mean relative error {error * 100:.2f}% over {lit.sum()} lit pixels, "
          f"ours/Cycles {ratio:.4f}, Cycles {SAMPLES} samples at {SIZE}x{SIZE}")
    assert lit.sum() > SIZE * SIZE / 10
    assert error < 0.03
