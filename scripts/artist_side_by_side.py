"""Ours, Cycles' F12 and EEVEE's F12 of artist scenes side by side, through the scene's
own view transform (as F12 saves them), in one PNG: a row a scene.

    .venv/bin/python scripts/artist_side_by_side.py studio_materials area_room --out side.png
        [--width 192 --height 108 --samples 128 --sets 8]

builds each scene of demo/artist/ with bpy, renders our frame of `--sets` VPL sets,
Cycles' Combined at `--samples` with the scene's settings and EEVEE's at 16 samples, and
prints each one's mean linear value.
"""
import argparse

import bpy  # noqa: F401 (addon_utils comes with it)
import addon_utils
import numpy as np
import OpenImageIO as oiio

from lpv_preview import demo
from lpv_preview.addon.combined_renders import cycles_combined, eevee_combined
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.addon.view_transform import scene_view_transform
from lpv_preview.gpu.colour_management import display_values
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings


def row(name, size, samples, sets):
    """The scene's three images through its view transform, side by side, and their means."""
    scene = demo.build(name, resolution=size)
    pipeline = Pipeline(Settings(width=size[0], height=size[1], converge_sets=sets))
    try:
        ours = pipeline.render_converged(scene_to_render(scene, size)).passes["combined"]
    finally:
        pipeline.release()
    cycles, _ = cycles_combined(scene, samples, size)
    eevee, _ = eevee_combined(scene, size, samples=16)
    images = [np.ascontiguousarray(image[..., :3], dtype=np.float32) for image in (ours, cycles, eevee)]
    shown = [np.asarray(display_values(image, scene_view_transform(scene)), np.float32)[..., :3] for image in images]
    return np.concatenate(shown, axis=1), [float(image.mean()) for image in images]


def main():
    parser = argparse.ArgumentParser(description="ours, Cycles and EEVEE of artist scenes side by side")
    parser.add_argument("names", nargs="+", choices=demo.ARTIST_SCENES)
    parser.add_argument("--out", required=True, help="the PNG to write")
    parser.add_argument("--width", type=int, default=192)
    parser.add_argument("--height", type=int, default=108)
    parser.add_argument("--samples", type=int, default=128, help="Cycles' samples")
    parser.add_argument("--sets", type=int, default=8, help="our VPL sets")
    args = parser.parse_args()
    addon_utils.enable("cycles")
    rows = []
    for name in args.names:
        image, means = row(name, (args.width, args.height), args.samples, args.sets)
        print(f"{name}: mean ours {means[0]:.3f}, Cycles {means[1]:.3f}, EEVEE {means[2]:.3f}", flush=True)
        rows.append(image)
    image = np.concatenate(rows, axis=0)
    out = oiio.ImageBuf(oiio.ImageSpec(image.shape[1], image.shape[0], 3, "float"))
    out.set_pixels(oiio.ROI(0, image.shape[1], 0, image.shape[0]), np.ascontiguousarray(image))
    out.write(args.out)


if __name__ == "__main__":
    main()
