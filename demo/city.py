"""A procedural city: square blocks of box buildings on raised sidewalks between streets,
taller towards the centre, facades divided into wall and window panels, lit by a low sun.

The layout comes from a seeded generator, so a seed always gives the same city. The
triangle budget is met by the facade resolution (panels per metre); larger budgets also
get more blocks, so the panels do not shrink to slivers.
"""
import math

import bpy
import numpy as np

from .builder import MeshBuilder, add_camera, add_light, principled_material, rectangle_footprint, search_detail

FACADE_TINTS = ((0.60, 0.55, 0.50), (0.45, 0.45, 0.50), (0.70, 0.62, 0.50), (0.50, 0.35, 0.30), (0.65, 0.65, 0.65))
WINDOW = (0.08, 0.10, 0.12)
ROOF = (0.30, 0.30, 0.30)
SIDEWALK = (0.35, 0.34, 0.32)
ASPHALT = (0.12, 0.12, 0.13)
WINDOW_SLOT = len(FACADE_TINTS)
ROOF_SLOT = WINDOW_SLOT + 1

BLOCK = 40.0  # block side, metres
STREET = 14.0  # street width
LOTS = 2  # buildings per block side
CURB = 0.15  # sidewalk height
PANEL = 3.0  # facade panel size at detail 1, metres


def build(triangles=130_000, seed=7, resolution=(640, 360)):
    """Build the city into the current scene with about `triangles` triangles and return
    the scene."""
    scene = bpy.context.scene
    blocks = max(3, round(8 * (triangles / 130_000) ** 0.25))
    buildings = _layout(blocks, np.random.default_rng(seed))
    detail = search_detail(lambda d: _geometry(buildings, blocks, d, evaluate=False)[1], triangles, steps=30)
    parts, _ = _geometry(buildings, blocks, detail, evaluate=True)
    facade_materials = [principled_material(f"Facade {i}", tint) for i, tint in enumerate(FACADE_TINTS)]
    materials = {"Buildings": facade_materials + [principled_material("Window", WINDOW, roughness=0.2),
                                                  principled_material("Roof", ROOF)],
                 "Ground": [principled_material("Asphalt", ASPHALT), principled_material("Sidewalk", SIDEWALK)]}
    for name, builder in parts.items():
        builder.to_object(f"City {name.lower()}", materials[name], scene.collection)
    half = blocks * (BLOCK + STREET) / 2
    add_light(scene, "Sun", "SUN", (0.0, 0.0, 200.0), 4.0, color=(1.0, 0.93, 0.82), aim=(-0.55, 0.45, -0.45),
              angle=math.radians(0.5))
    # Above the street that runs along the city's near edge, looking across the blocks.
    add_camera(scene, (-0.35 * half, -half, 60.0), (0.1 * half, 0.3 * half, 0.0), lens=24.0,
               resolution=resolution, clip_end=8 * half + 500.0)
    return scene


def _layout(blocks, rng):
    """Buildings as (x, y, width, depth, height, tint) rows: LOTS x LOTS per block."""
    pitch = BLOCK + STREET
    lot = BLOCK / LOTS
    rows = []
    centers = (np.arange(blocks) - (blocks - 1) / 2) * pitch
    radius = blocks * pitch / 2
    for block_x in centers:
        for block_y in centers:
            downtown = 1.0 + 2.0 * math.exp(-(block_x ** 2 + block_y ** 2) / (0.5 * radius) ** 2)
            for i in range(LOTS):
                for j in range(LOTS):
                    x = block_x + (i - (LOTS - 1) / 2) * lot
                    y = block_y + (j - (LOTS - 1) / 2) * lot
                    width, depth = lot - rng.uniform(1.5, 5.0, size=2)
                    height = float(np.clip(rng.lognormal(math.log(15.0), 0.45) * downtown, 6.0, 150.0))
                    rows.append((x, y, width, depth, height, rng.integers(len(FACADE_TINTS))))
    return rows


def _geometry(buildings, blocks, detail, evaluate):
    """The city's buildings and ground as MeshBuilders at `detail`, with the total
    triangle count."""
    parts = {"Buildings": MeshBuilder(evaluate), "Ground": MeshBuilder(evaluate)}
    for x, y, width, depth, height, tint in buildings:
        _building(parts["Buildings"], x, y, width, depth, height, tint, detail)
    pitch = BLOCK + STREET
    extent = blocks * pitch + STREET
    grid = max(1, round(4 * blocks * detail))
    ground = parts["Ground"]
    ground.parallelogram((-extent / 2, -extent / 2, 0), (extent, 0, 0), (0, extent, 0), grid, grid, material=0)
    centers = (np.arange(blocks) - (blocks - 1) / 2) * pitch
    for block_x in centers:
        for block_y in centers:
            ground.prism(rectangle_footprint((block_x, block_y), BLOCK, BLOCK), 0.0, CURB, material=1,
                         faces=("sides", "top"))
    return parts, sum(builder.triangle_count for builder in parts.values())


def _building(builder, x, y, width, depth, height, tint, detail):
    """A box on the sidewalk: four facades of wall and window panels, and a flat roof."""
    corners = np.column_stack([rectangle_footprint((x, y), width, depth), np.full(4, CURB)])
    up = np.array([0.0, 0.0, height])
    rows = max(1, round(height * detail / PANEL))
    for start, end in zip(corners, np.roll(corners, -1, axis=0)):
        along = end - start
        columns = max(1, round(np.linalg.norm(along) * detail / PANEL))
        builder.parallelogram(start, along, up, columns, rows, lambda nu, nv: _facade_pattern(nu, nv, tint))
    builder.surface(1, 1, lambda u, v: corners[0] + up + u[..., None] * (corners[1] - corners[0])
                    + v[..., None] * (corners[3] - corners[0]), ROOF_SLOT)


def _facade_pattern(columns, rows, tint):
    """Every other panel of every other row is a window; the rest is wall."""
    column, row = np.meshgrid(np.arange(columns), np.arange(rows), indexing="ij")
    return np.where((column % 2 == 1) & (row % 2 == 1), WINDOW_SLOT, tint)
