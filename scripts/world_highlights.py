"""Where a scene's highlights of the world's own light go: Cycles counts them as Glossy
Direct, ours are in the Reflections pass (a Sky Texture's sun disc's in Direct: it lights
as a sun light). For a demo scene at 160 pixels across, prints
over the whole frame and over each third of it (rows, then columns) the means of Cycles'
Diffuse Direct and Glossy Direct (times their colours) and of our Direct and Reflections
(8 VPL sets).

    .venv/bin/python scripts/world_highlights.py [sunlit_foliage] [--samples 64]
"""
import argparse

from lpv_preview import demo
from lpv_preview.addon.cycles_reference import render_cycles_passes
from lpv_preview.addon.cycles_render import REFERENCE_FILTER_WIDTH
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.settings import Settings

WIDTH = 160


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default="sunlit_foliage")
    parser.add_argument("--samples", type=int, default=64)
    args = parser.parse_args()
    bpy_scene = demo.build(args.scene)
    render = bpy_scene.render
    size = (WIDTH, round(WIDTH * render.resolution_y / render.resolution_x))
    render.resolution_x, render.resolution_y = size
    cycles = render_cycles_passes(bpy_scene, ("DiffDir", "DiffCol", "GlossDir", "GlossCol"), args.samples, size, 0,
                                  pixel_filter_width=REFERENCE_FILTER_WIDTH)
    ours = render_once(scene_to_render(bpy_scene), Settings(width=size[0], height=size[1], converge_sets=8)).passes
    images = {"Cycles Diffuse Direct": cycles["DiffDir"] * cycles["DiffCol"],
              "Cycles Glossy Direct": cycles["GlossDir"] * cycles["GlossCol"],
              "our Direct": ours["direct"], "our Reflections": ours["reflections"]}
    height, width = size[1], size[0]
    regions = {"whole frame": (slice(None), slice(None))}
    for row in range(3):
        for column in range(3):
            regions[f"row {row + 1}, column {column + 1}"] = (slice(row * height // 3, (row + 1) * height // 3),
                                                             slice(column * width // 3, (column + 1) * width // 3))
    print("| region | " + " | ".join(images) + " |\n|---|" + "---|" * len(images))
    for name, (rows, columns) in regions.items():
        print(f"| {name} | " + " | ".join(f"{image[rows, columns].mean():.3f}" for image in images.values()) + " |")


if __name__ == "__main__":
    main()
