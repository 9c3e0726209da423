"""User actions: the comparison with Cycles, its reference cache and the settings presets."""
from . import cache, compare, presets

MODULES = (compare, cache, presets)
"""The modules with register()/unregister(), in registration order."""
