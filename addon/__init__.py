"""Everything that touches bpy: scene extraction, properties, the engine, its overlays and
panels, the Cycles reference and the comparison."""
from . import engine, overlay, properties, ui

MODULES = (properties, engine, overlay, ui)
"""The modules with register()/unregister(), in registration order."""
