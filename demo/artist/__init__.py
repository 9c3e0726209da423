"""The artist-scene suite: scenes built in bpy the way an artist builds them (factory
startup file, primitives, modifiers, Principled BSDF materials, node worlds), so the
renderer and its benchmark (`bench --artist`) meet what users make, not only our own
quad-grid demo scenes.

Each scene is the module of its name here, whose `build(resolution)` starts from
Blender's factory startup file (not an empty one) and returns the bpy scene. Importing
this package does not import bpy.
"""

ARTIST_SCENES = ("default_cube", "hdri_product", "sky_interior", "noon_exterior", "world_only", "studio_materials",
                 "area_room", "sunlit_foliage")
"""The suite, in the order the benchmark reports it."""

GI_ROOMS = ("window_room", "sunlit_courtyard", "furnished_room", "small_lights_room")
"""Rooms built the same way for the full-GI benchmark (scripts/full_gi_rooms.py) beside the
Cornell box and the suite's rooms: a sun through one window, a courtyard open to the sky,
a room of many objects and a room of many small lights."""
