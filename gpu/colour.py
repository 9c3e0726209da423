"""Colour constants shared by the image writer and the error metrics."""
import numpy as np

LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, linear RGB
