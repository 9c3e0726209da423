"""Everything that touches bpy: scene extraction, properties, the Cycles reference."""
from . import properties

MODULES = (properties,)


def register_addon():
    for module in MODULES:
        module.register()


def unregister_addon():
    for module in reversed(MODULES):
        module.unregister()
