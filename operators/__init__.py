"""User actions: the comparison with Cycles and the settings presets."""
from . import compare, presets

MODULES = (compare, presets)
"""The modules with register()/unregister(), in registration order."""
