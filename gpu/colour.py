"""Colour constants shared by the image writer and the error metrics, and the exposure
that shows an image at middle grey."""
import math

import numpy as np

LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, linear RGB
MIDDLE_GREY = 0.18


def middle_grey_exposure(image):
    """The exposure in stops that brings the log-average luminance of the lit pixels of
    `image` to middle grey (0 for an image with none)."""
    luminance = np.maximum(np.asarray(image, dtype=np.float64), 0.0) @ LUMINANCE_WEIGHTS
    lit = luminance[luminance > 1e-9]
    return math.log2(MIDDLE_GREY) - float(np.mean(np.log2(lit))) if lit.size else 0.0
