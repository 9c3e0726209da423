"""An atrium in the manner of Crytek's Sponza: a long courtyard open to the sky, two
storeys of columns and arches along both long sides, galleries behind them, and coloured
cloth banners hanging in the upper arches, lit by the sun.

Every part is a quad grid whose resolution follows one detail level; the level is chosen
so the whole scene has the requested number of triangles.
"""
import math

import bpy
import numpy as np

from .builder import MeshBuilder, add_camera, add_light, principled_material, rectangle_footprint, search_detail

STONE = (0.58, 0.52, 0.44)
FLOOR = (0.45, 0.40, 0.34)
BANNER_COLORS = {"red": (0.60, 0.05, 0.04), "green": (0.08, 0.40, 0.08),
                 "blue": (0.05, 0.10, 0.50), "yellow": (0.70, 0.55, 0.08)}

SPAN = 3.5  # column spacing along the courtyard
COLUMN_X = -14.0 + SPAN * np.arange(9)
ARCADE_Y = 5.0  # the column lines are at y = ±ARCADE_Y
ARCH_DEPTH = 0.9
HALF_LENGTH = 15.5  # end walls at x = ±HALF_LENGTH
OUTER_Y = 8.0  # gallery back walls at y = ±OUTER_Y
TOP = 14.0


class Storey:
    """One level of the arcade: plinths, columns, capitals, arches and the slab above."""

    def __init__(self, floor, column_top, radius, block, slab_top):
        self.floor = floor
        self.column_top = column_top
        self.radius = radius
        self.block = block  # plinth and capital: width and height
        self.spring = column_top + block[1]
        self.arch_radius = SPAN / 2 - block[0] / 2
        self.slab_top = slab_top
        self.slab_bottom = slab_top - 0.3
        self.wall_top = self.slab_bottom


STOREYS = (Storey(0.0, 4.0, 0.32, (0.9, 0.3), 6.5), Storey(6.5, 9.6, 0.26, (0.8, 0.25), 12.1))


def build(triangles=250_000, resolution=(640, 360)):
    """Build the atrium into the current scene with about `triangles` triangles (the
    coarsest level has about 4,400) and return the scene."""
    scene = bpy.context.scene
    detail = search_detail(lambda d: _geometry(d, evaluate=False)[1], triangles, low=0.2)
    parts, _ = _geometry(detail, evaluate=True)
    stone = principled_material("Atrium stone", STONE)
    floor = principled_material("Atrium floor", FLOOR)
    banners = [principled_material(f"Banner {name}", color, roughness=0.9) for name, color in BANNER_COLORS.items()]
    materials = {"Floor": [floor], "Walls": [stone], "Columns": [stone], "Arches": [stone], "Banners": banners}
    for name, builder in parts.items():
        builder.to_object(f"Atrium {name.lower()}", materials[name], scene.collection)
    add_light(scene, "Sun", "SUN", (0.0, 0.0, 30.0), 5.0, color=(1.0, 0.95, 0.88), aim=(0.3, -0.25, -0.92),
              angle=math.radians(0.5))
    add_camera(scene, (-14.8, 0.0, 2.5), (14.0, 0.0, 7.5), lens=18.0, resolution=resolution, clip_end=200.0)
    return scene


def _geometry(detail, evaluate):
    """The atrium's parts as MeshBuilders at `detail`, and their total triangle count."""
    def steps(base, minimum=1):
        return max(minimum, round(base * detail))

    parts = {name: MeshBuilder(evaluate) for name in ("Floor", "Walls", "Columns", "Arches", "Banners")}
    parts["Floor"].parallelogram((-HALF_LENGTH, -OUTER_Y, 0), (2 * HALF_LENGTH, 0, 0), (0, 2 * OUTER_Y, 0),
                                 steps(32), steps(16))
    _walls(parts["Walls"], steps)
    for storey in STOREYS:
        for side in (1, -1):
            _arcade(parts["Columns"], parts["Arches"], storey, side, steps)
    _banners(parts["Banners"], STOREYS[1], steps)
    return parts, sum(builder.triangle_count for builder in parts.values())


def _walls(walls, steps):
    """Gallery back walls, end walls, the slabs over each storey and the parapets, all
    facing into the building."""
    length, width = 2 * HALF_LENGTH, 2 * OUTER_Y
    top_of_galleries = STOREYS[-1].slab_top
    walls.parallelogram((-HALF_LENGTH, OUTER_Y, 0), (length, 0, 0), (0, 0, top_of_galleries), steps(32), steps(12))
    walls.parallelogram((HALF_LENGTH, -OUTER_Y, 0), (-length, 0, 0), (0, 0, top_of_galleries), steps(32), steps(12))
    walls.parallelogram((-HALF_LENGTH, -OUTER_Y, 0), (0, width, 0), (0, 0, TOP), steps(16), steps(14))
    walls.parallelogram((HALF_LENGTH, OUTER_Y, 0), (0, -width, 0), (0, 0, TOP), steps(16), steps(14))
    inner_face = ARCADE_Y - ARCH_DEPTH / 2
    for side in (1, -1):
        slab_y = side * (inner_face + OUTER_Y) / 2
        for storey in STOREYS:
            walls.prism(rectangle_footprint((0, slab_y), length, OUTER_Y - inner_face), storey.slab_bottom,
                        storey.slab_top, steps(16), 1, cap_steps=(steps(16), steps(2)))
        parapet_y = side * (inner_face + 0.15)
        walls.prism(rectangle_footprint((0, parapet_y), length, 0.3), top_of_galleries, TOP, steps(16), steps(2),
                    faces=("sides", "top"), cap_steps=(steps(16), 1))


