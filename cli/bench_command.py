"""`bench`: Table 1 by default, or the one measurement a flag of BENCH_MODES picks."""
import os
import sys
from dataclasses import dataclass

from .. import demo
from ..bench.artist import CONVERGE_SETS
from ..gpu.errors import LPVError
from .bench_blender import (ARTIST_SAMPLES, ARTIST_SIZE, EMITTER_CYCLES_COUNTS, EMITTER_CYCLES_SAMPLES,
                            EMITTER_CYCLES_SIZE, bench_artist, bench_corrections, bench_cycles_indirect, bench_sample_workers, bench_scene, blender_available,
                            check_bench_scenes, particle_cases)
from .flags import check_setting_flags, check_writable, command_line, positive_int, settings_from


def bench_report(args, log):
    from ..bench.sweep_report import read_sweep_report, write_sweep_outputs
    check_writable(args.out)
    same_folder = os.path.abspath(args.out) == os.path.abspath(os.path.dirname(args.report))
    return write_sweep_outputs(read_sweep_report(args.report), args.out, write_json=not same_folder)


def bench_page(args, log):
    from ..bench.page import write_benchmarks_page
    check_writable(os.path.dirname(args.page))
    return write_benchmarks_page(args.page)


def bench_invariance(args, log):
    from ..bench.invariance import measure_invariances, write_invariances
    check_writable(args.out)
    return write_invariances(measure_invariances(log=log), args.out, command_line(args))


def bench_workers(args, log):
    check_writable(args.out)
    return bench_sample_workers(args, log)


def bench_corrected(args, log):
    check_setting_flags(args)
    if args.width is not None or args.height is not None:
        raise LPVError("bench --corrections renders each demo scene at its own size (bench/corrections.py "
                       "SCENES); leave out --width and --height.")
    check_writable(args.out)
    return bench_corrections(args, log)


def bench_emitters(args, log):
    from ..bench.emitters import (emitter_bench_size, measure_against_cycles, measure_emitter_counts,
                                  measure_many_lights, write_emitter_report)
    check_writable(args.out)
    counts = tuple(4 ** k for k in range(args.emitters_up_to + 1))
    width, height = emitter_bench_size()
    report = {"counts": [measure_emitter_counts(counts, width, height, resolution, log=log)
                         for resolution in (32, 64)],
              "lights": measure_many_lights(log=log), "command": command_line(args)}
    if blender_available():
        report["cycles"] = {**measure_against_cycles(particle_cases(EMITTER_CYCLES_COUNTS, *EMITTER_CYCLES_SIZE,
                                                                    EMITTER_CYCLES_SAMPLES),
                                                     *EMITTER_CYCLES_SIZE, log=log),
                            "samples": EMITTER_CYCLES_SAMPLES}
    return write_emitter_report(report, args.out)


def bench_artist_suite(args, log):
    check_setting_flags(args)
    check_writable(args.out)
    return bench_artist(args, log)


def bench_fuzz(args, log):
    from ..bench.fuzz import fuzz
    report = fuzz(range(args.fuzz), log=log)
    if report["failures"]:
        raise LPVError(f"{len(report['failures'])} of {args.fuzz} fuzzed scenes failed, the first with seed "
                       f"{report['failures'][0]['seed']}: {report['failures'][0]['detail'].splitlines()[-1]}")
    return report


def bench_sweep(args, log):
    from ..bench.sweep import SWEEPS_FILE, load_sweep, run_sweep
    from ..bench.sweep_report import write_sweep_outputs
    check_writable(args.out)
    sweep = load_sweep(args.sweep, args.sweeps or SWEEPS_FILE)
    report = run_sweep(args.sweep, sweep, bench_scene, log=log, cycles_indirect=bench_cycles_indirect)
    report["command"] = command_line(args)
    return {**write_sweep_outputs(report, args.out), "points": len(report["points"]), "seconds": report["seconds"]}


