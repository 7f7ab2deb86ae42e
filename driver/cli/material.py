"""``rubberfriction material``: inspect material files and fit Prony series to DMA data.

    rubberfriction material show NAME|FILE [--T-C 0]
    rubberfriction material fit DMA.csv [--terms N] [--plot out.png] [--toml out.toml]
                                        [--base tread_default]

``show`` prints the summary of a compound (or road), E'(f), E''(f) and tan delta at a few
frequencies, and the WLF shift table.  ``fit`` fits a Prony series (eq. 3.34, non-negative least
squares on E' and E'') to a DMA master curve in the pyvisco CSV format and can write a ready-to-use
compound TOML whose Mooney-Rivlin, WLF and thermal data come from ``--base``.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

import numpy as np

from rubberfriction.forms import compound as M
from rubberfriction.forms import material_files

SHOW_FREQUENCIES_HZ = (1e-2, 1e-1, 1.0, 10.0, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8)
WLF_TABLE_C = (-40.0, -20.0, 0.0, 20.0, 40.0, 60.0, 80.0, 100.0)


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("material",
                                   help="show material files, fit Prony series to DMA data",
                                   description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])
    sub = parser.add_subparsers(dest="material_command", metavar="ACTION")

    show = sub.add_parser("show", help="summary, moduli and WLF table of a compound or road")
    show.add_argument("name", help="a shipped name (e.g. tread_default, m1, r1) or a TOML file")
    show.add_argument("--T-C", type=float, default=None,
                      help="temperature (degC) of the moduli table")
    show.set_defaults(func=run_show)

    fit = sub.add_parser("fit", help="fit a Prony series to a DMA master curve (pyvisco CSV)")
    fit.add_argument("dma", type=Path,
                     help="CSV: header row, optional units row, frequency, E', E''")
    fit.add_argument("--terms", type=int, default=None,
                     help="number of Prony terms (default: one per decade)")
    fit.add_argument("--freq-unit", choices=("Hz", "rad/s"), default="Hz")
    fit.add_argument("--columns", nargs=3, default=("f", "E_stor", "E_loss"),
                     metavar=("FREQ", "E1", "E2"))
    fit.add_argument("--T-C", type=float, default=None,
                     help="temperature (degC) of the master curve; default: the base "
                          "compound's WLF T_ref")
    fit.add_argument("--base", default=material_files.DEFAULT_COMPOUND,
                     help="compound providing Mooney-Rivlin, WLF and thermal data for --toml")
    fit.add_argument("--fix-E-inf", action="store_true",
                     help="fix E_inf to the base compound's Mooney-Rivlin long-term modulus")
    fit.add_argument("--bound", action="store_true",
                     help="also compute the best max error any Prony series could reach "
                          "(linear programme)")
    fit.add_argument("--plot", type=Path, default=None, help="write a PNG of data, fit and errors")
    fit.add_argument("--toml", type=Path, default=None,
                     help="write a compound TOML with the fitted series")
    fit.add_argument("--name", default=None,
                     help="compound name for --toml (default: the CSV name)")
    fit.set_defaults(func=run_fit)


# --------------------------------------------------------------------------------------------
# show
# --------------------------------------------------------------------------------------------


def _error(command: str, err: Exception) -> int:
    """One line ``rubberfriction material COMMAND: error: ...`` on stderr; exit status 2 (bad
    input, as every ``rubberfriction`` command)."""
    if isinstance(err, OSError) and err.filename is not None:
        msg = f"{err.filename}: {err.strerror or err}"  # e.g. "dma.csv: No such file or directory"
    else:
        msg = " ".join(str(err).split())
    print(f"rubberfriction material {command}: error: {msg}", file=sys.stderr)
    return 2


def _kind(name: str) -> str:
    with material_files.resolve_data_path(name).open("rb") as fh:
        return str(tomllib.load(fh).get("kind"))


def run_show(args: argparse.Namespace) -> int:
    try:
        kind = _kind(args.name)
        if kind == "road":
            print(material_files.load_road(args.name).summary())
            return 0
        compound = material_files.load_compound(args.name)
    except (ValueError, OSError) as err:
        return _error("show", err)
    print(compound.summary())
    print()
    T = None if args.T_C is None else args.T_C + M.ZERO_CELSIUS
    try:
        print("\n".join(moduli_table(compound, T)))
    except ValueError as err:
        return _error("show", err)
    if compound.wlf is not None:
        print()
        print("\n".join(wlf_table(compound.wlf)))
    return 0


def moduli_table(compound: M.Compound, T: float | None = None) -> list[str]:
    """E', E'', tan delta at :data:`SHOW_FREQUENCIES_HZ` (at T in K, default the reference)."""
    where = "the reference temperature" if T is None else f"{T - M.ZERO_CELSIUS:g} degC"
    if T is None and compound.wlf is not None:
        where += f" ({compound.wlf.T_ref - M.ZERO_CELSIUS:g} degC)"
    f = np.array(SHOW_FREQUENCIES_HZ)
    E = compound.complex_modulus(2 * np.pi * f, T)
    lines = [f"moduli at {where}:",
             f"  {'f (Hz)':>10} {'E_stor (MPa)':>13} {'E_loss (MPa)':>13} {'tan delta':>10}"]
    lines += [f"  {fi:>10.0e} {e.real:>13.5g} {e.imag:>13.5g} {e.imag / e.real:>10.4f}"
              for fi, e in zip(f, E)]
    return lines


