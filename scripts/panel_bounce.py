"""The emissive ceiling panel's bounce (tests/cycles/test_emission.py's room: a closed
4 x 4 x 3 m room of 10 cm hollow walls with a table, lit only by a 1 m emissive panel)
against Cycles' one-bounce indirect light, with the panel 40 cm and 5 cm under the
ceiling and every indirect method, as a Markdown table:

    .venv/bin/python scripts/panel_bounce.py [--samples 256]

Ours is one frame of the default settings at 64 x 48 with one bounce, its indirect mean
over Cycles'.
"""
import argparse

from lpv_preview.addon.cycles_reference import cycles_reference
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings
from lpv_preview.tests.cycles.test_emission import SIZE, room_lit_by_a_panel

CEILING = 3.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=256)
    args = parser.parse_args()
    print("| panel under the ceiling | " + " | ".join(INDIRECT_METHODS) + " |")
    print("|---|" + "---|" * len(INDIRECT_METHODS))
    for gap in (0.4, 0.05):
        built = room_lit_by_a_panel()
        built.objects["Panel"].location.z = CEILING - gap - 2.95  # the quad's own height is 2.95
        reference = cycles_reference(built, "one_bounce", args.samples)
        scene = scene_to_render(built, SIZE)
        ratios = [render_once(scene, Settings(width=SIZE[0], height=SIZE[1], indirect_method=method, bounces=1))
                  .passes["indirect"].mean() / reference.indirect.mean() for method in INDIRECT_METHODS]
        print(f"| {gap * 100:.0f} cm | " + " | ".join(f"{ratio:.2f}" for ratio in ratios) + " |", flush=True)


if __name__ == "__main__":
    main()
