"""A view's first corrections against its preview: is the partly corrected frame ever worse?

    .venv/bin/python scripts/partial_corrections.py OUT [cornell,atrium] [--width 640 --height 360]
        [--reference-samples 1024] [--requests 6]

builds each scene at the size given, renders (or reads from the references' cache) its
full-GI reference, its preview, then asks Cycles for the requests the view's own queue
asks for first (corrections/request_queue.py: a row of tiles at 1 sample a pixel, then
more), one after another, and after each prints the corrected frame's relative MSE beside
the preview's, over the frame and over 32 × 32-pixel blocks: the share of blocks the
correction made worse, the worst block's error over its preview's and the rebuild's
seconds (its first also makes the filter's edges). OUT gets, per scene
and request, preview | corrected | reference as a PNG (the scene's view transform).
"""
import argparse
import os
import time

import numpy as np

from lpv_preview import demo
from lpv_preview.addon.cycles_samples import SampleRenderer
from lpv_preview.cli.correction_runs import path_views, render_previews
from lpv_preview.cli.flags import add_setting_flags, check_setting_flags, settings_from
from lpv_preview.corrections.layers import Corrections
from lpv_preview.corrections.request_queue import RequestQueue
from lpv_preview.corrections.sample_request import SampleRequest
from lpv_preview.addon.view_transform import scene_view_transform
from lpv_preview.gpu.image_io import write_png
from lpv_preview.gpu.metrics import RELATIVE_EPSILON, relative_mse

BLOCK = 32
WORSE = 1.1
"""A block counts as made worse where its corrected error passes its preview's by this factor."""


def block_errors(image, reference):
    """Per BLOCK × BLOCK block, the relative MSE of `image` against `reference`."""
    height, width = reference.shape[:2]
    rows, columns = height // BLOCK, width // BLOCK
    squared = ((image - reference) ** 2 / (reference ** 2 + RELATIVE_EPSILON)).mean(-1)
    return squared[:rows * BLOCK, :columns * BLOCK].reshape(rows, BLOCK, columns, BLOCK).mean((1, 3))


def scene_rows(name, folder, out, args):
    settings = settings_from(args, args.width, args.height)
    size = (settings.width, settings.height)
    blend = os.path.join(folder, f"{name}.blend")
    built = {}

    def build():
        built["scene"] = demo.build(name, resolution=size)
        return built["scene"]

    view = path_views(name, build, size, (0.0,), args.reference_samples, blend, log=print)[0]
    view_transform = scene_view_transform(built["scene"])
    render_previews([view], settings)
    corrections = Corrections()
    corrections.view(view.key, view.scene.camera, view.gbuffer, view.preview)
    queue = RequestQueue(size)
    renderer = SampleRenderer(blend)
    preview_blocks = block_errors(view.preview, view.reference)
    print(f"{name} preview: {relative_mse(view.preview, view.reference):.4f}", flush=True)
    rows = []
    try:
        for request in range(1, args.requests + 1):
            region, spp = queue.next()
            result = renderer.render(SampleRequest(region, size, spp, 2000 + request, view.camera))
            queue.done(region, spp)
            corrections.add(view.key, region, result.passes["Combined"], spp)
            began = time.perf_counter()
            reconstruction = corrections.reconstruct(view.key)
            seconds = time.perf_counter() - began
            queue.update(reconstruction.error, reconstruction.samples, corrections.layers[view.key].samples)
            blocks = block_errors(reconstruction.image, view.reference)
            worse = float(np.mean(blocks > WORSE * preview_blocks))
            worst = float(np.max(blocks / np.maximum(preview_blocks, 1e-12)))
            covered = float(np.mean(reconstruction.samples > 0))
            rows.append((request, covered, relative_mse(reconstruction.image, view.reference), worse, worst))
            print(f"{name} request {request} ({spp} spp over {region}): covered {covered:.2f}  corrected "
                  f"{rows[-1][2]:.4f}  blocks worse {worse:.2f}  worst block {worst:.2f}× its preview's  rebuilt in "
                  f"{seconds:.2f} s", flush=True)
            write_png(os.path.join(out, f"{name}_{request}.png"),
                      np.concatenate((view.preview, reconstruction.image, view.reference), axis=1), view_transform)
    finally:
        renderer.close()
    return rows


def main():
    parser = argparse.ArgumentParser(description="a view's first corrections against its preview")
    parser.add_argument("out")
    parser.add_argument("scenes", nargs="?", default="cornell,atrium")
    parser.add_argument("--reference-samples", type=int, default=1024)
    parser.add_argument("--requests", type=int, default=6)
    add_setting_flags(parser)
    args = parser.parse_args()
    args.width, args.height = args.width or 640, args.height or 360
    check_setting_flags(args)
    os.makedirs(args.out, exist_ok=True)
    import tempfile
    with tempfile.TemporaryDirectory(prefix="lpv_partial_") as folder:
        for name in args.scenes.split(","):
            scene_rows(name, folder, args.out, args)


if __name__ == "__main__":
    main()
