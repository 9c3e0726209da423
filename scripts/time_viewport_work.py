"""The viewport's own work, as it redraws after each kind of change, on the GPU: per scene
and preset the wall-clock milliseconds of a camera move, a light edit, a material edit and
an emitter frame, each the median over many frames with its least and most, and the
stages' medians beside it.

    python scripts/time_viewport_work.py DIR [NAME ...] [--frames 20]
        [--presets defaults,fast,balanced,accurate] [--emitters 1048576]

NAME is DIR/NAME.npz (`python -m lpv_preview export NAME`) or `room1200k`, a closed room of
1,228,800 triangles around a point light (bench/synthetic.py NAMED_SCENES), made here, or
`room1200k_glossy`, the same with the Principled BSDF's default glossy layer everywhere, or
`room1200k_boxed_lamp`, the same with a second lamp shut in a closed box on the floor (a room:
gpu/closed_meshes.py), and `room1200k_boxed_lamp_no_rooms`, the same with no rooms. Every
frame is one `Pipeline.render` of one VPL set at 1920×1080 with the combined image read
into a float buffer, as a viewport redraw does (`display_into`), after a frame of the
same scene that warms it up (for half a second): camera moves, light edits and material
edits as bench/viewport_work.py makes them, and emitter frames, a room of `--emitters`
point emitters that all move every frame (bench/synthetic.py particle_room with a new
seed), once per preset (with no NAME, the emitter frames alone).
Prints the report as JSON.
"""
import argparse
import json

from lpv_preview.bench.synthetic import particle_room, scene_by_name
from lpv_preview.bench.viewport_work import EDITS, display_buffer, edited_frames, timed_redraws
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import preset_settings

SIZE = (1920, 1080)


def main():
    parser = argparse.ArgumentParser(description="the viewport's own work on the GPU")
    parser.add_argument("folder")
    parser.add_argument("names", nargs="*")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--presets", default="defaults,fast,balanced,accurate")
    parser.add_argument("--emitters", type=int, default=1 << 20)
    args = parser.parse_args()
    display = display_buffer(preset_settings(None, width=SIZE[0], height=SIZE[1]))
    runs, renderer = {}, None
    presets = args.presets.split(",")
    for name in args.names:
        scene = scene_by_name(args.folder, name)
        for preset in presets:
            settings = preset_settings(None if preset == "defaults" else preset, width=SIZE[0], height=SIZE[1])
            for edit in EDITS:
                if edit == "light edit" and not scene.lights:
                    continue
                pipeline = Pipeline(settings)
                try:
                    runs[f"{name}, {preset}, {edit}"] = timed_redraws(pipeline, edited_frames(scene, edit, args.frames), display)
                    renderer = pipeline.glc.renderer
                finally:
                    pipeline.release()
                print(f"{name}, {preset}, {edit}: {runs[f'{name}, {preset}, {edit}']['frame_ms']} ms", flush=True)
    scenes = [particle_room(args.emitters, seed=seed) for seed in range(args.frames + 1)]
    for preset in presets:
        settings = preset_settings(None if preset == "defaults" else preset, width=SIZE[0], height=SIZE[1])
        pipeline = Pipeline(settings)
        try:
            runs[f"particles, {preset}, emitter frame"] = timed_redraws(pipeline, scenes, display)
            renderer = pipeline.glc.renderer
        finally:
            pipeline.release()
        print(f"particles, {preset}, emitter frame: {runs[f'particles, {preset}, emitter frame']['frame_ms']} ms",
              flush=True)
    print(json.dumps({"renderer": renderer, "frames": args.frames, "size": SIZE, "emitters": args.emitters,
                      "runs": runs}, indent=1))


if __name__ == "__main__":
    main()
