"""Everything that touches bpy: scene extraction, properties, the engine, its overlays and
panels, the Cycles reference."""
from . import engine, overlay, properties, ui

MODULES = (properties, engine, overlay, ui)


def register_addon():
    for module in MODULES:
        module.register()


def unregister_addon():
    for module in reversed(MODULES):
        module.unregister()
