"""The viewport's own work, as it redraws after each kind of change, on the GPU: per scene
and preset the wall-clock milliseconds of a camera move, a light edit, a material edit and
an emitter frame, each the median over many frames with its least and most, and the
stages' medians beside it.

    python scripts/time_viewport_work.py DIR NAME [NAME ...] [--frames 20]
        [--presets defaults,fast,balanced,accurate] [--emitters 1048576]

NAME is DIR/NAME.npz (`python -m lpv_preview export NAME`) or `room1200k`, a closed room of
1,228,800 triangles around a point light (bench/synthetic.py room_scene), made here, or
`room1200k_glossy`, the same with the Principled BSDF's default glossy layer everywhere. Every
frame is one `Pipeline.render` of one VPL set at 1920×1080 with the combined image read
into a float buffer, as a viewport redraw does (`display_into`), after a frame of the
same scene that warms it up (for half a second):
- camera move: the camera turned a quarter of a degree a frame (the grids stay);
- light edit: the first lamp's power 1 % up and down in turn (its maps are redone);
- material edit: every surface's albedo 1 % up and down in turn (the mesh is uploaded again);
- emitter frame: a room of `--emitters` point emitters that all move every frame
  (bench/synthetic.py particle_room with a new seed), once per preset.
Prints the report as JSON.
"""
import argparse
import dataclasses
import json
import statistics
import time

import numpy as np

from lpv_preview.bench.synthetic import particle_room, room_scene
from lpv_preview.bench.timing import THROUGHPUT_WARM_UP_SECONDS
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene_edits import camera_path
from lpv_preview.gpu.scene_file import load_scene
from lpv_preview.gpu.settings import preset_settings

SIZE = (1920, 1080)
TURN_DEGREES = 0.25
SYNTHETIC = {"room1200k": lambda: room_scene(320), "room1200k_glossy": lambda: glossy(room_scene(320))}


def glossy(scene):
    """`scene` with the Principled BSDF's default glossy layer on every surface (F0 0.04,
    roughness 0.5), as an artist's scene has it."""
    return dataclasses.replace(scene, specular=np.tile(np.float32([0.04, 0.04, 0.04, 0.5, 0.0]),
                                                       (len(scene.triangles), 1)))


def edited_frames(scene, edit, frames):
    """The scenes of `frames` redraws after edits of kind `edit`, the first one's before it.
    As the add-on's are, each is the last one with a part replaced: what it keeps keeps its
    content keys (gpu/scene.py), made once here."""
    scene.sanitize()
    scene.geometry_key(), scene.point_emitters_key(), scene.bounds()
    if edit == "camera move":
        return [dataclasses.replace(scene, camera=camera) for camera in
                camera_path(scene.camera, frames + 1, degrees=TURN_DEGREES * frames / 2)]
    if edit == "light edit":
        first = scene.lights[0]
        return [dataclasses.replace(scene, lights=[dataclasses.replace(first, power=first.power * (1.01 if i % 2 else 1.0)),
                                                   *scene.lights[1:]]) for i in range(frames + 1)]
    if edit == "material edit":
        return [dataclasses.replace(scene, albedo=np.ascontiguousarray(scene.albedo * np.float32(0.99 if i % 2 else 1.0)),
                                    _geometry_key=None) for i in range(frames + 1)]
    raise ValueError(edit)


def timed(pipeline, scenes, display):
    """Wall-clock milliseconds of each redraw after the first, and the stages of each. The
    first is drawn for THROUGHPUT_WARM_UP_SECONDS first: the GPU's clocks drop while the
    CPU builds the next case's scenes (bench/timing.py)."""
    warm_up_until = time.perf_counter() + THROUGHPUT_WARM_UP_SECONDS
    while True:
        pipeline.invalidate()
        pipeline.render(scenes[0], passes=(), display_into=display)
        if time.perf_counter() >= warm_up_until:
            break
    times, stages = [], []
    for scene in scenes[1:]:
        began = time.perf_counter()
        frame = pipeline.render(scene, passes=(), display_into=display)
        times.append((time.perf_counter() - began) * 1000.0)
        stages.append({key: value for key, value in frame.stats.items() if key.endswith("_ms") and key != "total_ms"})
    names = sorted({key for s in stages for key in s})
    return {"frame_ms": round(statistics.median(times), 2), "least_ms": round(min(times), 2),
            "most_ms": round(max(times), 2),
            "stages": {key: round(statistics.median(s.get(key, 0.0) for s in stages), 2) for key in names
                       if statistics.median(s.get(key, 0.0) for s in stages) >= 0.05}}


def main():
    parser = argparse.ArgumentParser(description="the viewport's own work on the GPU")
    parser.add_argument("folder")
    parser.add_argument("names", nargs="+")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--presets", default="defaults,fast,balanced,accurate")
    parser.add_argument("--emitters", type=int, default=1 << 20)
    args = parser.parse_args()
    display = np.empty(SIZE[0] * SIZE[1] * 4, dtype=np.float32)
    runs, renderer = {}, None
    presets = args.presets.split(",")
    for name in args.names:
        scene = SYNTHETIC[name]() if name in SYNTHETIC else load_scene(f"{args.folder}/{name}.npz")
        for preset in presets:
            settings = preset_settings(None if preset == "defaults" else preset, width=SIZE[0], height=SIZE[1])
            for edit in ("camera move", "light edit", "material edit"):
                if edit == "light edit" and not scene.lights:
                    continue
                pipeline = Pipeline(settings)
                try:
                    runs[f"{name}, {preset}, {edit}"] = timed(pipeline, edited_frames(scene, edit, args.frames), display)
                    renderer = pipeline.glc.renderer
                finally:
                    pipeline.release()
                print(f"{name}, {preset}, {edit}: {runs[f'{name}, {preset}, {edit}']['frame_ms']} ms", flush=True)
    scenes = [particle_room(args.emitters, seed=seed) for seed in range(args.frames + 1)]
    for preset in presets:
        settings = preset_settings(None if preset == "defaults" else preset, width=SIZE[0], height=SIZE[1])
        pipeline = Pipeline(settings)
        try:
            runs[f"particles, {preset}, emitter frame"] = timed(pipeline, scenes, display)
        finally:
            pipeline.release()
        print(f"particles, {preset}, emitter frame: {runs[f'particles, {preset}, emitter frame']['frame_ms']} ms",
              flush=True)
    print(json.dumps({"renderer": renderer, "frames": args.frames, "size": SIZE, "emitters": args.emitters,
                      "runs": runs}, indent=1))


if __name__ == "__main__":
    main()
