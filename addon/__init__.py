"""Everything that touches bpy: scene extraction, properties, the engine, its overlays and
panels, the Cycles references and the comparison. Its modules load when asked for, so
that a process can unpickle one of its names (a Cycles sample worker's renderer) before
bpy is imported."""
import re
import sys

BLENDER_SCRIPTS = re.compile(r"[/\\]bpy[/\\][0-9.]+[/\\]scripts")
"""The folders of Blender's own scripts, which `import bpy` puts on sys.path."""

if "bpy" not in sys.modules:
    # a process that inherited the sys.path of one that imported bpy (a Dask worker) would
    # find the scripts' package `bpy` before the module: the module's folder goes first
    sys.path.sort(key=lambda folder: bool(BLENDER_SCRIPTS.search(folder)))


def registered_modules():
    """The modules with register()/unregister(), in registration order."""
    from . import engine, overlay, properties, ui
    return properties, engine, overlay, ui
