"""``rubberfriction surface ...``: analyse road profiles, split them into scales, make samples.

Subcommands
-----------
``analyse FILE``   defects, rms height/slope, PSD (with power-law fit) and HDC (eq. 2.5 fit);
                   ``--plot out.png`` (profile, PSD with band edges, HDC with fit), ``--json``.
``split FILE...``  band-pass scales (eq. 6.10) from one or several measurements of a surface
                   (each band from the coarsest file that resolves it) and periodic samples:
                   ``--edges 20 3 0.3 --samples 10 --seed 1 --out DIR``.
``default``        the embedded default road (CAPTIF measured + self-affine generated) with its
                   samples: ``--out DIR``.
``generate KIND``  synthetic profiles: ``self-affine``, ``two-sine`` (eqs. 6.7-6.8),
                   ``sawtooth`` (ch. 6.4.1) to CSV.
``compare FILE``   the three decompositions of thesis fig. 6.5 side by side (``--plot``).
"""

from __future__ import annotations

import argparse
import functools
import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction import validation as V
from rubberfriction.validation import InputError

#: Keyword arguments of the surface library that are command-line options here: a library
#: message's hint ``pass x_col= and h_col=`` reads ``pass --x-col and --h-col`` on the command
#: line, ``units='auto'`` reads ``--units auto``.
_KEYWORD_OPTIONS = ("x_col", "h_col", "dx", "dataset", "skiprows", "delimiter", "units", "max_gap",
                    "long_gaps", "edges", "cutoff", "max_slope", "top_fraction", "samples", "seed")
_NAMES = "|".join(_KEYWORD_OPTIONS)


def option_message(message: str) -> str:
    """A surface library message with its keyword arguments written as this command's options
    (``x_col=`` -> ``--x-col``, ``units='auto'`` -> ``--units auto``, ``max_gap = 9.6`` ->
    ``--max-gap 9.6``)."""
    def flag(m: re.Match) -> str:
        return "--" + m.group(1).replace("_", "-")

    message = re.sub(rf"\b({_NAMES})=(['\"])([^'\"]*)\2", lambda m: f"{flag(m)} {m.group(3)}",
                     message)
    message = re.sub(rf"\b({_NAMES}) = ", lambda m: f"{flag(m)} ", message)
    return re.sub(rf"\b({_NAMES})=", flag, message)


#: (option, what, bounds) of the numeric options of the surface commands (those a command has).
_NUMERIC_OPTIONS: tuple[tuple[str, str, str, dict[str, float]], ...] = (
    ("dx", "--dx", "a sample spacing", {"above": 0.0}),
    ("skiprows", "--skiprows", "a number of header lines", {"minimum": 0}),
    ("max_gap", "--max-gap", "a gap length", {"above": 0.0}),
    ("edges", "--edges", "band edges (wavelengths)", {"above": 0.0}),
    ("psd_fit", "--psd-fit", "wavelengths", {"above": 0.0}),
    ("hdc_range", "--hdc-range", "lags", {"above": 0.0}),
    ("max_slope", "--max-slope", "an rms slope", {"above": 0.0}),
    ("samples", "--samples", "a number of samples", {"minimum": 1}),
    ("top_fraction", "--top-fraction", "a fraction of the carrier",
     {"above": 0.0, "maximum": 1.0}),
    ("length", "--length", "a profile length", {"above": 0.0}),
    ("hurst", "--hurst", "a Hurst exponent", {"above": 0.0, "maximum": 1.0}),
    ("rms", "--rms", "an rms height", {"above": 0.0}),
    ("rolloff", "--rolloff", "a roll-off wavelength", {"above": 0.0}),
    ("cutoff", "--cutoff", "a cut-off wavelength", {"above": 0.0}),
    ("wavelength", "--wavelength", "a wavelength", {"above": 0.0}),
    ("height", "--height", "a peak-to-valley height", {"above": 0.0}),
    ("steep_fraction", "--steep-fraction", "a fraction of the period",
     {"above": 0.0, "below": 1.0}),
)
_MM = {"dx", "max_gap", "edges", "psd_fit", "hdc_range", "length", "rms", "rolloff", "cutoff",
       "wavelength", "height"}


