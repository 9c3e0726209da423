"""The corrections' reconstruction against raw and denoised Cycles at equal samples, on the
demo scenes the corrections' benchmark uses (docs/method.md, "Corrections toward Cycles").

    .venv/bin/python scripts/reconstruction_errors.py [cornell,atrium,city] [setting flags]

builds each scene at its benchmark size, renders (or reads from the references' cache) its
4,096-sample full-GI reference and its preview (with the setting flags given, such as
--bounces 4), then feeds the corrections whole-frame Cycles requests of 1, 1, 2, 4, ... 32
samples a pixel (64 in all, one renderer on every core) and prints, at each total, the
relative MSE of the samples' mean, of the corrected frame and of Cycles denoised at as many
samples, and their geometric means over the scenes at 1, 2, 4, 16 and 64 samples. It also
prints the corrected frame when the first request's samples have reached only a band of
rows (a third or a half of the view, as the first requests' rows of tiles come back) and
the geometric mean of those. Run it at another commit to compare reconstructions.
"""
import argparse
import os
import tempfile

import numpy as np

from lpv_preview import demo
from lpv_preview.cli.flags import add_setting_flags, check_setting_flags, settings_from
from lpv_preview.cli.correction_runs import path_views, render_previews
from lpv_preview.addon.cycles_samples import SampleRenderer
from lpv_preview.bench.corrections import REFERENCE_SAMPLES, SCENES
from lpv_preview.bench.sweep_report import geometric_mean
from lpv_preview.corrections.layers import Corrections
from lpv_preview.gpu.metrics import relative_mse
from lpv_preview.corrections.sample_request import SampleRequest

REQUESTS = (1, 1, 2, 4, 8, 16, 32)
SUMMARISED = (1, 2, 4, 16, 64)
BANDS = ((0, 1, 3), (1, 2, 3), (2, 3, 3), (0, 1, 2), (1, 2, 2))
"""Bands of rows the first request reaches alone: (first, end, parts): rows from first / parts
to end / parts of the height."""


def scene_errors(name, folder, args):
    settings = settings_from(args, *SCENES[name])  # --width, --height: another size
    size = (settings.width, settings.height)
    blend = os.path.join(folder, f"{name}.blend")
    view = path_views(name, lambda: demo.build(name, resolution=size), size, (0.0,), REFERENCE_SAMPLES, blend,
                      log=lambda *_: None)[0]
    render_previews([view], settings)
    renderer = SampleRenderer(blend)
    corrections = view_corrections(view)
    whole = (0, 0, *size)
    total, count, rows, bands = 0.0, 0, [], []
    try:
        for seed, samples in enumerate(REQUESTS, start=50):
            image = renderer.render(SampleRequest(whole, size, samples, seed, view.camera)).passes["Combined"]
            if not rows:
                bands = [band_error(view, image, samples, band) for band in BANDS]
                print(f"{name} first request's rows alone: " + "  ".join(f"{first}/{parts}-{end}/{parts} {error:.4f}"
                                                                        for (first, end, parts), error in
                                                                        zip(BANDS, bands)), flush=True)
            corrections.add(view.key, whole, image, samples)
            total, count = total + image.astype(np.float64) * samples, count + samples
            denoised = renderer.render(SampleRequest(whole, size, count, seed + 100, view.camera, denoise=True))
            rows.append((count, relative_mse(total / count, view.reference),
                         relative_mse(corrections.reconstruct(view.key).image, view.reference),
                         relative_mse(denoised.passes["Combined"], view.reference)))
            print(f"{name} {count:3d} samples: raw {rows[-1][1]:.4f}  corrected {rows[-1][2]:.4f}  "
                  f"denoised {rows[-1][3]:.4f}", flush=True)
    finally:
        renderer.close()
    return rows, bands


def view_corrections(view):
    """Corrections of the View `view` alone, before any sample."""
    corrections = Corrections()
    corrections.view(view.key, view.scene.camera, view.gbuffer, view.preview)
    return corrections


def band_error(view, image, samples, band):
    """The corrected frame's relative MSE when the request's `image` has reached the band of rows alone."""
    first, end, parts = band
    height, width = image.shape[:2]
    top, bottom = first * height // parts, end * height // parts
    corrections = view_corrections(view)
    corrections.add(view.key, (0, top, width, bottom), image[top:bottom], samples)
    return relative_mse(corrections.reconstruct(view.key).image, view.reference)


def main():
    parser = argparse.ArgumentParser(description="the corrections' reconstruction against raw and denoised Cycles")
    parser.add_argument("scenes", nargs="?", default=",".join(SCENES), help="comma-separated: " + ", ".join(SCENES))
    add_setting_flags(parser)
    args = parser.parse_args()
    names = args.scenes.split(",")
    if set(names) - set(SCENES):
        parser.error(f"unknown scene in '{args.scenes}'; choose from {', '.join(SCENES)}")
    check_setting_flags(args)
    with tempfile.TemporaryDirectory(prefix="lpv_reconstruction_") as folder:
        errors = [scene_errors(name, folder, args) for name in names]
    rows = [row for scene_rows, _ in errors for row in scene_rows if row[0] in SUMMARISED]
    for column, label in ((1, "raw"), (2, "corrected"), (3, "denoised")):
        print(f"geometric mean at {', '.join(map(str, SUMMARISED))} samples, {label}: "
              f"{geometric_mean([row[column] for row in rows]):.5f}")
    print(f"geometric mean with the first request's rows alone: "
          f"{geometric_mean([error for _, bands in errors for error in bands]):.4f}")


if __name__ == "__main__":
    main()
