"""Sub-pixel offsets for anti-aliasing: each VPL set of a frame looks through another point
of the pixel, drawn from Blender's pixel filter (Blackman-Harris over the Film's filter
width, as Cycles importance-samples it), so that the average of the sets is filtered as
Cycles' pixels are. The first set looks through the pixel's centre."""
import math

import numpy as np

R2 = (0.7548776662466927, 0.5698402909980532)
"""The R2 low-discrepancy sequence's steps (Roberts 2018): the sets' offsets cover the
filter evenly in any number."""
TABLE_SIZE = 256


def _inverse_cdf(width):
    """Positions in [-width/2, width/2] at TABLE_SIZE evenly spaced values of the
    Blackman-Harris window's cumulative distribution."""
    x = np.linspace(0.0, 1.0, 4097)
    window = (0.35875 - 0.48829 * np.cos(2 * math.pi * x) + 0.14128 * np.cos(4 * math.pi * x)
              - 0.01168 * np.cos(6 * math.pi * x))
    cdf = np.concatenate([[0.0], np.cumsum((window[1:] + window[:-1]) / 2)])
    cdf /= cdf[-1]
    return (np.interp(np.linspace(0.0, 1.0, TABLE_SIZE), cdf, x) - 0.5) * width


def pixel_offset(index, width):
    """The (x, y) offset in pixels of set `index` (0: none) for a filter `width` pixels wide."""
    if index == 0 or width <= 0:
        return 0.0, 0.0
    table = _inverse_cdf(width)
    return tuple(float(np.interp((0.5 + index * step) % 1.0, np.linspace(0.0, 1.0, TABLE_SIZE), table))
                 for step in R2)