def check_options(args: argparse.Namespace) -> None:
    """Raise an :class:`InputError` naming the first impossible option as typed
    (``--dx -1: expected a sample spacing > 0 in mm``) before a surface command reads anything."""
    for name, flag, what, bounds in _NUMERIC_OPTIONS:
        value = getattr(args, name, None)
        if isinstance(value, str):  # ``surface default --cutoff slope``: checked by parse_cutoff
            continue
        V.option(flag, value, what=what, unit="mm" if name in _MM else "", **bounds)
    for name, flag, what in (("edges", "--edges", "at least two band edges in mm, descending"),
                             ("psd_fit", "--psd-fit", "LAMBDA_LONG > LAMBDA_SHORT"),
                             ("hdc_range", "--hdc-range", "LO < HI")):
        value = getattr(args, name, None)
        if value is None:
            continue
        descending = name != "hdc_range"
        steps = np.diff(value)
        if len(value) < 2 or not (np.all(steps < 0) if descending else np.all(steps > 0)):
            raise InputError(f"{flag} {' '.join(f'{v:g}' for v in value)}: expected {what}")
    units = getattr(args, "units", None)
    if units is not None and units != "auto":
        from rubberfriction.driver.surfaces.profile import UNIT_TO_MM, unit_factor

        try:
            unit_factor(units)
        except InputError:
            raise InputError(f"--units {units}: expected 'auto' or one of "
                             f"{', '.join(sorted(set(UNIT_TO_MM)))}") from None


def _options_in_errors(command: Callable[[argparse.Namespace], int]
                       ) -> Callable[[argparse.Namespace], int]:
    """Run a surface command after checking its options; an input error's message names the
    options as typed here (the ``rubberfriction`` command prints it as one line)."""
    @functools.wraps(command)
    def run(args: argparse.Namespace) -> int:
        check_options(args)
        try:
            return command(args)
        except InputError as err:
            raise type(err)(option_message(str(err))) from None

    return run


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    if hasattr(obj, "to_dict"):
        return _jsonable(obj.to_dict())
    return obj


def _write_json(path: str | Path, data: dict[str, Any]) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_jsonable(data), indent=2))


