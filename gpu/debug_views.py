"""What the viewport overlays and the debug render passes show, from a frame's stages.

The overlays are data for Blender to draw (addon/overlay.py): the VPLs as points
coloured by flux, a slice through the LPV, each warped light's status map. The debug
passes are camera images beside Combined: the VPLs splatted where the camera sees them
(flux in W), and per pixel the warp status of the map texel that looks at its surface.
"""
import math
from dataclasses import dataclass

import moderngl
import numpy as np

from .context import dispatch, set_uniforms
from .shade import bind_gbuffer, draw_points, gbuffer_uniforms

STATUS_COLOURS = np.array([
    (0.0, 0.0, 0.0),     # no warped map sees it / background texel in the map overlay
    (0.10, 0.75, 0.20),  # converged
    (1.00, 0.80, 0.10),  # approximate
    (0.90, 0.10, 0.10),  # failed
    (0.85, 0.10, 0.85),  # missed: the texel found nothing where the camera sees a surface
], dtype=np.float32)
"""The warp status colours of the overlay and the Warp Status pass, by code."""

SLICE_OPACITY = 0.7


def display_levels(values, peak):
    """Linear values to 0..1 for an overlay drawn without the view transform: scaled by
    `peak`, then the square root, so a hundredth of the peak still shows as a tenth."""
    if peak <= 0 or not math.isfinite(peak):
        return np.zeros_like(values, dtype=np.float32)
    return np.sqrt(np.clip(values / peak, 0.0, 1.0)).astype(np.float32)


@dataclass
class VPLPoints:
    """Valid VPLs of every light: world positions (n, 3), their flux in W (n, 3) and
    RGBA display colours (n, 4) scaled by the brightest VPL."""

    positions: np.ndarray
    flux: np.ndarray
    colours: np.ndarray


def vpl_points(light_maps, origin=(0.0, 0.0, 0.0)):
    """The VPLPoints of `light_maps`, positions in world space (the maps' are relative to
    the scene's `origin`)."""
    positions, flux = [], []
    for vpls in (vpl_set.read() for maps in light_maps for vpl_set in maps.vpl_sets()):
        positions.append(vpls["position"][vpls["valid"]])
        flux.append(vpls["flux"][vpls["valid"]])
    positions = np.concatenate(positions) if positions else np.zeros((0, 3), np.float32)
    flux = np.concatenate(flux) if flux else np.zeros((0, 3), np.float32)
    colours = np.ones((len(flux), 4), dtype=np.float32)
    colours[:, :3] = display_levels(flux, float(flux.max()) if len(flux) else 0.0)
    return VPLPoints((positions + np.asarray(origin)).astype(np.float32), flux.astype(np.float32), colours)


@dataclass
class LPVSlice:
    """One layer of LPV cells: the quad's world corners (4, 3), counter-clockwise from
    the low-low corner, and its RGBA image (rows along the second in-plane axis, GL's
    bottom row first); `light` holds each cell's propagated intensity integrated over
    all directions (W, per colour)."""

    corners: np.ndarray
    image: np.ndarray
    light: np.ndarray


def lpv_slice(indirect, axis, position, world_origin=(0.0, 0.0, 0.0)):
    """The layer of cells of the finest indirect grid (gpu/indirect.py IndirectMethod) at
    `position` (0 low side .. 1 high side) across `axis`, with
    colours scaled by the brightest cell of the whole volume (the slice keeps its
    brightness as it moves); corners in world space (the grid's are relative to the
    scene's `world_origin`)."""
    a = "xyz".index(axis)
    grid = indirect.grids[0]
    n = grid.size
    volume = np.maximum(indirect.cell_light(), 0.0)  # (x, y, z, channel)
    layer = min(int(position * n), n - 1)
    u, v = [i for i in range(3) if i != a]
    light = np.take(volume, layer, axis=a)  # (u, v, channel)
    image = np.full((n, n, 4), SLICE_OPACITY, dtype=np.float32)
    image[..., :3] = display_levels(light.transpose(1, 0, 2), float(volume.max()))
    image[..., 3] *= image[..., :3].max(axis=-1) > 0
    origin = np.asarray(grid.origin, dtype=np.float64)
    extent = grid.cell_size * n
    depth = origin[a] + (layer + 0.5) * grid.cell_size
    corners = []
    for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
        corner = origin.copy()
        corner[a] = depth
        corner[u] += du * extent
        corner[v] += dv * extent
        corners.append(corner)
    return LPVSlice((np.array(corners) + np.asarray(world_origin)).astype(np.float32), image, light.transpose(1, 0, 2).astype(np.float32))


def warp_status_image(warp):
    """A warped map's status atlas as RGBA colours (GL's bottom row first); texels with
    no geometry are transparent."""
    status, _, _ = warp.read()
    image = np.zeros(status.shape + (4,), dtype=np.float32)
    image[..., :3] = STATUS_COLOURS[status]
    image[..., 3] = status > 0
    return image


def render_debug_passes(glc, targets, camera, light_maps, point_size):
    """Fill the VPL Splats and Warp Status images of `targets` for this frame."""
    gl = glc.gl
    splats, status, framebuffer = targets.debug_images()
    glc.clear(splats, status)
    framebuffer.use()
    framebuffer.viewport = (0, 0, *targets.size)
    program = glc.program("vpl_splat", "vpl_splat")
    set_uniforms(program, view_projection=camera.projection @ camera.view,
                 camera_position=tuple(float(v) for v in camera.position), point_size=float(point_size),
                 pixel_angle=camera.pixel_angle(targets.size[1]))
    gl.enable(moderngl.DEPTH_TEST)
    draw_points(gl, program, [set_and_count for maps in light_maps for set_and_count in maps.emitter_sets()])
    program = glc.compute("warp_status_pass")
    bind_gbuffer(targets)
    status.bind_to_image(0, read=True, write=True)
    for maps in light_maps:
        if maps.warp is None:
            continue
        maps.warp.texture.use(location=2)
        set_uniforms(program, **gbuffer_uniforms(camera), warp_status=2, status_colours=STATUS_COLOURS,
                     **maps.rsm.lookup_uniforms())
        dispatch(program, *targets.size)
