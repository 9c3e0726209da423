"""What a still view's refinement costs on the GPU and what a camera move costs after it:
per scene, at 1920×1080 with the display read as a viewport does, the wall-clock
milliseconds (median, least, most over 10 rounds) of a VPL set at the finer grids
(Settings.refined), the first and second camera moves after them (which keep the finer
grids, as the viewport does), a camera move at the coarser grids, and the first move
after refining had it gone back to the coarser grids (their light made again).

    python scripts/time_refined_moves.py DIR NAME [NAME ...]

NAME is DIR/NAME.npz (`scripts/full_gi_rooms.py DIR --export`) or `room1200k`
(bench/synthetic.py NAMED_SCENES). Prints the figures as JSON.
"""
import argparse
import json
import statistics
import time

from lpv_preview.bench.synthetic import scene_by_name
from lpv_preview.bench.viewport_work import display_buffer, edited_frames
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings

ROUNDS = 10
CASES = ("refined set", "first move after refining", "second move after refining", "move at the coarser grids",
         "first move after refining, at the coarser grids")


def timed(runs, case, render):
    start = time.perf_counter()
    render()
    runs[case].append((time.perf_counter() - start) * 1000.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("names", nargs="+")
    args = parser.parse_args()
    settings = Settings(width=1920, height=1080)
    report = {}
    for name in args.names:
        scene = scene_by_name(args.folder, name)
        moves = edited_frames(scene, "camera move", 4 * ROUNDS)
        pipeline, display = Pipeline(settings), display_buffer(settings)
        fine = settings.refined(pipeline.glc.is_software)
        runs = {case: [] for case in CASES}
        try:
            for first in range(0, 4 * ROUNDS, 4):
                pipeline.render(moves[first], settings, passes=(), display_into=display)  # an edit's first frame
                for _ in range(2):
                    timed(runs, CASES[0], lambda: pipeline.render(moves[first], fine, passes=(), display_into=display,
                                                                  vpl_set=pipeline.vpl_pattern + 1, accumulate=True))
                timed(runs, CASES[1], lambda: pipeline.render(moves[first + 1], fine, passes=(), display_into=display))
                timed(runs, CASES[2], lambda: pipeline.render(moves[first + 2], fine, passes=(), display_into=display))
                pipeline.render(moves[first + 2], settings, passes=(), display_into=display)
                timed(runs, CASES[3], lambda: pipeline.render(moves[first + 3], settings, passes=(), display_into=display))
                for _ in range(2):
                    pipeline.render(moves[first + 3], fine, passes=(), display_into=display,
                                    vpl_set=pipeline.vpl_pattern + 1, accumulate=True)
                timed(runs, CASES[4], lambda: pipeline.render(moves[first + 4], settings, passes=(), display_into=display))
            report[name] = {"renderer": pipeline.glc.renderer, "finer grids": fine.lpv_resolution,
                            **{case: [round(statistics.median(v), 2), round(min(v), 2), round(max(v), 2)]
                               for case, v in runs.items()}}
        finally:
            pipeline.release()
        print(name, report[name], flush=True)
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
