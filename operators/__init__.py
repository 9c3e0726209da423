"""User actions: the comparison with Cycles."""
from . import compare

MODULES = (compare,)


def register_operators():
    for module in MODULES:
        module.register()


def unregister_operators():
    for module in reversed(MODULES):
        module.unregister()