def _arcade(columns, arches, storey, side, steps):
    """One side's columns (with plinth and capital) and the arches between them."""
    y = side * ARCADE_Y
    segments, rings = steps(24, 8), steps(6, 2)
    width, height = storey.block
    for x in COLUMN_X:
        columns.prism(rectangle_footprint((x, y), width, width), storey.floor, storey.floor + height,
                      faces=("sides", "top"))
        columns.surface(segments, rings, _cylinder((x, y), storey.radius, storey.floor + height, storey.column_top),
                        closed_u=True)
        columns.prism(rectangle_footprint((x, y), width, width), storey.column_top, storey.spring,
                      faces=("sides", "bottom"))
    for left, right in zip(COLUMN_X[:-1], COLUMN_X[1:]):
        _arch(arches, (left + right) / 2, y, storey, steps)


def _cylinder(center, radius, bottom, top):
    def point_at(u, v):
        angle = 2 * math.pi * u
        return np.stack([center[0] + radius * np.cos(angle), center[1] + radius * np.sin(angle),
                         bottom + v * (top - bottom)], axis=-1)
    return point_at


def _arch(arches, x, y, storey, steps):
    """A semicircular arch: its underside, and the wall around it on both faces of the
    arcade, each face split where the arch's rays meet the wall's corners so the
    corners are exact."""
    radius, spring, half_span = storey.arch_radius, storey.spring, SPAN / 2
    arc_segments, radial_segments = steps(16, 6), steps(3)
    front, back = y - ARCH_DEPTH / 2, y + ARCH_DEPTH / 2

    def underside(u, v):
        angle = math.pi * u
        return np.stack([x + radius * np.cos(angle), front + v * (back - front), spring + radius * np.sin(angle)],
                        axis=-1)
    arches.surface(arc_segments, 2, underside)
    rise = storey.wall_top - spring
    corner = math.atan2(rise, half_span)
    pieces = ((0.0, corner), (corner, math.pi - corner), (math.pi - corner, math.pi))
    for face_y in (front, back):
        # Angles running up face +y; each face must face away from the arcade's middle.
        facing = 1 if face_y > y else -1
        for start, end in pieces:
            count = max(1, round(arc_segments * (end - start) / math.pi))
            if facing < 0:
                start, end = end, start
            arches.surface(count, radial_segments, _spandrel(x, face_y, spring, radius, half_span, rise, start, end))


def _spandrel(x, face_y, spring, radius, half_span, rise, start, end):
    """The wall between the arch (angles start..end) and the rectangle around it."""
    def point_at(u, v):
        angle = start + u * (end - start)
        cos, sin = np.cos(angle), np.sin(angle)
        with np.errstate(divide="ignore"):
            reach = np.minimum(np.where(np.abs(cos) > 1e-12, half_span / np.abs(cos), np.inf),
                               np.where(sin > 1e-12, rise / np.maximum(sin, 1e-12), np.inf))
        distance = radius + v * (reach - radius)
        return np.stack([x + distance * cos, np.full_like(u, face_y), spring + distance * sin], axis=-1)
    return point_at


def _banners(banners, storey, steps):
    """A banner in every upper arch on both sides, waving gently, facing the courtyard,
    colours taking turns."""
    top, bottom, width = storey.wall_top - 0.4, storey.floor + 0.5, 2.0
    offset = ARCADE_Y - ARCH_DEPTH / 2 - 0.25
    index = 0
    for side in (1, -1):
        for left, right in zip(COLUMN_X[:-1], COLUMN_X[1:]):
            center = (left + right) / 2
            banners.surface(steps(16), steps(28), _banner(center, side * offset, side, width, bottom, top, index),
                            material=index % len(BANNER_COLORS))
            index += 1


def _banner(center, y, side, width, bottom, top, phase):
    """A cloth hanging from a straight top edge: waves grow towards the free bottom."""
    def point_at(u, v):
        across = (u - 0.5) * width * side  # u runs so the cloth faces the courtyard
        hanging = 1.0 - v
        wave = 0.12 * hanging * np.sin(2 * math.pi * (1.5 * u + 0.6 * v) + phase)
        return np.stack([center + across, y + side * wave, bottom + v * (top - bottom)], axis=-1)
    return point_at
