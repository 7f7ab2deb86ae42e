"""Benchmark of the surface pipeline: decompose a long profile into four scales with samples.

The issue's figure: time to decompose a 2-million-point profile into the four thesis scales
(20-3-0.3-0.04-0.003 mm) with ten periodic samples each.  The profile is a self-affine random
profile (H = 0.8, 1.5 um spacing, 3 m long) treated as a *measured*, non-periodic record, so
the mirror-extended (DCT) filter path of real data is timed.  Steps timed separately: PSD
(Hann window, log-binned), band split (4 bands), the multiscale decomposition (4 bands + 4
carriers from one spectrum) and the sample extraction with periodic closure (4 x n samples).

    /usr/bin/python3 -m rubberfriction bench surfaces            # via the bench command
    /usr/bin/python3 -m rubberfriction.driver.bench.surfaces --points 2000000 --samples 10
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from typing import Any, Callable

import numpy as np

from rubberfriction.driver.surfaces import (
    band_split,
    log_bin,
    multiscale_from_measurements,
    psd_1d,
    self_affine_profile,
)
from rubberfriction.driver.surfaces.default_road import DEFAULT_EDGES
from rubberfriction.driver.surfaces.profile import Profile


def _best(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run(points: int = 2_000_000, samples: int = 10, seed: int = 1, repeat: int = 1,
        dx: float = 0.0015) -> dict[str, Any]:
    """Run the benchmark and return the timings (s) and sizes."""

    t_gen, prof = _best(lambda: self_affine_profile(points * dx, dx, H=0.8, rms_height=1.0,
                                                    q_rolloff=2 * np.pi / 20.0, seed=seed), 1)
    meta = dict(prof.meta)
    meta["periodic"] = False
    meta["provenance"] = {"kind": "measured", "note": "benchmark stand-in for a measured scan"}
    prof = Profile(prof.x, prof.h, "mm", "benchmark profile", meta)

    t_psd, _ = _best(lambda: log_bin(*psd_1d(prof, window="hann", detrend="linear")), repeat)
    t_split, bands = _best(lambda: band_split(prof, DEFAULT_EDGES), repeat)
    t_ms, road = _best(lambda: multiscale_from_measurements([prof], DEFAULT_EDGES), repeat)
    t_smp, smp = _best(lambda: road.extract_samples(samples, seed), repeat)
    total = t_ms + t_smp
    return {
        "points": prof.n,
        "dx_mm": dx,
        "length_mm": prof.length,
        "edges_mm": list(DEFAULT_EDGES),
        "samples_per_scale": samples,
        "n_samples": sum(len(g) for g in smp),
        "time_generate_s": t_gen,
        "time_psd_s": t_psd,
        "time_band_split_s": t_split,
        "time_multiscale_s": t_ms,
        "time_samples_s": t_smp,
        "time_decompose_total_s": total,
        "band_rms_mm": [b.rms_height() for b in bands],
        "repeat": repeat,
    }


def main(argv: list[str] | None = None) -> int:
    """Print the benchmark figures; ``--json FILE`` also writes them."""
    ap = argparse.ArgumentParser(prog="bench_surfaces", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=2_000_000)
    ap.add_argument("--samples", type=int, default=10)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=1, help="repeat each step, report the best")
    ap.add_argument("--json", help="write the figures to this file")
    args = ap.parse_args(argv)
    r = run(args.points, args.samples, args.seed, args.repeat)
    print(f"surface pipeline benchmark: {r['points']} points, dx {r['dx_mm']} mm, "
          f"length {r['length_mm']:.0f} mm, edges {r['edges_mm']} mm")
    print(f"  generate self-affine profile  {r['time_generate_s']:8.3f} s")
    print(f"  PSD (Hann, log-binned)        {r['time_psd_s']:8.3f} s")
    print(f"  band split, 4 bands           {r['time_band_split_s']:8.3f} s")
    print(f"  multiscale (bands + carriers) {r['time_multiscale_s']:8.3f} s")
    print(f"  samples, {r['n_samples']:3d} with closure      {r['time_samples_s']:8.3f} s")
    print(f"  decompose into 4 scales with {args.samples} samples each: "
          f"{r['time_decompose_total_s']:.3f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(r, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
