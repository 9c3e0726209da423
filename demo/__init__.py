"""Built-in demo scenes, built with bpy: `build("cornell")`, `export_npz("city", path)`."""
import bpy

from ..addon.extract import extract_scene, render_resolution
from ..gpu.errors import LPVError
from ..gpu.sweep import store_cycles_indirect, with_lights
from .atrium import build_atrium
from .builder import replace_lights
from .city import build_city
from .cornell import build_cornell_box

SCENES = {"cornell": build_cornell_box, "atrium": build_atrium, "city": build_city}


def build(name, **params):
    """Reset Blender to an empty file, build the demo scene `name` and return the bpy scene."""
    if name not in SCENES:
        raise LPVError(f"Unknown demo scene '{name}'; choose one of {', '.join(SCENES)}.")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return SCENES[name](**params)


def export_npz(name, path, lights=None, light_kind="point", cycles_samples=None, cycles_width=None, **params):
    """Build the demo scene `name`, extract it and save it to `path` for `Scene.load`.

    With `lights`, its lights are replaced by that many of `light_kind` (gpu/sweep.py
    `with_lights`) in Blender too. With `cycles_samples`, its Cycles one-bounce indirect
    image at `cycles_width` pixels across (the scene's aspect) is stored beside it for
    sweeps on machines without Cycles (gpu/sweep.py `stored_cycles_indirect`).
    Returns the extracted `Scene`.
    """
    bpy_scene = build(name, **params)
    scene = extract_scene(bpy.context.evaluated_depsgraph_get())
    if lights:
        replace_lights(bpy_scene, with_lights(scene, lights, light_kind).lights)
        scene = extract_scene(bpy.context.evaluated_depsgraph_get())
    scene.save(path)
    if cycles_samples:
        from ..addon.cycles_reference import ReferenceCache, cycles_reference
        size = render_resolution(bpy_scene, cycles_width)
        reference = cycles_reference(bpy_scene, "one_bounce", cycles_samples, 0, size, ReferenceCache())
        store_cycles_indirect(path, reference.indirect, cycles_samples)
    return scene
