"""What softens a light's shadows (docs/method.md, "Soft shadows"): the uniforms of
shaders/soft_shadow.glsl, from the light's size and shape, and the Poisson taps of its
filter, shifted per pixel and per VPL set."""
import math

import numpy as np

from .vpl import concentric_square, poisson_disk_points

SHADOW_HARD, SHADOW_ROUND, SHADOW_SQUARE = 0, 1, 2
MAX_SHADOW_TAPS = 64  # shaders/soft_shadow.glsl MAX_SHADOW_TAPS
SEARCH_NEAR_SHARE = 0.25
"""A local light's blocker search reaches blockers down to this share of the receiver's
distance from the light: nearer ones, whose penumbra is over three times the light's size
wide, are missed at the penumbra's outer edge."""
LARGEST_SUN_ANGLE = math.radians(179.0)  # Blender allows 180 degrees, whose tangent is infinite


def light_extent(light):
    """(shape, facing, radius, axis_x, axis_y): how the light's emitting surface looks from
    a receiver. A point or spot light is a sphere and a sun a disc of directions, both
    `facing` every receiver with a disc of `radius` (a sun's: per unit of depth); an area
    light is a rectangle or ellipse whose half-extents are `axis_x`, `axis_y` (world
    vectors). A light of no size is SHADOW_HARD."""
    none = np.zeros(3)
    if light.kind == "AREA":
        right = np.cross(light.up, -light.direction)
        axis_x, axis_y = right * light.size[0] / 2, light.up * light.size[1] / 2
        if max(light.size) <= 0:
            return SHADOW_HARD, False, 0.0, none, none
        shape = SHADOW_ROUND if light.shape in ("DISK", "ELLIPSE") else SHADOW_SQUARE
        return shape, False, 0.0, axis_x, axis_y
    radius = math.tan(min(light.angle, LARGEST_SUN_ANGLE) / 2) if light.kind == "SUN" else light.radius
    return (SHADOW_ROUND if radius > 0 else SHADOW_HARD), True, float(max(radius, 0.0)), none, none


def shadow_pattern(taps):
    """`taps` Poisson-disc points (at most MAX_SHADOW_TAPS) as the concentric square's
    [-1, 1]^2 points that map onto them, padded to MAX_SHADOW_TAPS rows: the shader shifts
    them per pixel on the square (a toroidal shift keeps a Poisson set one) and maps them
    to the disc for a round light."""
    taps = min(taps, MAX_SHADOW_TAPS)
    disc = 2.0 * poisson_disk_points(taps, in_disk=True).astype(np.float64) - 1.0
    pattern = np.zeros((MAX_SHADOW_TAPS, 2), dtype=np.float32)
    pattern[:taps] = np.clip(concentric_square(disc), -1.0, 1.0)
    return pattern


def shadow_uniforms(light, taps, seed):
    """The uniforms of shaders/soft_shadow.glsl for `light` with a filter of `taps` taps
    (the blocker search takes half), shifted by VPL set `seed`."""
    shape, facing, radius, axis_x, axis_y = light_extent(light)
    return {"shadow_shape": shape, "shadow_facing": facing, "shadow_radius": radius,
            "shadow_axis_x": tuple(map(float, axis_x)), "shadow_axis_y": tuple(map(float, axis_y)),
            "shadow_search_scale": (1.0 - SEARCH_NEAR_SHARE) / SEARCH_NEAR_SHARE,
            "shadow_taps": min(taps, MAX_SHADOW_TAPS), "shadow_pattern": shadow_pattern(taps),
            "shadow_seed": int(seed) & 0xFFFFFFFF}
