"""Alpha and transmission against Cycles (issue 31, deliverable 3).

A diffuse floor lit by a sun from straight above, seen from above, with a card between
the sun and the floor: an Alpha-0 card neither shows nor shadows; a card cut out by a
checker image's alpha (a leaf's holes) lets light through its holes; a glass pane (IOR 1:
no refraction, no reflection, the thin sheet the preview draws) shows the floor tinted.
Tiny images, few samples; Cycles renders everything (its bounces too), the preview its
combined image.
"""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import render_cycles_passes  # noqa: E402
from lpv_preview.addon.extract import extract_scene  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

SIZE = 32
SAMPLES = 32
FLOOR_ALBEDO = (0.8, 0.8, 0.8)
CENTRE = slice(SIZE // 2 - 4, SIZE // 2 + 4)  # within the card's shadow and view (camera: 1.5 m half-width)
EDGE = slice(1, 5)                            # the floor beside it, lit
GLASS_TINT = (0.9, 0.3, 0.15)
CONVERGED_SETS = 8


def principled(name, colour, **inputs):
    material = bpy.data.materials.new(name)
    node = material.node_tree.nodes["Principled BSDF"]
    node.inputs["Base Color"].default_value = (*colour, 1.0)
    node.inputs["Roughness"].default_value = 1.0
    node.inputs["Specular IOR Level"].default_value = 0.0  # purely diffuse, as the preview models
    for name, value in inputs.items():
        node.inputs[name].default_value = value
    return material, node


def plane(name, half, height, material, camera_sees=True):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(-half, -half, height), (half, -half, height), (half, half, height), (-half, half, height)],
                     [], [(0, 1, 2, 3)])
    mesh.uv_layers.new(name="UVMap").uv.foreach_set("vector", [0, 0, 1, 0, 1, 1, 0, 1])
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.visible_camera = camera_sees
    bpy.context.scene.collection.objects.link(obj)
    return obj


def floor_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    plane("floor", 2.0, 0.0, principled("floor", FLOOR_ALBEDO)[0])
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy, sun.data.angle = 3.0, 0.0
    scene.collection.objects.link(sun)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location, camera.data.lens = (0, 0, 5), 60
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    return scene


def checker_alpha_image(cells=4):
    """A leaf-like mask: a checker of opaque and clear cells (alpha 1 and 0)."""
    image = bpy.data.images.new("leaf", cells, cells, alpha=True)
    alpha = (np.add.outer(np.arange(cells), np.arange(cells)) % 2).astype(np.float32)
    pixels = np.zeros((cells, cells, 4), np.float32)
    pixels[..., 1], pixels[..., 3] = 0.6, alpha
    image.pixels.foreach_set(pixels.ravel())
    return image


def add_card(kind):
    if kind == "alpha_0":
        material, _ = principled("card", (0.2, 0.7, 0.2), Alpha=0.0)
        plane("card", 0.5, 1.0, material)
    elif kind == "opaque":
        material, _ = principled("card", (0.2, 0.7, 0.2))
        plane("card", 0.5, 1.0, material, camera_sees=False)
    elif kind == "leaf":
        material, node = principled("card", (0.2, 0.7, 0.2))
        texture = material.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image, texture.interpolation = checker_alpha_image(), "Closest"
        material.node_tree.links.new(texture.outputs["Alpha"], node.inputs["Alpha"])
        plane("card", 0.5, 1.0, material, camera_sees=False)
    elif kind == "glass":
        material, _ = principled("glass", GLASS_TINT, **{"Transmission Weight": 1.0, "IOR": 1.0, "Roughness": 0.0})
        # high above the floor, the sun from aside: the pane is seen against the floor, its shadow off the image
        plane("glass", 0.4, 2.5, material)
        bpy.data.objects["sun"].rotation_euler = (0.0, 0.9, 0.0)


@pytest.fixture(scope="module")
def pipeline():
    p = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=256, converge_sets=CONVERGED_SETS))
    yield p
    p.release()


def render_both(kind, pipeline):
    scene = floor_scene()
    add_card(kind)
    cycles = render_cycles_passes(scene, passes=("Combined",), samples=SAMPLES, pixel_filter_width=0.01)["Combined"]
    extracted = extract_scene(bpy.context.evaluated_depsgraph_get())
    ours = pipeline.render_converged(extracted)
    return cycles, ours.passes["combined"], extracted


def region_mean(image, rows=CENTRE, columns=CENTRE):
    return image[rows, columns].mean(axis=(0, 1))


def test_alpha_zero_card_neither_shows_nor_shadows(pipeline):
    cycles, ours, extracted = render_both("alpha_0", pipeline)
    assert extracted.dropped.get("clear") == 2  # the card's two triangles: gone from every pass
    ratio = region_mean(ours).mean() / region_mean(cycles).mean()
    assert ratio == pytest.approx(1.0, abs=0.04), ratio
    assert region_mean(ours).mean() == pytest.approx(region_mean(ours, EDGE, EDGE).mean(), rel=0.03)


def test_leaf_texture_lets_light_through_its_holes(pipeline):
    cycles_opaque, ours_opaque, _ = render_both("opaque", pipeline)
    cycles, ours, extracted = render_both("leaf", pipeline)
    assert extracted.alpha_layers is not None and extracted.images[0].pixels.shape[2] == 4
    lit = region_mean(cycles, EDGE, EDGE).mean()
    shadow, opaque_shadow = region_mean(cycles).mean(), region_mean(cycles_opaque).mean()
    ours_shadow, ours_opaque_shadow = region_mean(ours).mean(), region_mean(ours_opaque).mean()
    assert opaque_shadow < 0.1 * lit and ours_opaque_shadow < 0.1 * lit  # an opaque card's shadow is dark
    assert 0.3 * lit < shadow < 0.7 * lit  # Cycles: about half the light passes the holes
    assert ours_shadow == pytest.approx(shadow, rel=0.1), (ours_shadow, shadow, lit)


def test_glass_pane_shows_the_floor_tinted(pipeline):
    cycles, ours, extracted = render_both("glass", pipeline)
    assert extracted.transmission is not None and not any("transmission" in entry and "black" in entry
                                                          for entry in extracted.approximated_materials)
    seen_through, beside = region_mean(ours), region_mean(ours, EDGE, CENTRE)
    cycles_through = region_mean(cycles)
    # one crossing of a Principled BSDF's transmission tints by the base colour's square root
    np.testing.assert_allclose(seen_through / beside, np.sqrt(GLASS_TINT), rtol=0.05, atol=0.02)
    np.testing.assert_allclose(seen_through, cycles_through, rtol=0.06, atol=0.01)
