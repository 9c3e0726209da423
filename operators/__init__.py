"""User actions: the comparison with Cycles."""
from . import compare

MODULES = (compare,)
"""The modules with register()/unregister(), in registration order."""
