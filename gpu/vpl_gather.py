"""VPL gathering: every pixel sums the light of the VPLs that see it (issue 16's accurate
mode). Visibility is a march through the scene's occupancy (gpu/occupancy.py) over the
grid levels, each part of a segment in the finest level that holds it; each pixel of an INTERLEAVE² block takes its own subset of the VPLs
and a filter that heeds depth and normal puts the block back together."""


from .context import dispatch, set_uniforms
from .occupancy import GATHER_VOXELS_PER_CELL, LARGE_TRIANGLE_BYTES, Occupancy, march_batch, occupancy_bytes
from .shade import bind_seen_room, seen_room_defines

INTERLEAVE = 4
"""Pixels along each side of an interleaving block: each pixel gathers one VPL in
INTERLEAVE²."""
DEPTH_TOLERANCE = 0.02
"""A neighbour this far off a pixel's plane, over the pixel's distance to the camera,
counts half in the filter."""
GATHER_BYTES_PER_PIXEL = 2 * 16  # the gather's sums and their filtered image (RGBA32F)


def pixel_gather_bytes(s, scene, pixels):
    """A pixel gather's memory for settings `s`: every level's occupancy, its canvas, its
    images and the voxelisation's list of large triangles."""
    n = s.lpv_resolution
    return (occupancy_bytes(s.grid_levels, n, GATHER_VOXELS_PER_CELL)
            + pixels * GATHER_BYTES_PER_PIXEL + scene.triangle_count * LARGE_TRIANGLE_BYTES)


class VPLGather:
    """The occupancy the gather marches through and the per-pixel images it writes."""

    def __init__(self, glc, levels):
        self.glc = glc
        self.levels = tuple(levels)
        self.occupancy = Occupancy(glc, self.levels, GATHER_VOXELS_PER_CELL)
        self.gathered = self.filtered = None

    def _images(self, size):
        if self.gathered is None or self.gathered.size != size:
            for image in (self.gathered, self.filtered):
                if image is not None:
                    image.release()
            self.gathered, self.filtered = (self.glc.gl.texture(size, 4, dtype="f4") for _ in range(2))
        return self.gathered, self.filtered

    def gather(self, targets, uniforms, camera_position, emitter_sets, singularity_bound, vpl_set, held_bound=None,
               room_sides=None):
        """Gather every pixel's irradiance from the emitters (buffers with counts), their
        1/r² bounded by `singularity_bound` (shaders/emitter.glsl), those whose bound is
        held by `held_bound` (None: the same), with `room_sides` (the mesh's sides-and-rooms
        buffer; the emitters VPLs, in rooms) only those in the room of the side each pixel
        sees (gpu/closed_meshes.py), and filter it into `filtered`; the pixels' subsets
        follow `vpl_set`. `uniforms` are the G-buffer's (gpu/shade.py gbuffer_uniforms),
        its textures bound."""
        gathered, filtered = self._images(targets.size)
        layers = self.occupancy.every_grid_layers()
        rooms = seen_room_defines(1) if room_sides is not None else {}
        program = self.glc.compute("vpl_gather_pixels", INTERLEAVE=INTERLEAVE, MARCH_LEVELS=len(layers), **rooms)
        gathered.bind_to_image(0, read=True, write=True)
        batch = march_batch(self.occupancy.voxels, len(layers), INTERLEAVE ** 2)
        set_uniforms(program, **uniforms, **self.occupancy.march_uniforms(layers, first_unit=2),
                     batch=batch, singularity_bound=singularity_bound, subset_shift=vpl_set % INTERLEAVE ** 2,
                     held_bound=singularity_bound if held_bound is None else held_bound)
        if room_sides is not None:  # after the march's two units
            bind_seen_room(program, targets, room_sides, 1, 4)
        accumulate = False
        for buffer, count in emitter_sets:
            buffer.bind_to_storage_buffer(0)
            for first in range(0, count, batch):
                set_uniforms(program, emitter_count=count, first_emitter=first, accumulate=accumulate)
                dispatch(program, *targets.size)
                accumulate = True
        if not accumulate:
            set_uniforms(program, emitter_count=0, first_emitter=0, accumulate=False)
            dispatch(program, *targets.size)
        program = self.glc.compute("vpl_gather_filter", INTERLEAVE=INTERLEAVE)
        gathered.bind_to_image(0, read=True, write=False)
        filtered.bind_to_image(1, read=False, write=True)
        set_uniforms(program, **uniforms, camera_position=tuple(float(v) for v in camera_position),
                     depth_tolerance=DEPTH_TOLERANCE)
        dispatch(program, *targets.size)

    def lookup_uniforms(self, first_unit):
        self.filtered.use(location=first_unit)
        return {"gathered": first_unit}

    def resources(self):
        images = tuple(image for image in (self.gathered, self.filtered) if image is not None)
        return (*self.occupancy.resources(), *images)

    def release(self):
        self.occupancy.release()
        for image in (self.gathered, self.filtered):
            if image is not None:
                image.release()
