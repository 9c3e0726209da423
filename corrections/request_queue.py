"""The seed's priority queue of Cycles sample requests (issue 18): which region of the view
to ask for next, and how many samples a pixel.

The image is cut into square tiles; a tile's priority is the error its next request is
expected to remove for each second it costs. The error is the reconstruction's own
estimate (reconstruction.py), so the seed's three sources are one rule: tiles no sample
has reached yet carry the preview's assumed error and go first, a row of them at 1 sample
a pixel in one request (the uniform requests),
tiles the reprojected corrections of earlier views leave uncertain carry that (their
largest errors), and a tile next to one with a large error shares part of it (its
children). A tile's samples a pixel double from request to request, as progressive
rendering's do; a request carries REQUEST_SAMPLES samples or more, so that its fixed cost
stays a minority, but no more than about REQUEST_SECONDS of work.
"""
import math

import numpy as np

TILES = 16
"""About how many tiles an image is cut into (their side a power of two, 16 to 128 pixels)."""
REQUEST_SAMPLES = 16384
PIXEL_SAMPLES = 4096
"""Samples a pixel after which a tile is done (the references' count): a view at rest
stops asking once every tile is done."""
DONE_ERROR = 1e-4
"""A tile whose expected relative MSE (its pixels' estimate, the samples still to come and
a share of its neighbours' counted) averages below this is done too (1 % RMS, chosen near
Cycles' default adaptive-sampling threshold for renders, 0.01)..."""
DONE_SAMPLES = 16
"""...once it has this many samples a pixel of the view's own: the estimate counts the
noise of samples carried over from other views, not the error of their resampling, and a
tile's first samples may all agree by chance."""
REQUEST_SECONDS = 0.5
"""A request takes about this long at most (its samples a pixel stop doubling): a moved
view's first requests never wait long behind the last view's."""
CHILD_SHARE = 0.5
"""Share of its largest neighbour's error a tile takes on."""
FIXED_SECONDS = 0.0015
"""A request's cost beyond its samples on its worker (docs/bench/cpu/sample_workers.md)."""
SAMPLES_PER_SECOND = 250_000.0
"""A worker's samples a second until the requests' times tell."""


class RequestQueue:
    """Tiles of a `size` (width, height) view, their errors and the samples asked of them."""

    def __init__(self, size):
        width, height = size
        side = int(np.clip(2 ** round(math.log2(math.sqrt(width * height / TILES))), 16, 128))
        self.tiles = [(x0, y0, min(x0 + side, width), min(y0 + side, height))
                      for y0 in range(0, height, side) for x0 in range(0, width, side)]
        self.grid = (math.ceil(height / side), math.ceil(width / side))
        self.pixels = np.array([(x1 - x0) * (y1 - y0) for x0, y0, x1, y1 in self.tiles], dtype=np.float64)
        self.side = side
        # summed over a tile's pixels, at the last update; until the first, every pixel alike
        self.error = self.pixels.copy()
        # a pixel's samples (earlier views' weighed by their age) at the last update, received
        # since, and asked but not received
        self.samples, self.received, self.pending, self.own = (np.zeros(len(self.tiles)) for _ in range(4))
        self.samples_per_second = SAMPLES_PER_SECOND

    def update(self, error, samples, own):
        """The reconstruction's per-pixel relative error and samples, and the view's own
        samples ((h, w) each), every sample received so far in them."""
        grid = self._sums(error).reshape(self.grid)
        padded = np.pad(grid, 1)
        neighbours = np.max([padded[1 + dy:1 + dy + grid.shape[0], 1 + dx:1 + dx + grid.shape[1]]
                             for dy in (-1, 0, 1) for dx in (-1, 0, 1) if dy or dx], axis=0)
        self.error = np.maximum(grid, CHILD_SHARE * neighbours).reshape(-1)
        self.samples, self.own = self._sums(samples) / self.pixels, self._sums(own) / self.pixels
        self.received[:] = 0.0

    def _sums(self, image):
        """Each tile's sum of `image` ((h, w))."""
        return np.array([image[y0:y1, x0:x1].sum() for x0, y0, x1, y1 in self.tiles])

    def done(self, region, spp, seconds=None):
        """The request of `region` at `spp` came back after `seconds` on its worker (None:
        it was cancelled or failed): its tiles' samples and the pace follow."""
        tiles = self._tiles_in(region)
        self.pending[tiles] -= spp
        if seconds is None:
            return
        self.received[tiles] += spp
        pace = max(seconds - FIXED_SECONDS, 0.5 * seconds) / (self.pixels[tiles].sum() * spp)
        self.samples_per_second = 0.8 * self.samples_per_second + 0.2 / pace

    def _tiles_in(self, region):
        x0, y0, x1, y1 = region
        return [row * self.grid[1] + column for row in range(y0 // self.side, -(-y1 // self.side))
                for column in range(x0 // self.side, -(-x1 // self.side))]

    def next(self):
        """The next request: (region, samples a pixel), or None when every tile is done
        (PIXEL_SAMPLES, or DONE_ERROR with DONE_SAMPLES). A tile nothing was asked of yet
        is asked for at 1 sample a pixel with the untouched tiles beside it in its row (one
        request, the fixed cost once): the
        whole view is covered first, as soon as the workers can. A request whose doubled
        samples stay under REQUEST_SAMPLES takes the tiles beside it in its row that hold
        as many: a pixel's requests then grow by at most about 4 times what it holds, not
        16, so the spread of their means tells the noise (reconstruction.py)."""
        held = self.samples + self.received + self.pending
        step = 2.0 ** np.floor(np.log2(np.maximum(held, 1.0)))
        spp = np.maximum(np.ceil(REQUEST_SAMPLES / self.pixels), step)
        spp = np.minimum(spp, np.maximum(1.0, np.floor(REQUEST_SECONDS * self.samples_per_second / self.pixels)))
        # the error falls as 1/samples: what remains of it now, and what the request takes away
        remaining = self.error * (self.samples + 1.0) / (held + 1.0)
        own = self.own + self.received + self.pending
        wanted = (held < PIXEL_SAMPLES) & ((own < DONE_SAMPLES) | (remaining > DONE_ERROR * self.pixels))
        gain = np.where(wanted, remaining * spp / (held + spp), -1.0)
        cost = FIXED_SECONDS + self.pixels * spp / self.samples_per_second
        tile = int(np.argmax(gain / cost))
        if not wanted[tile]:
            return None
        untouched = held[tile] == 0
        alike = (held == 0) if untouched else (step == step[tile]) & (held > 0) & wanted
        row = tile - tile % self.grid[1]
        first = last = tile
        while untouched or self.pixels[first:last + 1].sum() * step[tile] < REQUEST_SAMPLES:
            if first > row and alike[first - 1]:
                first -= 1
            elif last + 1 < row + self.grid[1] and alike[last + 1]:
                last += 1
            else:
                break
        pixels = self.pixels[first:last + 1].sum()
        count = 1.0 if untouched else max(step[tile], math.ceil(REQUEST_SAMPLES / pixels))
        count = min(count, max(1.0, math.floor(REQUEST_SECONDS * self.samples_per_second / pixels)))
        region = (self.tiles[first][0], self.tiles[first][1], self.tiles[last][2], self.tiles[last][3])
        self.pending[first:last + 1] += count
        return region, int(count)