def _add_reader_args(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("reading")
    g.add_argument("--delimiter",
                   help="column delimiter (default: detected); 'tab', ',', ';', 'whitespace'")
    g.add_argument("--skiprows", type=int, help="header lines (default: detected)")
    g.add_argument("--x-col", help="position column, index or header name (default: detected)")
    g.add_argument("--h-col", help="height column, index or header name (default: detected)")
    g.add_argument("--units", default="mm",
                   help="units in the file, or 'auto' from the header (default mm)")
    g.add_argument("--dx", type=float, help="spacing for files without a position column")
    g.add_argument("--dataset", help="HDF5 dataset of heights")
    g.add_argument("--invert", action="store_true", help="heights increase downwards in the file")
    g.add_argument("--max-gap", type=float,
                   help="longest gap (mm) to interpolate (default 0.5 %% of the scan)")
    g.add_argument("--long-gaps", choices=("longest", "error"), default="longest",
                   help="longer gaps: keep the longest stretch between them, or fail")
    g.add_argument("--no-outliers", action="store_true", help="do not detect outliers")


def _col(v: str | None) -> int | str | None:
    if v is None:
        return None
    return int(v) if v.lstrip("-").isdigit() else v


def _load(path: str, args: argparse.Namespace):
    from rubberfriction.driver.surfaces import load_profile

    delim = {"tab": "\t", "\\t": "\t"}.get(args.delimiter, args.delimiter)
    return load_profile(
        path, delimiter=delim, skiprows=args.skiprows, x_col=_col(args.x_col),
        h_col=_col(args.h_col), units=args.units, dx=args.dx, dataset=args.dataset,
        invert=args.invert, max_gap=args.max_gap, long_gaps=args.long_gaps,
        outliers=not args.no_outliers,
    )


def _cmd_analyse(args: argparse.Namespace) -> int:
    from rubberfriction.driver.surfaces import (
        band_split,
        fit_hdc,
        fit_psd_power_law,
        hdc,
        psd_1d,
        rms_from_psd,
    )
    from rubberfriction.driver.surfaces.cutoff import cumulative_slope_2d
    from rubberfriction.driver.surfaces.plots import plot_analysis
    from rubberfriction.driver.surfaces.samples import provenance_kind

    prof = _load(args.file, args)
    window = None if args.window == "none" else args.window
    q, c = psd_1d(prof, window=window, detrend=args.detrend)
    lam_long, lam_short = args.psd_fit if args.psd_fit else (prof.length / 10, 8 * prof.dx)
    pfit = fit_psd_power_law(q, c, (2 * np.pi / lam_long, 2 * np.pi / lam_short))
    lam, ch = hdc(prof)
    lo, hi = args.hdc_range if args.hdc_range else (4 * prof.dx, prof.length / 4)
    hfit = fit_hdc(lam, ch, (lo, hi))
    print(f"file: {prof.source}")
    if "defects" in prof.meta:
        print(str(prof.meta["defects"]))
    print(f"points {prof.n}, dx {prof.dx:.6g} mm, length {prof.length:.6g} mm")
    print(f"rms height {prof.rms_height():.5g} mm, rms slope {prof.rms_slope():.4g}")
    print(f"PSD ({args.window} window, {args.detrend} detrend): "
          f"rms from PSD {rms_from_psd(q, c):.5g} mm")
    print(f"PSD power law over {lam_long:.4g}-{lam_short:.4g} mm: H = {pfit.H:.4f}, "
          f"K = {pfit.K:.4g} mm^(2-2H) (C1D = K q^-(1+2H))")
    print(f"HDC fit eq. (2.5) over {hfit.fit_range[0]:.4g}-{hfit.fit_range[1]:.4g} mm: "
          f"H = {hfit.H:.4f}, "
          f"xi_par = {hfit.xi_par:.4g} mm, xi_perp = {hfit.xi_perp:.4g} mm"
          + ("" if hfit.plateau_found else " (no plateau in range: xi_par is a lower bound)"))
    bands_out = []
    if args.edges:
        bands = band_split(prof, args.edges, allow_unresolved=True)
        cum = cumulative_slope_2d([b.rms_slope() for b in bands])
        kind = provenance_kind(prof)
        for b, c2 in zip(bands, cum):
            lo_b, hi_b = b.meta["band"]
            res = "" if b.meta["resolved"] else " (partly beyond the resolution)"
            print(f"band {lo_b:g}-{hi_b:g} mm ({kind}): rms height {b.rms_height():.5g} mm, rms "
                  f"slope {b.rms_slope():.4g}, cumulative 2D rms slope {c2:.4g}{res}")
            bands_out.append({"band_mm": [lo_b, hi_b], "rms_height_mm": b.rms_height(),
                              "rms_slope": b.rms_slope(), "cumulative_slope_2d": float(c2),
                              "kind": kind, "resolved": b.meta["resolved"]})
        over = [i for i, c2 in enumerate(cum) if c2 > args.max_slope]
        if over:
            lo_b, hi_b = bands[over[0]].meta["band"]
            keep = ("measured bands are kept by the slope rule; a generated continuation below "
                    "would be dropped" if kind != "generated" else
                    "the slope rule would shorten this band and drop the ones below")
            print(f"the cumulative 2D rms slope passes max_slope {args.max_slope:g} in band "
                  f"{lo_b:g}-{hi_b:g} mm: {keep} (scene key [surface] cutoff)")
    if args.plot:
        plot_analysis(prof, q, c, lam, ch, args.plot, edges=args.edges, psd_fit=pfit, hdc_fit=hfit)
        print(f"plot: {args.plot}")
    if args.json:
        _write_json(args.json, {
            "file": prof.source, "n": prof.n, "dx_mm": prof.dx, "length_mm": prof.length,
            "rms_height_mm": prof.rms_height(), "rms_slope": prof.rms_slope(),
            "defects": prof.meta.get("defects"),
            "psd": {"convention": "Persson 1D, two-sided, h_rms^2 = 2 Int_0^inf C1D dq",
                    "window": args.window, "detrend": args.detrend,
                    # the arrays the plot shows: q_k = 2 pi k / L, k = 1 .. N/2 (uniform)
                    "q_1_per_mm": q, "C1D_mm3": c,
                    "power_law_fit": {"H": pfit.H, "K": pfit.K,
                                      "lambda_range_mm": [lam_long, lam_short]}},
            "hdc": {"definition": "eq. (2.4): C_HDC(lambda) = <(h(x + lambda) - h(x))^2>",
                    "lambda_mm": lam, "C_HDC_mm2": ch},
            "hdc_fit": hfit.to_dict(),
            "bands": bands_out,
        })
        print(f"json: {args.json}")
    return 0


def _write_samples(road, samples, out: Path) -> dict[str, Any]:
    from rubberfriction.driver.surfaces import samples_table
    from rubberfriction.driver.surfaces.plots import plot_samples

    out.mkdir(parents=True, exist_ok=True)
    files = []
    for sc, group in zip(road.scales, samples):
        for j, s in enumerate(group):
            f = out / f"{sc.name}_sample{j:02d}.csv"
            s.to_csv(f)
            files.append(f.name)
        print(samples_table(group))
    plot_samples(samples, out / "samples.png", names=road.names)
    summary = {"surface": road.to_dict(), "samples": [[s.summary() for s in g] for g in samples],
               "files": files}
    _write_json(out / "summary.json", summary)
    print(f"wrote {len(files)} samples, summary.json and samples.png to {out}")
    return summary


def _cmd_split(args: argparse.Namespace) -> int:
    from rubberfriction.driver.surfaces import multiscale_from_measurements

    profiles = [_load(f, args) for f in args.files]
    road = multiscale_from_measurements(profiles, args.edges, filter=args.filter,
                                        name=", ".join(Path(f).name for f in args.files))
    print(road.describe())
    samples = road.extract_samples(args.samples, args.seed, top_fraction=args.top_fraction)
    _write_samples(road, samples, Path(args.out))
    return 0


def _cmd_road(args: argparse.Namespace) -> int:
    """``surface default`` / ``surface four-scale``: a shipped road cut by the lowest-scale rule,
    its table, samples and (``--plot``) band PSDs with the cumulative slope."""
    from rubberfriction.driver.surfaces import DEFAULT_EDGES, default_road
    from rubberfriction.driver.surfaces.cutoff import apply_cutoff, parse_cutoff
    from rubberfriction.driver.surfaces.four_scale import FOUR_SCALE_EDGES, four_scale_road
    from rubberfriction.driver.surfaces.plots import plot_road_scales

    rule = parse_cutoff(args.cutoff, args.max_slope)  # a bad one: "--cutoff x: expected ..."
    if args.surface_command == "four-scale":
        road, report = apply_cutoff(four_scale_road, FOUR_SCALE_EDGES, rule)
    else:
        road, report = apply_cutoff(lambda e: default_road(args.shared_data, edges=e),
                                    DEFAULT_EDGES, rule)
    print(road.describe())
    print("\n".join(report.lines()))
    if args.plot:
        print(f"plot: {plot_road_scales(road, report, args.plot)}")
    samples = road.extract_samples(args.samples, args.seed, top_fraction=args.top_fraction)
    _write_samples(road, samples, Path(args.out))
    return 0


def _cmd_generate(args: argparse.Namespace) -> int:
    from rubberfriction.driver.surfaces import (
        sawtooth_profile,
        self_affine_profile,
        two_sine_profile,
    )

    if args.kind == "self-affine":
        qr = 2 * np.pi / args.rolloff if args.rolloff else None
        qs = 2 * np.pi / args.cutoff if args.cutoff else None
        p = self_affine_profile(args.length, args.dx, H=args.hurst, rms_height=args.rms,
                                q_rolloff=qr, q_cutoff=qs, seed=args.seed)
    elif args.kind == "two-sine":
        p = two_sine_profile(args.length, args.dx)
    else:
        p = sawtooth_profile(args.length, args.dx, wavelength=args.wavelength, height=args.height,
                             orientation=args.orientation, steep_fraction=args.steep_fraction)
    p.to_csv(args.out, header=json.dumps(_jsonable(p.meta.get("provenance", {}))))
    print(f"{p.source}: {p.n} points, rms height {p.rms_height():.5g} mm -> {args.out}")
    return 0


def _cmd_compare(args: argparse.Namespace) -> int:
    from rubberfriction.driver.surfaces import compare_decompositions
    from rubberfriction.driver.surfaces.plots import plot_decompositions

    prof = _load(args.file, args)
    res = compare_decompositions(prof, args.edges, seed=args.seed)
    for key, bands in res.items():
        rms = ", ".join(f"{b.meta['band'][0]:g}-{b.meta['band'][1]:g}: {b.rms_height():.4g}"
                        for b in bands)
        print(f"{key:<20} rms height per scale (mm): {rms}")
    if args.plot:
        plot_decompositions(res, args.plot)
        print(f"plot: {args.plot}")
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``surface`` with its subcommands to the ``rubberfriction`` command."""
    p = subparsers.add_parser("surface", help="rough surfaces: analyse, split into scales, samples",
                              description=__doc__,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="surface_command", metavar="SUBCOMMAND")
    p.set_defaults(func=lambda a: (p.print_help(), 2)[1])

    a = sub.add_parser("analyse", aliases=["analyze"], help="defects, PSD, HDC of a profile")
    a.add_argument("file")
    _add_reader_args(a)
    a.add_argument("--window", choices=("hann", "none"), default="hann")
    a.add_argument("--detrend", choices=("mean", "linear"), default="linear")
    a.add_argument("--psd-fit", nargs=2, type=float, metavar=("LAMBDA_LONG", "LAMBDA_SHORT"),
                   help="wavelength range (mm) of the PSD power-law fit")
    a.add_argument("--hdc-range", nargs=2, type=float, metavar=("LO", "HI"),
                   help="lag range (mm) of the HDC fit (default 4 dx .. L/4)")
    a.add_argument("--edges", nargs="+", type=float, help="band edges (mm) to mark and report")
    a.add_argument("--max-slope", type=float, default=1.3,
                   help="cumulative 2D rms slope of the slope cut-off (default 1.3), reported "
                        "with --edges")
    a.add_argument("--plot", help="PNG with profile, PSD and HDC")
    a.add_argument("--json", help="write the results as JSON, with the arrays the plot shows: "
                   "psd.q_1_per_mm, psd.C1D_mm3, hdc.lambda_mm, hdc.C_HDC_mm2")
    a.set_defaults(func=_options_in_errors(_cmd_analyse))

    s = sub.add_parser("split", help="band-pass scales and periodic samples")
    s.add_argument("files", nargs="+", help="one or several measurements of the same surface")
    _add_reader_args(s)
    s.add_argument("--edges", nargs="+", type=float, required=True,
                   help="descending band edges (mm)")
    s.add_argument("--samples", type=int, default=10, help="samples per scale (default 10)")
    s.add_argument("--seed", type=int, default=1)
    s.add_argument("--top-fraction", type=float, default=0.2,
                   help="sample centres in the top fraction of the carrier (default 0.2)")
    s.add_argument("--filter", choices=("ideal", "cosine"), default="ideal")
    s.add_argument("--out", required=True, help="output folder")
    s.set_defaults(func=_options_in_errors(_cmd_split))

    roads = (("default", "the embedded default road (CAPTIF + generated extension)"),
             ("four-scale", "the synthetic four-scale road (driver.surfaces.four_scale)"))
    for name, what in roads:
        d = sub.add_parser(name, help=f"{what}: its scales under the cut-off rule, samples")
        d.add_argument("--out", required=True, help="output folder")
        d.add_argument("--samples", type=int, default=10)
        d.add_argument("--seed", type=int, default=1)
        d.add_argument("--top-fraction", type=float, default=0.2)
        if name == "default":
            d.add_argument("--shared-data", help="folder with captif_chipseal_station0.dat")
        d.add_argument("--cutoff", default="slope",
                       help="lowest scale: slope (default), resolution or a wavelength in mm")
        d.add_argument("--max-slope", type=float, default=1.3,
                       help="cumulative 2D rms slope of the slope cut-off (default 1.3)")
        d.add_argument("--plot", help="PNG: band PSDs and the cumulative slope")
        d.set_defaults(func=_options_in_errors(_cmd_road))

    g = sub.add_parser("generate", help="synthetic profiles to CSV")
    g.add_argument("kind", choices=("self-affine", "two-sine", "sawtooth"))
    g.add_argument("--out", required=True)
    g.add_argument("--length", type=float, default=20.0, help="mm")
    g.add_argument("--dx", type=float, default=0.005, help="mm")
    g.add_argument("--hurst", type=float, default=0.8)
    g.add_argument("--rms", type=float, default=0.1, help="rms height (mm)")
    g.add_argument("--rolloff", type=float, help="roll-off wavelength (mm)")
    g.add_argument("--cutoff", type=float, help="cut-off wavelength (mm)")
    g.add_argument("--seed", type=int, default=0)
    g.add_argument("--wavelength", type=float, default=5.0, help="sawtooth wavelength (mm)")
    g.add_argument("--height", type=float, default=1.0, help="sawtooth peak to valley (mm)")
    g.add_argument("--orientation", choices=("sharp", "smooth"), default="sharp")
    g.add_argument("--steep-fraction", type=float, default=0.1)
    g.set_defaults(func=_options_in_errors(_cmd_generate))

    c = sub.add_parser("compare", help="fig. 6.5: HDC sinusoids vs PSD reconstruction vs filtering")
    c.add_argument("file")
    _add_reader_args(c)
    c.add_argument("--edges", nargs="+", type=float, required=True)
    c.add_argument("--seed", type=int, default=0)
    c.add_argument("--plot", help="PNG")
    c.set_defaults(func=_options_in_errors(_cmd_compare))
