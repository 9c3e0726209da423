"""Built-in demo scenes, built with bpy: `build("cornell")`, `export_npz("city", path)`.

Each scene is the module of its name here, whose `build()` makes it in the current
Blender file. Importing this package does not import bpy, so the command line can list
the scenes where Blender is missing (the GPU machine).
"""
import importlib

from ..gpu.errors import LPVError
from .artist import ARTIST_SCENES, GI_ROOMS

SCENES = ("cornell", "atrium", "city", "particles")
ALL_SCENES = SCENES + ARTIST_SCENES + GI_ROOMS
"""Every scene `build` makes: the demo scenes, the artist suite and the full-GI rooms."""
LAMP_SCENES = ("cornell", "atrium", "city")
"""The demo scenes lit by lamps, whose maps Table 1 compares (the particle room has none)."""

TRIANGLE_RANGES = {"atrium": (5_000, 10_000_000), "city": (500, 10_000_000)}
"""The triangle counts the scenes that take one can be built with: from about their
coarsest detail (4,436 and 452 triangles) to where Blender and the extracted Scene hold
some 6 GB (about 600 bytes a triangle). The Cornell box's count is fixed."""


def check_triangles(name, triangles):
    """Refuse a triangle count the demo scene `name` cannot be built with."""
    if name not in TRIANGLE_RANGES:
        raise LPVError(f"The demo scene '{name}' has a fixed triangle count; give a triangle count only for "
                       f"{' or '.join(TRIANGLE_RANGES)}.")
    low, high = TRIANGLE_RANGES[name]
    if not low <= triangles <= high:
        raise LPVError(f"The demo scene '{name}' is built with {low:,} to {high:,} triangles, not {triangles:,}; "
                       f"choose a triangle count in that range.")


def build(name, **params):
    """Reset Blender to an empty file, build the demo scene `name` and return the bpy scene;
    an artist scene (ARTIST_SCENES, GI_ROOMS) starts from Blender's factory startup file instead."""
    if name not in ALL_SCENES:
        raise LPVError(f"Unknown demo scene '{name}'; choose one of {', '.join(ALL_SCENES)}.")
    if "triangles" in params:
        check_triangles(name, params["triangles"])
    if name in ARTIST_SCENES + GI_ROOMS:
        return importlib.import_module(f".artist.{name}", __name__).build(**params)
    import bpy
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return importlib.import_module(f".{name}", __name__).build(**params)


def extracted(name, **params):
    """The demo scene `name` built and extracted as a gpu Scene."""
    from ..addon.render_scene import scene_to_render
    return scene_to_render(build(name, **params))


def cycles_indirect(bpy_scene, samples, width=None, kind="one_bounce"):
    """A built scene's Cycles indirect image (top row first) of the reference `kind`
    (one_bounce, full_gi) at `width` pixels across (None: its own render width) with the
    scene's own aspect, rendered or taken from the reference cache."""
    from ..addon.cycles_reference import ReferenceCache, cycles_reference
    from ..addon.extract import render_resolution
    size = render_resolution(bpy_scene, width)
    return cycles_reference(bpy_scene, kind, samples, 0, size, ReferenceCache()).indirect


def export_npz(name, path, lights=None, light_kind="point", cycles_samples=None, cycles_width=None, **params):
    """Build the demo scene `name`, extract it and save it to `path` (gpu/scene_file.py).

    With `lights`, its lights are replaced by that many of `light_kind` (gpu/scene_edits.py
    `with_lights`) in Blender too. With `cycles_samples`, its Cycles one-bounce indirect
    image at `cycles_width` pixels across (the scene's aspect), and its full-GI one, are
    stored beside it for sweeps on machines without Cycles (gpu/scene_file.py
    `stored_cycles_indirect`).
    Returns the extracted `Scene`.
    """
    from ..addon.render_scene import scene_to_render
    from ..gpu.scene_edits import with_lights
    from ..gpu.scene_file import save_scene, store_cycles_indirect
    from .builder import replace_lights
    bpy_scene = build(name, **params)
    scene = scene_to_render(bpy_scene)
    if lights:
        replace_lights(bpy_scene, with_lights(scene, lights, light_kind).lights)
        scene = scene_to_render(bpy_scene)
    save_scene(scene, path)
    if cycles_samples:
        store_cycles_indirect(path, cycles_indirect(bpy_scene, cycles_samples, cycles_width), cycles_samples,
                              cycles_indirect(bpy_scene, cycles_samples, cycles_width, "full_gi"))
    return scene
