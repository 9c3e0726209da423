"""What the point emitters' shadows (gpu/emitter_shadows.py) take from the light, on the
synthetic scenes of bench/synthetic.py at 160 x 120, as lines on stdout:

    .venv/bin/python scripts/emitter_shadow_figures.py

For an open room (1,000 particles; 64 lamps beyond the light-map budget over a floor):
the mean of the direct light with shadows over without, the share of pixels darkened
below 0.9 and the least ratio; for 2,000 particles shut in a closed box: the light
outside with shadows as a share of that without.
"""
import numpy as np

from lpv_preview.bench.synthetic import lamps_over_floor, particle_room, particles_in_a_box
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings


def direct_light(scene, shadows):
    pipeline = Pipeline(Settings(width=160, height=120, emitter_shadows=shadows, light_map_budget=0))
    try:
        return pipeline.render(scene, passes=("direct",)).passes["direct"]
    finally:
        pipeline.release()


def main():
    for name, scene in (("1,000 particles", particle_room(1000)), ("64 lamps", lamps_over_floor(64))):
        shaded, unshaded = direct_light(scene, True), direct_light(scene, False)
        lit = unshaded.mean(axis=-1) > 1e-4
        ratio = shaded.mean(axis=-1)[lit] / unshaded.mean(axis=-1)[lit]
        print(f"{name}: with shadows {shaded.mean() / unshaded.mean():.4f} of the light without, "
              f"{(ratio < 0.9).mean() * 100:.1f} % of the pixels below 0.9, the least {ratio.min():.2f}")
    box = particles_in_a_box()
    print(f"particles in a closed box: outside {direct_light(box, True).mean() / direct_light(box, False).mean() * 100:.2f} "
          "% of the light without shadows")


if __name__ == "__main__":
    main()
