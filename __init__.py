"""LPV Preview: indirect light in milliseconds, measured against Cycles.

Blender loads this file as the extension; it only wires `addon/` and `operators/` in.
The command line (`python -m lpv_preview`) and the tests import `gpu/` without bpy, so
nothing here imports bpy at module level.
"""


def _modules():
    from . import addon, operators
    return addon.registered_modules() + operators.MODULES


def register():
    for module in _modules():
        module.register()


def unregister():
    for module in reversed(_modules()):
        module.unregister()
