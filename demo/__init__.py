"""Built-in demo scenes, built with bpy: `build("cornell")`, `export_npz("city", path)`."""
import bpy

from ..addon.extract import extract_scene
from ..gpu.errors import LPVError
from .atrium import build_atrium
from .city import build_city
from .cornell import build_cornell_box

SCENES = {"cornell": build_cornell_box, "atrium": build_atrium, "city": build_city}


def build(name, **params):
    """Reset Blender to an empty file, build the demo scene `name` and return the bpy scene."""
    if name not in SCENES:
        raise LPVError(f"Unknown demo scene '{name}'; choose one of {', '.join(SCENES)}.")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return SCENES[name](**params)


def export_npz(name, path, **params):
    """Build the demo scene `name`, extract it and save it to `path` for `Scene.load`.

    Returns the extracted `Scene`.
    """
    build(name, **params)
    scene = extract_scene(bpy.context.evaluated_depsgraph_get())
    scene.save(path)
    return scene
