"""A measuring scene, not a demo: a floor, a plate above it that only the lights see, and
one light of a given size straight above the plate's edge, seen from above by an
orthographic camera; and how wide the penumbra of the edge's shadow is in an image of it
(scripts/penumbra_widths.py, tests/blender/test_soft_shadows.py,
tests/cycles/test_soft_shadows_vs_cycles.py).

The plate covers x < 0 at PLATE_HEIGHT; its edge runs along y, so the shadow's edge is a
column of the image and every row is one measurement of the same profile.
"""
import bpy
import numpy as np

from .builder import MeshBuilder, add_camera, add_light, principled_material

FLOOR_HALF = 4.0
PLATE_HEIGHT = 1.0
LIGHT_HEIGHT = 2.5
VIEW_WIDTH = 2.0  # the camera sees x in [-1, 1] m


def build(kind, size, width=128, height=8, shape="SQUARE"):
    """Build the scene into an empty file; `size` is the light's: a sun's angle (radians),
    a point or spot light's radius, an area light's side (or diameter). Returns the scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    grey = principled_material("grey", (0.5, 0.5, 0.5), roughness=1.0)
    floor = MeshBuilder()
    floor.parallelogram((-FLOOR_HALF, -FLOOR_HALF, 0.0), (2 * FLOOR_HALF, 0, 0), (0, 2 * FLOOR_HALF, 0))
    floor.to_object("Floor", [grey], scene.collection)
    plate = MeshBuilder()
    plate.parallelogram((-FLOOR_HALF, -FLOOR_HALF, PLATE_HEIGHT), (FLOOR_HALF, 0, 0), (0, 2 * FLOOR_HALF, 0))
    plate_object = plate.to_object("Plate", [grey], scene.collection)
    plate_object.visible_camera = False
    settings = {"SUN": {"angle": size}, "AREA": {"shape": shape, "size": size, "size_y": size}}.get(
        kind, {"shadow_soft_size": size})
    aim = (0.0, 0.0, -1.0) if kind == "SUN" else (0.0, 0.0, 0.0)
    add_light(scene, "Light", kind, (0.0, 0.0, LIGHT_HEIGHT), 3.0 if kind == "SUN" else 500.0, aim=aim,
              **settings)
    camera = add_camera(scene, (0.0, 0.0, 5.0), (0.0, 0.0, 0.0), resolution=(width, height))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = VIEW_WIDTH
    return scene


def show_plate(shown):
    """Let the plate cast its shadow, or take it out of the render (the unshadowed image)."""
    plate = bpy.data.objects["Plate"]
    plate.hide_render = plate.hide_viewport = not shown  # the viewport's depsgraph, which extraction reads


def edge_profile(shadowed, unshadowed):
    """The share of the light that reaches the floor along x (one value per image column,
    the rows averaged): the shadowed image over the unshadowed one."""
    lit = np.asarray(unshadowed, dtype=np.float64).mean(axis=-1).mean(axis=0)
    return np.asarray(shadowed, dtype=np.float64).mean(axis=-1).mean(axis=0) / np.maximum(lit, 1e-12)


def penumbra_width(profile, low=0.1, high=0.9):
    """The distance in metres between where `profile` (edge_profile) first rises past `low`
    and first past `high`, interpolated between columns: the penumbra's 10-90 % width."""
    x = (np.arange(len(profile)) + 0.5) / len(profile) * VIEW_WIDTH - VIEW_WIDTH / 2

    def crossing(level):
        above = np.nonzero(profile >= level)[0]
        if not len(above) or above[0] == 0:
            return x[0] if len(above) else x[-1]
        i = above[0]
        t = (level - profile[i - 1]) / max(profile[i] - profile[i - 1], 1e-12)
        return x[i - 1] + t * (x[i] - x[i - 1])
    return float(crossing(high) - crossing(low))
