"""Everything that touches bpy: scene extraction, properties, the Cycles reference."""
from . import engine, properties, ui

MODULES = (properties, engine, ui)


def register_addon():
    for module in MODULES:
        module.register()


def unregister_addon():
    for module in reversed(MODULES):
        module.unregister()
