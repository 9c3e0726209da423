"""LPV Preview: indirect light in milliseconds, measured against Cycles.

Blender loads this file as the extension; it only wires `addon/` and `operators/` in.
The command line (`python -m lpv_preview`) and the tests import `gpu/` without bpy, so
nothing here imports bpy at module level.
"""


def register():
    from .addon import register_addon
    from .operators import register_operators
    register_addon()
    register_operators()


def unregister():
    from .addon import unregister_addon
    from .operators import unregister_operators
    unregister_operators()
    unregister_addon()
