"""``rubberfriction bench NAME``: benchmarks that print figures (speed and memory live here, not
in tests)."""

from __future__ import annotations

import argparse
import importlib

BENCHMARKS = {
    "bulk": ("rubberfriction.driver.bench.bulk",
             "Newton iteration cost of the viscoelastic block vs dofs"),
    "contact": ("rubberfriction.driver.bench.contact",
                "contact search/assembly scaling, Hertz error vs time"),
    "surfaces": ("rubberfriction.driver.bench.surfaces",
                 "decomposition of a 2-million-point profile"),
    "theory": ("rubberfriction.driver.bench.theory",
               "50-velocity mu(v) curve from the analytical theories"),
    "sliding": ("rubberfriction.driver.bench.sliding",
                "micro-cell speed-accuracy and stability sweep"),
    "multiscale": ("rubberfriction.driver.bench.multiscale",
                   "default scene and four-scale point, serial vs ranks"),
    "farm": ("rubberfriction.driver.bench.farm",
             "a finished campaign replayed on N ranks: wall time, speed-up"),
    "trade": ("rubberfriction.driver.bench.trade",
              "speed-accuracy trade of one mu point: mesh, penalty, samples"),
    "cutoff": ("rubberfriction.driver.bench.cutoff",
               "cut-off sensitivity: mu(v) at several max_slope, FE next to Persson"),
    "periods": ("rubberfriction.driver.bench.periods",
                "periods to the periodic steady state with and without slow-mode extrapolation"),
    "thermal": ("rubberfriction.driver.bench.thermal",
                "thermal macro scale: z-resolution study, T_R and T_C over v"),
    "thermal-loop": ("rubberfriction.driver.bench.thermal_loop",
                     "thermal multiscale loop: partitions n_p (8.4.2) and divisions n_d (8.4.3)"),
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("bench", help="run a benchmark and print its figures",
                       description="Benchmarks: " + "; ".join(f"{k}: {v[1]}"
                                                              for k, v in BENCHMARKS.items()))
    p.add_argument("name", choices=sorted(BENCHMARKS), help="which benchmark")
    p.add_argument("args", nargs=argparse.REMAINDER,
                   help="options passed to the benchmark (see NAME --help)")
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    module_name, _ = BENCHMARKS[args.name]
    module = importlib.import_module(module_name)
    return int(module.main(args.args) or 0)
