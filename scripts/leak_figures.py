"""The leak scenes of tests/leak_scenes.py against Cycles' one bounce, with either indirect
method, as a Markdown table on stdout and PNGs in OUT_DIR:

    .venv/bin/python scripts/leak_figures.py OUT_DIR [--width 160 --height 120 --samples 256] [--export]

Each PNG shows ours (left) beside Cycles (right), the indirect light above and diffuse
direct plus indirect below, through the scene's view transform (AgX) with one exposure
that brings the log-average of Cycles' picture (or, where the view sees no light at all,
of the light it would get without the box that holds it in: closed_box) to middle grey.
Our settings are the defaults but for the image size.

"ours/Cycles" is the ratio of the indirect means; where Cycles' indirect is black it is
undefined, as PSNR is, and "ours indirect / direct" is the leak's size: our indirect
mean over the mean direct light of the view (or, marked *, of the view without the box:
the light the box keeps from it).

With --export it writes instead each scene as OUT_DIR/NAME.npz with its Cycles one-bounce
and full-GI indirect images beside it, for scripts/convergence.py on a machine without
Blender.
"""
import argparse
import os
from dataclasses import replace

import numpy as np

from lpv_preview.addon.cycles_reference import cycles_reference
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.addon.view_transform import scene_view_transform
from lpv_preview.gpu.colour import middle_grey_exposure
from lpv_preview.gpu.image_io import write_png
from lpv_preview.gpu.metrics import figure_text, image_errors
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.scene_file import save_scene, store_cycles_indirect
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings
from lpv_preview.tests.leak_scenes import BUILDERS, unblocked_scene

BLACK = 1e-6
"""An indirect mean below this is Cycles' zero (its one-bounce image of a lone plane)."""


def side_by_side(ours, reference, view_transform, exposure_of, path):
    indirect = np.concatenate([ours.passes["indirect"], reference.indirect], axis=1)
    combined = np.concatenate([ours.passes["direct"] + ours.passes["indirect"], reference.combined], axis=1)
    write_png(path, np.concatenate([indirect, combined], axis=0),
              replace(view_transform, exposure=view_transform.exposure + middle_grey_exposure(exposure_of)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--samples", type=int, default=256)
    parser.add_argument("--export", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.export:
        for name, build in BUILDERS.items():
            built = build((args.width, args.height))
            path = os.path.join(args.out, f"{name}.npz")
            save_scene(scene_to_render(built.scene), path)
            store_cycles_indirect(path, cycles_reference(built.scene, "one_bounce", args.samples).indirect,
                                  args.samples, cycles_reference(built.scene, "full_gi", args.samples).indirect)
            print(path, flush=True)
        return
    print(f"Cycles one bounce, {args.samples} samples; ours with the default settings; {args.width}x{args.height}\n")
    print("| scene | indirect method | indirect PSNR dB | ours/Cycles indirect mean | ours indirect / direct "
          "| mean direct | lpv_cell_size | grid_levels |")
    print("|---|---|---|---|---|---|---|---|")
    for name, build in BUILDERS.items():
        built = build((args.width, args.height))
        content = scene_to_render(built.scene)
        reference = cycles_reference(built.scene, "one_bounce", args.samples)
        unblocked = unblocked_scene(built)
        for method in INDIRECT_METHODS:
            settings = Settings(width=args.width, height=args.height, indirect_method=method, bounces=1)
            ours = render_once(content, settings)
            direct = (ours if unblocked is None else render_once(unblocked, settings)).passes["direct"]
            errors = image_errors(ours.passes["indirect"], reference.indirect)
            black = errors["reference_mean"] < BLACK
            ratio = None if black else errors["mean"] / errors["reference_mean"]
            leak = errors["mean"] / float(direct.mean())
            marked = "*" if unblocked is not None else ""
            print(f"| {name} | {method} | {figure_text(None if black else errors['psnr'], '.1f')} "
                  f"| {figure_text(ratio, '.3f')} | {leak:.4f}{marked} | {float(direct.mean()):.4g}{marked} "
                  f"| {ours.stats['lpv_cell_size']:.4g} | {ours.stats['grid_levels']} |", flush=True)
            exposure_of = direct if reference.combined.max() <= 0.0 else reference.combined
            side_by_side(ours, reference, scene_view_transform(built.scene), exposure_of,
                         os.path.join(args.out, f"{name}_{method}.png"))


if __name__ == "__main__":
    main()