def wlf_table(wlf: M.WLF) -> list[str]:
    """log10 a(T) (eq. 3.33) and the reference-temperature frequency equivalent to 10 Hz at T."""
    lines = ["WLF shift (eq. 3.33): 10 Hz at T acts like 10 Hz * a(T) at T_ref",
             f"  {'T (degC)':>9} {'log10 aT':>10} {'10 Hz at T_ref':>15}"]
    for T_C in WLF_TABLE_C:
        T = T_C + M.ZERO_CELSIUS
        if T <= wlf.T_singular:
            lines.append(f"  {T_C:>9g} {'(below WLF singularity)':>26}")
            continue
        lines.append(f"  {T_C:>9g} {wlf.log10_aT(T):>10.4f} {10.0 * wlf.aT(T):>15.4g}")
    return lines


# --------------------------------------------------------------------------------------------
# fit
# --------------------------------------------------------------------------------------------


def run_fit(args: argparse.Namespace) -> int:
    from rubberfriction.forms import prony as P

    try:
        base = material_files.load_compound(args.base)
        omega, E1, E2 = P.read_dma_csv(args.dma, freq_unit=args.freq_unit,
                                       columns=tuple(args.columns))
        fixed = base.E_inf if args.fix_E_inf else None
        fit = P.fit_prony(omega, E1, E2, n_terms=args.terms, E_inf=fixed)
    except (ValueError, OSError) as err:
        return _error("fit", err)
    f = omega / (2 * np.pi)
    print(f"{args.dma}: {omega.size} points, {f.min():.3g} .. {f.max():.3g} Hz")
    print(fit.report())
    if args.bound:
        lo, hi = np.log10(fit.series.tau.min()) - 2, np.log10(fit.series.tau.max()) + 2
        dense = np.logspace(lo, hi, int(4 * (hi - lo)) + 1)
        bound = P.minimax_rel_error_bound(omega, E1, E2, dense)
        print("  best possible max relative error of any Prony series "
              f"(4/decade, 2 decades beyond): {bound:.3%}")
    if args.plot is not None:
        print(f"plot: {P.plot_fit(fit, omega, E1, E2, args.plot)}")
    if args.toml is not None:
        write_compound_toml(args, fit, base)
    return 0


def _shifted_series(fit, base: M.Compound, T_C: float | None) -> tuple[M.PronySeries, str]:
    """The series at base's T_ref (``prony.series_at_reference``) and its note as a comment."""
    from rubberfriction.forms.prony import series_at_reference

    T = None if T_C is None else T_C + M.ZERO_CELSIUS
    series, note = series_at_reference(fit, base, T)
    return series, f"# {note}\n" if note else ""


def write_compound_toml(args: argparse.Namespace, fit, base: M.Compound) -> Path:
    """A compound TOML: the fitted series inline, Mooney-Rivlin/WLF/thermal data of ``base``."""
    from rubberfriction.forms.prony import prony_toml

    name = args.name or args.dma.stem
    series, shift_note = _shifted_series(fit, base, args.T_C)
    mr = base.hyperelastic
    ratio = base.E_inf / fit.E_inf
    report = "".join(f"# {line}\n" for line in fit.report().splitlines())
    text = (f"# Written by `rubberfriction material fit {args.dma}`; "
            f"format: forms/data/README.md\n{report}"
            f"# E_inf of the fit = {fit.E_inf:.6g} MPa; the compound uses the Mooney-Rivlin "
            f"E_inf = {base.E_inf:.6g} MPa, so its moduli are the fitted ones scaled by "
            f"{ratio:.4g}.\n{shift_note}"
            f'kind = "compound"\nname = "{name}"\n'
            f'description = "Prony series fitted to {args.dma.name}; equilibrium, WLF and '
            f'thermal data of {base.name}"\n'
            f'source = "Prony: rubberfriction material fit {args.dma.name}; '
            f'Mooney-Rivlin/WLF/thermal: {base.name}"\n\n'
            + _units_block(base.thermal is not None)
            + f'\n[hyperelastic]\nmodel = "mooney_rivlin"\nform = "{mr.form}"\n'
              f'volumetric = "{mr.volumetric}"\n'
              f"C10 = {mr.C10!r}  # MPa\nC01 = {mr.C01!r}  # MPa\nD1 = {mr.D1!r}  # 1/MPa\n"
            + "\n[prony]  # gamma_k = E_k/E0, tau_k in s at T_ref\n" + prony_toml(series)
            + _wlf_block(base.wlf) + _thermal_block(base.thermal))
    args.toml.write_text(text)
    material_files.load_compound(args.toml)  # the file must load
    print(f"compound file: {args.toml} ({len(series)} non-zero terms)")
    if abs(ratio - 1) > 0.05:
        print(f"note: fitted E_inf = {fit.E_inf:.4g} MPa differs from {base.name}'s "
              f"Mooney-Rivlin E_inf = {base.E_inf:.4g} MPa (x{ratio:.3g}); --fix-E-inf fits "
              "with the latter")
    return args.toml


def _units_block(thermal: bool) -> str:
    text = ('[units]\nlength = "mm"\ntime = "s"\nmass = "t"\nforce = "N"\nstress = "MPa"\n'
            'energy = "mJ"\ntemperature = "K"\n')
    if thermal:
        text += 'density = "t/mm^3"\nspecific_heat = "mJ/(t K)"\nconductivity = "mW/(mm K)"\n'
    return text


def _wlf_block(wlf: M.WLF | None) -> str:
    if wlf is None:
        return ""
    return f"\n[wlf]\nc1 = {wlf.c1!r}\nc2 = {wlf.c2!r}  # K\nT_ref = {wlf.T_ref!r}  # K\n"


def _thermal_block(thermal: M.Thermal | None) -> str:
    if thermal is None:
        return ""
    return (f"\n[thermal]\nrho = {thermal.rho!r}  # t/mm^3\nc = {thermal.c!r}  # mJ/(t K)\n"
            f"k = {thermal.k!r}  # mW/(mm K)\n")
