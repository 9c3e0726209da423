"""How closely our Sky Texture models (addon/sky_models.py) agree with Cycles'.

    .venv/bin/python scripts/sky_agreement.py [--elevations 5 35 70] [--size 128]

For each sky type and sun elevation: the sky's mean ratio and largest relative error
above and below the horizon against Cycles' equirectangular render of the world (away
from the sun and the horizon's rows), and the sun disc's power in our map against Cycles' (tests/blender/test_sky.py
renders them)."""
import argparse
import os
import tempfile

import numpy as np

from lpv_preview.tests.blender.test_sky import cycles_sun_power, map_sun_power, sky_agreement, sky_world_scene

SKY_TYPES = ("MULTIPLE_SCATTERING", "SINGLE_SCATTERING", "PREETHAM", "HOSEK_WILKIE")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--elevations", type=float, nargs="+", default=[5.0, 35.0, 70.0])
    parser.add_argument("--size", type=int, default=128, help="the sky's comparison height (width twice)")
    parser.add_argument("--types", nargs="+", default=SKY_TYPES)
    args = parser.parse_args()
    path = os.path.join(tempfile.mkdtemp(), "sky.exr")
    print(f"{'sky type':<20} {'elev':>5} {'sky mean':>9} {'max err above':>13} {'below':>7} "
          f"{'sun power ratio (r g b)':>26}")
    for sky_type in args.types:
        for elevation in args.elevations:
            scene = sky_world_scene(sky_type, elevation)
            mean_ratio, error_above, error_below = sky_agreement(scene, path, (args.size, 2 * args.size))
            sun = ""
            if sky_type in ("MULTIPLE_SCATTERING", "SINGLE_SCATTERING"):
                theirs = cycles_sun_power(scene, path)
                sun = " ".join(f"{value:.4f}" for value in map_sun_power(scene) / np.maximum(theirs, 1e-30))
            print(f"{sky_type:<20} {elevation:>5.0f} {mean_ratio:>9.4f} {error_above:>13.4f} {error_below:>7.4f} "
                  f"{sun:>26}", flush=True)


if __name__ == "__main__":
    main()
