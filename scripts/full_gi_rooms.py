"""Indirect light against Cycles' full GI in rooms: the Cornell box, the full-GI rooms of
demo/artist (GI_ROOMS), the artist suite's rooms and the particle room, as a Markdown
table on stdout and PNGs in OUT_DIR:

    .venv/bin/python scripts/full_gi_rooms.py OUT_DIR [--width 160 --samples 512 --sets 16]
                                                      [--scenes a,b] [--lpv-resolution N] [--export]

Cycles renders each scene's light passes (Diffuse and Glossy Direct, Diffuse Indirect and
their colours) with the scene's own Light Paths, as F12 does: the bounces our default
follows. Ours is a frame of the default settings at that size (with --lpv-resolution, the
indirect grids of that many cells a side), once with one VPL set and
once converged over --sets sets, those at a GPU's converged grids (AUTO_CONVERGED_RESOLUTION)
on any driver. Per scene the table gives the ratio of the direct
light's means (converged, against Diffuse and Glossy Direct times their colours: the
lamps', emitters' and world's light on the surfaces, highlights included, as our Direct
pass holds them) and
the ratio of the indirect means (against DiffInd times DiffCol), PSNR and relative MSE of
each frame. A PNG per scene shows ours (one set, converged) beside Cycles, the indirect
light through the scene's view transform, exposed so that Cycles' log-average is middle
grey. With --export it writes each scene as OUT_DIR/NAME.npz instead, for the GPU timings
(scripts/time_full_gi.py).
"""
import argparse
import os
from dataclasses import replace

import numpy as np

from lpv_preview import demo
from lpv_preview.addon.cycles_reference import render_cycles_passes
from lpv_preview.addon.cycles_render import REFERENCE_FILTER_WIDTH
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.addon.view_transform import scene_view_transform
from lpv_preview.gpu.colour import middle_grey_exposure
from lpv_preview.gpu.image_io import write_png
from lpv_preview.gpu.metrics import figure_text, image_errors
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.scene_file import save_scene
from lpv_preview.gpu.settings import AUTO_CONVERGED_RESOLUTION, Settings

ROOMS = ("cornell", *demo.GI_ROOMS, "sunlit_foliage", "area_room", "sky_interior", "particles")


def cycles_light(bpy_scene, samples, size):
    """Cycles' direct light (diffuse and glossy: our Direct pass holds both) and diffuse
    indirect light of the scene with its own Light Paths (linear RGB)."""
    images = render_cycles_passes(bpy_scene, ("DiffDir", "DiffInd", "DiffCol", "GlossDir", "GlossCol"), samples,
                                  size, 0, pixel_filter_width=REFERENCE_FILTER_WIDTH)
    return (images["DiffDir"] * images["DiffCol"] + images["GlossDir"] * images["GlossCol"],
            images["DiffInd"] * images["DiffCol"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--samples", type=int, default=512)
    parser.add_argument("--sets", type=int, default=16)
    parser.add_argument("--scenes", default=",".join(ROOMS))
    parser.add_argument("--lpv-resolution", type=int, default=Settings().lpv_resolution)
    parser.add_argument("--export", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    names = args.scenes.split(",")
    if not args.export:
        print(f"Cycles' diffuse indirect with each scene's Light Paths, {args.samples} samples; ours with the default "
              f"settings (grids {args.lpv_resolution}³), {args.width} pixels across; one VPL set and {args.sets} sets\n")
        print("| scene | bounces | direct, ours/Cycles | indirect ours/Cycles, one set | PSNR dB | relMSE "
              "| indirect ours/Cycles, converged | PSNR dB | relMSE |")
        print("|---|---|---|---|---|---|---|---|---|")
    for name in names:
        bpy_scene = demo.build(name)
        render = bpy_scene.render
        size = (args.width, round(args.width * render.resolution_y / render.resolution_x))
        render.resolution_x, render.resolution_y = size
        scene = scene_to_render(bpy_scene)
        if args.export:
            save_scene(scene, os.path.join(args.out, f"{name}.npz"))
            print(os.path.join(args.out, f"{name}.npz"), flush=True)
            continue
        direct, reference = cycles_light(bpy_scene, args.samples, size)
        settings = Settings(width=size[0], height=size[1], lpv_resolution=args.lpv_resolution,
                            converged_lpv_resolution=AUTO_CONVERGED_RESOLUTION)  # as on a GPU, on llvmpipe too
        frames = [render_once(scene, settings.with_changes(converge_sets=sets)) for sets in (1, args.sets)]
        cells = [f"{frames[1].passes['direct'].mean() / direct.mean():.3f}"]
        for frame in frames:
            errors = image_errors(frame.passes["indirect"], reference)
            cells += [f"{errors['mean'] / errors['reference_mean']:.3f}", figure_text(errors["psnr"], ".1f"),
                      figure_text(errors["relative_mse"], ".3f")]
        print(f"| {name} | {frames[0].stats['bounces']} | " + " | ".join(cells) + " |", flush=True)
        view = scene_view_transform(bpy_scene)
        images = np.concatenate([frames[0].passes["indirect"], frames[1].passes["indirect"], reference], axis=1)
        write_png(os.path.join(args.out, f"{name}.png"), images,
                  replace(view, exposure=view.exposure + middle_grey_exposure(reference)))


if __name__ == "__main__":
    main()
