"""The glossy reflection of direct light against Cycles (docs/method.md, "Specular
light"): a dark floor of roughness 0.3 (the Principled BSDF's default specular) under a
point light, seen at a slant, rendered by real Cycles and by our pipeline from the same
camera. Its highlight is where Cycles has it, and about as bright. And a chrome sphere
lit by the world alone (a colour, forest.exr) reflects it about as brightly as Cycles'.
"""
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import render_cycles_passes  # noqa: E402
from lpv_preview.addon.extract import extract_scene  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

from ..leak_scenes import camera, empty_scene, light, quad  # noqa: E402

SIZE = 48
SAMPLES = 32
BASE = (0.05, 0.05, 0.05)


def build_glossy_floor(roughness=0.3, metallic=0.0):
    scene = empty_scene((SIZE, SIZE))
    material = bpy.data.materials.new("glossy")
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (*BASE, 1.0)
    principled.inputs["Roughness"].default_value = roughness
    principled.inputs["Metallic"].default_value = metallic
    quad("floor", 4.0, 0.0, material)
    light("POINT", (0.0, 1.5, 1.5), energy=200.0)
    scene.camera = camera("camera", (0.0, -3.0, 2.0), (0.0, 0.0, 2.0 - 3.0 / np.tan(np.radians(60))), lens=35)
    return scene


@pytest.fixture(scope="module")
def pipeline():
    p = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=256))
    yield p
    p.release()


@pytest.mark.parametrize("roughness, metallic", [(0.3, 0.0), (0.3, 1.0)])
def test_a_glossy_floors_highlight_is_where_cycles_has_it(pipeline, roughness, metallic):
    scene = build_glossy_floor(roughness, metallic)
    reference = render_cycles_passes(scene, passes=("DiffDir", "DiffCol", "GlossDir", "GlossCol"), samples=SAMPLES,
                                     pixel_filter_width=0.01, max_bounces=0)
    cycles = (reference["DiffDir"] * reference["DiffCol"] + reference["GlossDir"] * reference["GlossCol"]).mean(axis=2)
    ours = pipeline.render(extract_scene(bpy.context.evaluated_depsgraph_get())).passes["direct"].mean(axis=2)
    peak, our_peak = (np.unravel_index(np.argmax(image), image.shape) for image in (cycles, ours))
    # the peak's neighbourhood, so one noisy pixel of Cycles' does not decide
    window = tuple(slice(max(c - 1, 0), c + 2) for c in peak)
    ratio = float(ours[window].mean() / cycles[window].mean())
    lit = cycles > 0.2 * cycles.max()
    overall = float(ours[lit].sum() / cycles[lit].sum())
    print(f"\nroughness {roughness}, metallic {metallic}: peak at {tuple(map(int, our_peak))} against Cycles' "
          f"{tuple(map(int, peak))}, its value ours/Cycles {ratio:.3f}, over the highlight {overall:.3f} "
          f"(Cycles {SAMPLES} samples at {SIZE}x{SIZE})")
    assert np.abs(np.subtract(our_peak, peak)).max() <= 3
    assert 0.7 < ratio < 1.3
    assert 0.7 < overall < 1.3


def build_chrome_sphere(world):
    """A chrome sphere (Metallic 1, Roughness 0.05) filling much of the view, lit by the
    world alone: a grey colour or Blender's forest.exr."""
    scene = empty_scene((SIZE, SIZE))
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.0)
    sphere = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    material = bpy.data.materials.new("chrome")
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Metallic"].default_value = 1.0
    principled.inputs["Roughness"].default_value = 0.05
    sphere.data.materials.append(material)
    scene.world = bpy.data.worlds.new("world")
    nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
    background = nodes["Background"]
    if world == "colour":
        background.inputs["Color"].default_value = (0.6, 0.7, 0.9, 1.0)
    else:
        texture = nodes.new("ShaderNodeTexEnvironment")
        # system_resource(..., path=...) answers "" for a file in bpy 5.0: join the folder's path
        texture.image = bpy.data.images.load(os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights",
                                                          "world", "forest.exr"))
        links.new(texture.outputs["Color"], background.inputs["Color"])
    scene.camera = camera("camera", (0.0, -4.0, 0.0), (0.0, 0.0, 0.0), lens=50.0)
    scene.render.film_transparent = True
    return scene


@pytest.mark.parametrize("world", ["colour", "forest"])
def test_a_chrome_sphere_reflects_the_world_as_cycles(pipeline, world):
    scene = build_chrome_sphere(world)
    reference = render_cycles_passes(scene, passes=("Combined",), samples=SAMPLES, pixel_filter_width=0.01,
                                     max_bounces=1)
    frame = pipeline.render(extract_scene(bpy.context.evaluated_depsgraph_get()))
    covered = frame.coverage > 0.99
    inside = covered & np.roll(covered, 1, 0) & np.roll(covered, -1, 0) & np.roll(covered, 1, 1) & \
        np.roll(covered, -1, 1)  # the sphere less its silhouette's pixels
    ours, cycles = frame.passes["combined"][inside].mean(), reference["Combined"][inside].mean()
    print(f"\nchrome sphere under the world {world}: mean ours {ours:.4f}, Cycles {cycles:.4f}, "
          f"ratio {ours / cycles:.3f} over {inside.sum()} pixels (Cycles {SAMPLES} samples at {SIZE}x{SIZE})")
    assert inside.sum() > SIZE * SIZE / 8
    assert 0.8 < ours / cycles < 1.2
