"""Where the grids of the indirect light lie: cubic cells, fitted to a box, and nested
levels (cascades) around what the camera sees, so one far object or a huge ground plane
never decides the size of the cells the camera looks at."""
import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Grid:
    """Cubic cells: cell (i, j, k) spans origin + [i, i+1] * cell_size, and so on."""

    origin: tuple
    cell_size: float
    size: int

    def coarser(self, factor):
        """The grid over the same box with cells `factor` times as wide."""
        return Grid(self.origin, self.cell_size * factor, max(1, self.size // factor))


GRID_ANCHOR_STEPS = 16
"""The grid's centre follows the box's centre in steps of about 1/GRID_ANCHOR_STEPS of a
cell (a power of two), so it moves with the scene when the scene moves (the picture
does not depend on where in the world the scene stands) and not when the box changes
by less."""


def fit_grid(bounds, size, shift=0.0):
    """A grid of size^3 cubic cells around the box `bounds` with a cell of margin on every
    side, moved by `shift` cells along every axis.

    The cell size is snapped to quarter octaves and the centre to GRID_ANCHOR_STEPS of a
    cell, so the grid does not swim when the box changes slightly; boxes whose sizes
    differ by a power of two get cells that differ by exactly that power.
    """
    low, high = (np.asarray(b, dtype=np.float64) for b in bounds)
    extent = max(float(np.max(high - low)), 1e-30)
    cell = extent / max(size - 2, 1)
    cell = 2.0 ** (math.ceil(math.log2(cell) * 4) / 4)
    step = 2.0 ** math.floor(math.log2(cell / GRID_ANCHOR_STEPS))
    centre = np.round((low + high) / 2 / step) * step
    origin = centre - cell * (size // 2 - shift)
    return Grid(tuple(float(v) for v in origin), cell, size)


VIEW_LATTICE = 64
"""The grids are placed around the surface points of VIEW_LATTICE^2 pixels of the camera's
G-buffer (gpu/shade.py seen_points)."""
SEEN_SHARE = 0.96
"""The share of the surface points the camera sees (the middle one, along every axis)
that the coarsest level must cover; the rest are outliers such as the far horizon."""
CORE_SHARE = 0.5
"""The finest level covers twice the box of the middle CORE_SHARE of what the camera sees."""


def level_boxes(seen_points, bounds, max_levels):
    """The boxes of nested grid levels, each twice the one before, around the surface
    points the camera sees (`seen_points`, (k, 3), the G-buffer sampled); the scene's
    `bounds` when it sees none.

    The finest level covers the core of the view (where most pixels look), the coarsest
    the view's spread (SEEN_SHARE), as few levels as that takes and at most `max_levels`.
    All levels share one centre, so each nests inside the next (Kaplanyan & Dachsbacher
    2010, cascaded LPVs); a pixel looks up the finest level that holds it.
    """
    points = np.asarray(seen_points, dtype=np.float64).reshape(-1, 3)
    axes = np.ascontiguousarray(points[np.all(np.isfinite(points), axis=1)].T)
    count = axes.shape[1]
    if count < 8:
        return [tuple(np.asarray(b, dtype=np.float64) for b in bounds)]
    tail = (1.0 - SEEN_SHARE) / 2
    shares = (tail, (1 - CORE_SHARE) / 2, 0.5, (1 + CORE_SHARE) / 2, 1.0 - tail)
    ranks = {share: min(int(share * count), count - 1) for share in shares}
    axes = np.partition(axes, sorted(set(ranks.values())), axis=1)

    def quantile(share):
        return axes[:, ranks[share]]

    low, high, centre = quantile(tail), quantile(1.0 - tail), quantile(0.5)
    spread = float(np.max(np.maximum(high - centre, centre - low))) * 2
    core = float(np.max(quantile((1 + CORE_SHARE) / 2) - quantile((1 - CORE_SHARE) / 2))) * 2
    finest = max(min(max(core, spread / 2 ** (max_levels - 1)), spread), 1e-30)
    levels = 1
    while finest * 2 ** (levels - 1) < spread and levels < max_levels:
        levels += 1
    return [(centre - finest * 2 ** level / 2, centre + finest * 2 ** level / 2) for level in range(levels)]


KEEP_WITHIN_CELLS = 2.0
"""A camera move keeps the grids (and what they hold) while the placement it asks for has
the same levels and cells and a centre within this many cells of theirs."""


def keep_or_move(previous, placed):
    """`previous` grids where they still serve the placement `placed` (both level-major
    tuples of grids), else `placed`: a small camera move redoes no indirect light."""
    if previous is None or len(previous) != len(placed):
        return placed
    for old, new in zip(previous, placed):
        if old.cell_size != new.cell_size or old.size != new.size:
            return placed
        if np.max(np.abs(np.subtract(old.origin, new.origin))) > KEEP_WITHIN_CELLS * new.cell_size:
            return placed
    return previous
