"""What the preview's G-buffer tells the corrections of each pixel (gpu/shade.py
GBufferRecord), and the edge-stopping weights it gives the reconstruction's à-trous filter:
neighbours weighed by their distance from the pixel's plane and their normals' likeness,
surfaces and background kept apart."""
from dataclasses import fields
from functools import cached_property

import numpy as np

from ..gpu.shade import GBufferRecord

ALBEDO_FLOOR = 0.05
"""Added to the albedo the samples are divided by and the corrections multiplied by: keeps
black surfaces, emitters and the background finite."""
NORMAL_POWER = 16
"""Sharpness of the normals' edge: a neighbour counts as (n·n')^NORMAL_POWER (a power of two)."""
PLANE_FOOTPRINTS = 1.0
"""A neighbour off the pixel's plane by this many pixel footprints times the step counts e^-1."""


class Guide(GBufferRecord):
    """A view's GBufferRecord with what the reconstruction derives from it once a view:
    the demodulating scale and the filter's edge weights."""

    @staticmethod
    def of(record):
        """The Guide of a GBufferRecord (the record itself when it is one)."""
        if isinstance(record, Guide):
            return record
        return Guide(**{field.name: getattr(record, field.name) for field in fields(record)})

    @cached_property
    def scale(self):
        """What a radiance seen here is divided by to be demodulated, and a correction
        multiplied by: the albedo, ALBEDO_FLOOR added."""
        return self.albedo.astype(np.float64) + ALBEDO_FLOOR

    @cached_property
    def edges(self):
        """The à-trous filter's edge weights, made on the first reconstruction of this view."""
        return EdgeWeights(self)


class EdgeWeights:
    """The G-buffer's edges for the à-trous filter: a 3 × 3 B-spline kernel at a step,
    neighbours weighted by plane distance and normals, surfaces and background apart. The
    weights depend on the guide alone: made once a view (Guide.edges), whatever the samples."""

    KERNEL = (0.25, 0.5, 0.25)

    def __init__(self, guide):
        self.position = guide.position.astype(np.float32)
        self.normal = guide.normal.astype(np.float32)
        self.seen = guide.seen
        self.footprint = guide.footprint.astype(np.float32)
        self.taps = {}  # step -> [(target slices, source slices, weight)]

    def _taps(self, step):
        if step not in self.taps:
            height, width = self.seen.shape
            taps = []
            for dy, ky in zip((-1, 0, 1), self.KERNEL):
                for dx, kx in zip((-1, 0, 1), self.KERNEL):
                    oy, ox = dy * step, dx * step
                    target = (slice(max(0, -oy), height - max(0, oy)), slice(max(0, -ox), width - max(0, ox)))
                    source = (slice(max(0, oy), height + min(0, oy)), slice(max(0, ox), width + min(0, ox)))
                    if target[0].start < target[0].stop and target[1].start < target[1].stop:
                        taps.append((target, source, ky * kx * self._edge(target, source, step)))
            self.taps[step] = taps
        return self.taps[step]

    def filter(self, numerator, denominator, spread, step):
        sums = [np.zeros_like(numerator), np.zeros_like(denominator), np.zeros_like(spread)]
        for target, source, weight in self._taps(step):
            sums[0][target] += weight[..., None] * numerator[source]
            sums[1][target] += weight * denominator[source]
            sums[2][target] += weight * weight * spread[source]
        return sums

    def _edge(self, at, neighbour, step):
        if at == neighbour:
            return np.ones(self.seen[at].shape, np.float32)
        seen = self.seen[at]
        normal = self.normal[at]
        offset = self.position[neighbour] - self.position[at]
        plane = np.abs(np.einsum("...k,...k->...", offset, normal)) / (PLANE_FOOTPRINTS * step * self.footprint[at]
                                                                        + 1e-30)
        alike = np.clip(np.einsum("...k,...k->...", normal, self.normal[neighbour]), 0.0, 1.0)
        for _ in range(int(np.log2(NORMAL_POWER))):
            alike *= alike
        surface = np.exp(-plane) * alike
        return np.where(seen == self.seen[neighbour], np.where(seen, surface, 1.0), 0.0)
