"""Time to equal error: how many Cycles samples, and seconds, reach a preview's error.

Cycles' MSE against a high-sample reference falls as a power of its samples and its
render time grows linearly with them; `time_to_equal_error` fits both through a ladder of
Cycles renders and finds where Cycles' fitted MSE meets each candidate's: our preview per
indirect method, or Cycles at a few samples denoised (against the undenoised ladder on
the Combined pass). The renders are made above this module (scripts/time_to_equal_error.py,
with bpy); it only measures and fits.
"""
from dataclasses import dataclass

import numpy as np

from ..gpu.metrics import mse


@dataclass
class EqualError:
    """The Cycles samples and seconds whose error (MSE against a high-sample reference)
    equals a candidate's (`label`, like 'WDPM light grid' or 'Cycles 1 spp + OIDN').
    `ladder` holds the measured (samples, seconds, MSE) rungs; `samples` comes from the
    line log MSE = a - b log samples fitted through them, and `seconds` from seconds =
    c + d samples (Cycles' fixed cost per render and per sample); both are None where one
    sample of Cycles is already closer than the candidate."""

    label: str
    image: str
    milliseconds: float
    mse: float
    ladder: list
    slope: float = 0.0
    samples: float = None
    seconds: float = None

    @property
    def extrapolated(self):
        return self.samples is not None and self.samples > max(rung[0] for rung in self.ladder)


def time_to_equal_error(candidates, reference, ladder, rungs):
    """An EqualError per candidate (label, image, milliseconds, test image): the test
    image against Cycles' `reference`'s `image` (an attribute: "indirect", "combined",
    "combined_pass"), from Cycles' `rungs` rendered at the `ladder` sample counts with
    another seed. References and rungs have their render seconds in `settings`."""
    seconds = [rung.settings["render_seconds"] for rung in rungs]
    fixed, per_sample = np.polynomial.polynomial.polyfit(ladder, seconds, 1)
    results = []
    for label, image, milliseconds, test in candidates:
        target = getattr(reference, image)
        errors = [mse(getattr(rung, image), target) for rung in rungs]
        error = mse(test, target)
        intercept, slope = np.polynomial.polynomial.polyfit(np.log(ladder), np.log(errors), 1)
        result = EqualError(label, image, milliseconds, error, list(zip(ladder, seconds, errors)), -slope)
        samples = float(np.exp((np.log(error) - intercept) / slope))
        if samples >= 1.0:
            result.samples, result.seconds = samples, float(fixed + per_sample * samples)
        results.append(result)
    return results
