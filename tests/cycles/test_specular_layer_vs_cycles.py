"""The Principled BSDF's glossy layer against Cycles (docs/method.md, "Specular light"):
Cycles darkens the diffuse under the layer by what the layer reflects toward the viewer,
and the layer's own reflection bounces light on. A grey floor of the default Principled
settings under a sun keeps Cycles' direct light; a room whose only lit surface is a
rough gold floor gets Cycles' one bounce off it on its walls; a polished steel floor lit
at a slant sends its light on toward the far wall. Real bpy, Cycles and GL."""
import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.cycles_reference import render_cycles_passes  # noqa: E402
from lpv_preview.addon.render_scene import scene_to_render  # noqa: E402
from lpv_preview.gpu.pipeline import render_once  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

from ..leak_scenes import GREY, camera, diffuse, empty_scene, light, quad, room_shell  # noqa: E402

SIZE = (48, 36)


def principled(name, base, roughness=0.5, metallic=0.0):
    material = bpy.data.materials.new(name)
    node = material.node_tree.nodes["Principled BSDF"]
    node.inputs["Base Color"].default_value = (*base, 1.0)
    node.inputs["Roughness"].default_value = roughness
    node.inputs["Metallic"].default_value = metallic
    return material


def test_a_default_principled_floor_keeps_cycles_direct_light():
    """Measured: 1.010 of Cycles' Diffuse and Glossy Direct; 1.087 while the diffuse under
    the layer was not darkened."""
    scene = empty_scene(SIZE)
    quad("Floor", 6.0, 0.0, principled("floor", GREY))
    light("SUN", (0.0, 0.0, 5.0), (math.radians(40.0), 0.0, 0.0), energy=3.0)
    scene.camera = camera("Camera", (0.0, -4.0, 2.5), (0.0, 0.5, 0.0), lens=30.0)
    reference = render_cycles_passes(scene, ("DiffDir", "DiffCol", "GlossDir", "GlossCol"), samples=32,
                                     max_bounces=0)
    cycles = reference["DiffDir"] * reference["DiffCol"] + reference["GlossDir"] * reference["GlossCol"]
    frame = render_once(scene_to_render(scene, SIZE), Settings(width=SIZE[0], height=SIZE[1], bounces=1))
    ratio = frame.passes["direct"].mean() / cycles.mean()
    print(f"\nthe default Principled floor's direct light: {ratio:.3f} of Cycles'")
    assert 0.97 < ratio < 1.04


def room_lit_off_its_floor(floor):
    """Our one bounce and Cycles' (Diffuse Indirect times its colour) in a closed room whose
    floor, of the material `floor()` makes, is all a spot lights: the walls and ceiling see
    only the light the floor sends on."""
    scene = empty_scene(SIZE)
    room_shell(2.0, 2.0, 2.5, diffuse("walls", GREY), floor())
    light("SPOT", (0.0, 0.0, 2.4), energy=400.0, spot_size=math.radians(60.0))
    scene.camera = camera("Camera", (1.6, -1.6, 0.6), (-1.0, 1.5, 1.6), lens=16.0)
    reference = render_cycles_passes(scene, ("DiffInd", "DiffCol"), samples=64, max_bounces=1)
    frame = render_once(scene_to_render(scene, SIZE),
                        Settings(width=SIZE[0], height=SIZE[1], bounces=1, converge_sets=4))
    return frame.passes["indirect"].mean(axis=(0, 1)), (reference["DiffInd"] * reference["DiffCol"]).mean(axis=(0, 1))


def test_a_gold_floor_bounces_its_glossy_light_onto_the_walls():
    """The light a rough gold floor sends onto the walls, over what a white diffuse floor
    sends, against the same in Cycles: measured 1.082 of Cycles' (1.167 while the layer's
    light left the floor as if diffuse), none (0.000) while only the diffuse bounced. The
    colour is gold, as in Cycles'."""
    ours_white, cycles_white = room_lit_off_its_floor(lambda: diffuse("white", GREY))
    ours_gold, cycles_gold = room_lit_off_its_floor(lambda: principled("gold", (1.0, 0.78, 0.34), 0.5, 1.0))
    ratio = (ours_gold.mean() / ours_white.mean()) / (cycles_gold.mean() / cycles_white.mean())
    colour = (ours_gold / ours_gold.mean()) / (cycles_gold / cycles_gold.mean())
    print(f"\nthe walls' light off a gold floor over a white one: {ratio:.3f} of Cycles' "
          f"(r, g, b: {np.round(colour, 3)})")
    assert 0.8 < ratio < 1.3
    assert np.all(np.abs(colour - 1.0) < 0.1)


def walls_lit_off_a_slanted_floor(floor):
    """The far and the near side wall's one bounce, ours and Cycles', in a closed room whose
    floor (of the material `floor()` makes) a spot by the near wall lights at a slant, 49°
    from straight down, toward the far wall: the image's outer sixths, seen from the front
    wall."""
    scene = empty_scene(SIZE)
    room_shell(1.0, 1.0, 2.0, diffuse("walls", GREY), floor())
    light("SPOT", (-0.9, 0.0, 1.0), (0.0, math.radians(-49.0), 0.0), energy=200.0, spot_size=math.radians(40.0))
    scene.camera = camera("Camera", (0.0, -0.95, 1.0), (0.0, 1.0, 1.0), lens=10.0)
    reference = render_cycles_passes(scene, ("DiffInd", "DiffCol"), samples=64, max_bounces=1)
    cycles = (reference["DiffInd"] * reference["DiffCol"]).mean(axis=-1)
    ours = render_once(scene_to_render(scene, SIZE),
                       Settings(width=SIZE[0], height=SIZE[1], bounces=1, converge_sets=4)).passes["indirect"].mean(axis=-1)
    sixth = SIZE[0] // 6
    return {name: (image[:, -sixth:].mean(), image[:, :sixth].mean()) for name, image in (("ours", ours),
                                                                                          ("cycles", cycles))}


def test_a_polished_metal_floor_sends_its_light_along_the_mirror_direction():
    """A steel floor of roughness 0.2 sends the spot's light on toward the far wall, as
    Cycles does with its default Filter Glossy (docs/method.md, "Glossy VPLs"). Measured:
    the far wall 1.04 of Cycles' light and the near wall 1.16 (0.99 and 1.12 off a white
    diffuse floor); the far wall's light over the near wall's 6.06 where Cycles has 6.76.
    While the steel's light left the floor as if diffuse: 0.68, 3.34 and 1.38."""
    walls = {"diffuse": walls_lit_off_a_slanted_floor(lambda: diffuse("white", GREY)),
             "steel": walls_lit_off_a_slanted_floor(lambda: principled("steel", (0.9, 0.9, 0.9), 0.2, 1.0))}
    for floor, found in walls.items():
        (far, near), (cycles_far, cycles_near) = found["ours"], found["cycles"]
        print(f"\n{floor} floor: the far wall {far / cycles_far:.2f} of Cycles' light, the near wall "
              f"{near / cycles_near:.2f}; far over near {far / near:.2f} (Cycles {cycles_far / cycles_near:.2f})")
        assert 0.85 < far / cycles_far < 1.2 and 0.85 < near / cycles_near < 1.35
    (far, near), (cycles_far, cycles_near) = walls["steel"]["ours"], walls["steel"]["cycles"]
    assert far / near > 0.8 * cycles_far / cycles_near