def bench_table1(args, log):
    from ..bench.sweep_report import scene_label
    from ..bench.table1 import BUDGETS, run_table1, write_table1
    check_writable(args.out)
    items = (args.scenes or ",".join(demo.LAMP_SCENES)).split(",")
    check_bench_scenes(items)
    scenes = [(scene_label(item), lambda item=item: bench_scene(item)) for item in items]
    budgets = BUDGETS if args.budget == "both" else (args.budget,)
    report = run_table1(scenes, settings_from(args, 960, 540), args.methods, args.frames, args.repeats, budgets,
                        command_line(args), log)
    write_table1(report, args.out)
    return {"out": args.out, "scenes": len(scenes), "methods": list(args.methods), "machine": report["machine"]}


@dataclass(frozen=True)
class BenchMode:
    """A measurement `bench` makes instead of Table 1 when its flag is given: the flag's
    argparse keywords and the function run(args, log) -> result."""

    flag: str
    argument: dict
    run: object

    @property
    def dest(self):
        return self.flag[2:].replace("-", "_")


BENCH_MODES = (
    BenchMode("--report", {"help": "write the Markdown and plots of this sweep_NAME.json again"}, bench_report),
    BenchMode("--page", {"help": "write this benchmarks page (docs/benchmarks.md) from the reports in the folder "
                                 "bench beside it, their tables and plots again too"}, bench_page),
    BenchMode("--invariance", {"action": "store_true",
                               "help": "measure the invariances (translation, grid shift, light frame, scale) per "
                                       "method on the closed room (invariance.json and invariance.md in --out)"},
              bench_invariance),
    BenchMode("--sample-workers", {"action": "store_true",
                                   "help": "measure Cycles sample requests (fixed cost, cost a sample) and samples a "
                                           "second with 1, 2 and 4 Dask workers (sample_workers.json, "
                                           "sample_workers.md)"}, bench_workers),
    BenchMode("--corrections", {"action": "store_true",
                                "help": "the preview corrected toward Cycles by sample workers against Cycles "
                                        "progressive and denoised, error over wall time, on the demo scenes lit by "
                                        "lamps (corrections.json, .md, plots; minutes, and the references the first "
                                        "time); the setting flags are the previews'"}, bench_corrected),
    BenchMode("--emitters", {"action": "store_true",
                             "help": "measure the emitter grid against the emitter count (1 to 4^N, --emitters-up-to) "
                                     "and 64 point lights against one (emitters.json, emitters.md)"}, bench_emitters),
    BenchMode("--artist", {"action": "store_true",
                            "help": f"the artist-scene suite (demo/artist/, or --scenes of it) against Cycles' Combined "
                                    f"at --samples (default {ARTIST_SAMPLES}): one frame and a converged frame of ours (--converge-sets, "
                                    f"default {CONVERGE_SETS}), "
                                    f"EEVEE, Cycles 1 spp + OIDN; mean ratio, HDR-FLIP, relMSE and the goals (artist.json, "
                                    f"artist.md) at --width (default {ARTIST_SIZE[0]}, 16:9)"}, bench_artist_suite),
    BenchMode("--fuzz", {"type": positive_int, "metavar": "N",
                         "help": "render N seeded random scenes; any that neither renders finite bounded light nor "
                                 "stops with one sentence is a failure (exit 2)"}, bench_fuzz),
    BenchMode("--sweep", {"help": "run this sweep of bench/sweeps.toml (or --sweeps FILE) instead of Table 1"},
              bench_sweep),
)
"""The measurements besides Table 1, in the order a flag is looked for when several are given."""


def add_bench_modes(parser):
    for mode in BENCH_MODES:
        parser.add_argument(mode.flag, **mode.argument)


def command_bench(args):
    """Table 1 on demo scenes (built with bpy) or .npz scene files (no Blender needed), or
    the measurement of the first BENCH_MODES flag given."""
    log = lambda line: print(line, file=sys.stderr, flush=True)  # noqa: E731
    for mode in BENCH_MODES:
        if getattr(args, mode.dest):
            return mode.run(args, log)
    return bench_table1(args, log)
