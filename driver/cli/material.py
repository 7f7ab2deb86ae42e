"""``rubberfriction material``: inspect material files and fit Prony series to DMA data.

    rubberfriction material show NAME|FILE [--T-C 0]
    rubberfriction material fit DATA.csv (--T-ref-C DEGC | --shift-factors SHIFT.csv)
                                [--kind frequency|time|prony] [--terms N] [--plot out.png]
                                [--toml out.toml] [--base tread_default]

``show`` prints the summary of a compound (or road), E'(f), E''(f) and tan delta at a few
frequencies, and the WLF shift table.  ``fit`` fits a Prony series to a master curve in the
pyvisco CSV format -- a DMA curve E'(f), E''(f) (eq. 3.34, non-negative least squares on both),
a relaxation curve E(t) (``--kind time``, E_inf + sum E_k exp(-t/tau_k), NNLS on a log-spaced
tau grid), or published Prony terms read as given (``--kind prony``) -- and can write a
ready-to-use compound TOML whose Mooney-Rivlin and thermal data come from ``--base``.

The master curve's reference temperature is an input, never assumed: ``--T-ref-C``, or
``--shift-factors`` (the table log10 aT vs T that built the curve; its zero is the reference,
and WLF c1, c2 are fitted to it by least squares and become the compound's WLF data).  Without
a shift-factor table the compound takes ``--base``'s WLF, the relaxation times shifted from
``--T-ref-C`` to its T_ref (eq. 3.37).  Every fit states its reference temperature and warns,
one line each, about a Poisson ratio outside 0 .. 0.5, a loss-tangent peak outside the data and
relaxation times more than a decade outside the data's time range.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

import numpy as np

from rubberfriction import validation as V
from rubberfriction.forms import compound as M
from rubberfriction.forms import material_files

KINDS = ("frequency", "time", "prony")
DEFAULT_COLUMNS = {"frequency": ("f", "E_stor", "E_loss"), "time": ("t", "E_relax")}
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

    fit = sub.add_parser("fit", help="fit a Prony series to a master curve (pyvisco CSV)")
    fit.add_argument("dma", type=Path,
                     help="CSV: header row, optional units row, then frequency, E', E'' "
                          "(--kind frequency), time, E(t) (--kind time) or the Prony terms "
                          "rel_mod, rel_time after a '# E0 = ... MPa' line (--kind prony)")
    fit.add_argument("--kind", choices=KINDS, default="frequency",
                     help="what the CSV holds (default: frequency)")
    fit.add_argument("--terms", type=int, default=None,
                     help="number of Prony terms (--kind frequency; default: one per decade)")
    fit.add_argument("--freq-unit", choices=("Hz", "rad/s"), default="Hz")
    fit.add_argument("--columns", nargs="+", default=None, metavar="COL",
                     help="column names: f E_stor E_loss (frequency) or t E_relax (time)")
    fit.add_argument("--T-ref-C", "--T-C", dest="T_ref_C", type=float, default=None,
                     help="reference temperature (degC) of the master curve")
    fit.add_argument("--shift-factors", type=Path, default=None, metavar="FILE",
                     help="CSV of log10 aT vs T (header T, log_aT; units row C or K): gives "
                          "the reference temperature (log10 aT = 0) and the WLF c1, c2 fitted "
                          "to it")
    fit.add_argument("--base", default=material_files.DEFAULT_COMPOUND,
                     help="compound providing Mooney-Rivlin and thermal data (and WLF without "
                          "--shift-factors) for --toml")
    fit.add_argument("--fix-E-inf", action="store_true",
                     help="fix E_inf to the base compound's Mooney-Rivlin long-term modulus")
    fit.add_argument("--bound", action="store_true",
                     help="also compute the best max error any Prony series could reach "
                          "(linear programme; --kind frequency)")
    fit.add_argument("--plot", type=Path, default=None,
                     help="write a PNG of data, fit and errors (--kind frequency)")
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
        _check_fit_options(args)
        base = material_files.load_compound(args.base)
        T_ref, wlf_fit = reference_of(args)
        fit, omega, E1, E2, w_range = _fit_data(args, base)
        series, shift_note = P.series_at_reference(fit, base, T_ref,
                                                   wlf_fit.wlf if wlf_fit else None)
        # the data-range checks on the series as fitted (at the data's reference temperature)
        warnings = P.plausibility_warnings(fit.series, base.E_inf, w_range,
                                           K=base.hyperelastic.K)
    except (ValueError, OSError) as err:
        return _error("fit", err)
    source = ("--shift-factors " + str(args.shift_factors) if wlf_fit else "--T-ref-C")
    if args.kind != "prony":
        lo, hi = (w_range[0] / (2 * np.pi), w_range[1] / (2 * np.pi))
        what = (f"{lo:.3g} .. {hi:.3g} Hz" if args.kind == "frequency"
                else f"t = {1 / w_range[1]:.3g} .. {1 / w_range[0]:.3g} s")
        print(f"{args.dma}: {fit.n_data} points, {what}")
    print(f"reference temperature of the master curve: {T_ref - M.ZERO_CELSIUS:g} degC "
          f"({source})")
    if wlf_fit is not None:
        print(wlf_fit.report())
    print(fit.report())
    for line in warnings:
        print(f"warning: {line}")
    if args.bound:
        lo, hi = np.log10(fit.series.tau.min()) - 2, np.log10(fit.series.tau.max()) + 2
        dense = np.logspace(lo, hi, int(4 * (hi - lo)) + 1)
        bound = P.minimax_rel_error_bound(omega, E1, E2, dense)
        print("  best possible max relative error of any Prony series "
              f"(4/decade, 2 decades beyond): {bound:.3%}")
    if args.plot is not None:
        print(f"plot: {P.plot_fit(fit, omega, E1, E2, args.plot)}")
    if args.toml is not None:
        wlf = wlf_fit.wlf if wlf_fit is not None else base.wlf
        notes = [f"master curve reference temperature {T_ref - M.ZERO_CELSIUS:g} degC "
                 f"({source})"]
        notes += [wlf_fit.report()] if wlf_fit is not None else []
        notes += ([shift_note] if shift_note else []) + [f"warning: {w}" for w in warnings]
        write_compound_toml(args, fit, base, series, wlf, notes)
    return 0


def _check_fit_options(args: argparse.Namespace) -> None:
    """Options that do not apply to ``--kind``: one line naming the option."""
    if args.kind != "frequency":
        for opt, given in (("--terms", args.terms is not None), ("--plot", args.plot is not None),
                           ("--bound", args.bound)):
            if given:
                raise V.InputError(f"{opt}: applies to --kind frequency, not --kind {args.kind}")
    if args.kind == "prony" and args.columns is not None:
        raise V.InputError("--columns: --kind prony reads the pyvisco terms file (rel_mod, "
                           "rel_time)")
    if args.kind == "prony" and args.fix_E_inf:
        raise V.InputError("--fix-E-inf: --kind prony takes the terms as given")
    want = len(DEFAULT_COLUMNS.get(args.kind, ()))
    if args.columns is not None and len(args.columns) != want:
        raise V.InputError(f"--columns {' '.join(args.columns)}: expected {want} column names "
                           f"for --kind {args.kind}")


def reference_of(args: argparse.Namespace):
    """The master curve's reference temperature (K) and, from ``--shift-factors``, the WLF fitted
    to the table (else None).  Neither option given: refused, nothing is assumed."""
    from rubberfriction.forms import prony as P

    T_opt = None
    if args.T_ref_C is not None:
        T_opt = V.option("--T-ref-C", args.T_ref_C, what="a temperature", above=-M.ZERO_CELSIUS,
                         unit="degC") + M.ZERO_CELSIUS
    if args.shift_factors is None:
        if T_opt is None:
            raise V.InputError("the master curve's reference temperature is not given: pass "
                               "--T-ref-C DEGC or --shift-factors FILE (nothing is assumed)")
        return T_opt, None
    try:
        T, log_aT = P.read_shift_factors(args.shift_factors)
        fit = P.fit_wlf(T, log_aT)
    except OSError as err:
        raise V.InputError(f"--shift-factors {args.shift_factors}: "
                           f"{err.strerror or err}") from None
    except ValueError as err:
        raise V.InputError(f"--shift-factors {args.shift_factors}: {err}") from None
    if T_opt is not None and abs(T_opt - fit.wlf.T_ref) > 0.005:
        raise V.InputError(f"--T-ref-C {args.T_ref_C:g}: --shift-factors {args.shift_factors} "
                           f"puts the reference (log10 aT = 0) at "
                           f"{fit.wlf.T_ref - M.ZERO_CELSIUS:g} degC; give one of the two")
    return fit.wlf.T_ref, fit


def _fit_data(args: argparse.Namespace, base: M.Compound):
    """(fit, omega, E', E'', data frequency range in rad/s or None) for ``--kind``."""
    from rubberfriction.forms import prony as P

    fixed = base.E_inf if args.fix_E_inf else None
    if args.kind == "prony":
        fit = P.read_prony_csv(args.dma)
        return fit, None, None, None, None
    columns = tuple(args.columns or DEFAULT_COLUMNS[args.kind])
    if args.kind == "time":
        t, E = P.read_relaxation_csv(args.dma, columns=columns)
        fit = P.fit_prony_time(t, E, E_inf=fixed)
        return fit, None, None, None, (1.0 / t.max(), 1.0 / t.min())
    omega, E1, E2 = P.read_dma_csv(args.dma, freq_unit=args.freq_unit, columns=columns)
    fit = P.fit_prony(omega, E1, E2, n_terms=args.terms, E_inf=fixed)
    return fit, omega, E1, E2, (float(omega.min()), float(omega.max()))


def write_compound_toml(args: argparse.Namespace, fit, base: M.Compound, series: M.PronySeries,
                        wlf: M.WLF | None, notes: list[str]) -> Path:
    """A compound TOML: the fitted series inline (at ``wlf``'s T_ref), Mooney-Rivlin and thermal
    data of ``base``; ``notes`` (reference temperature, WLF fit, shift, warnings) as comments."""
    from rubberfriction.forms.prony import prony_toml

    name = args.name or args.dma.stem
    mr = base.hyperelastic
    ratio = base.E_inf / fit.E_inf
    report = "".join(f"# {line}\n" for line in fit.report().splitlines())
    note_lines = "".join(f"# {line}\n" for line in notes)
    wlf_of = "the shift factors' WLF fit" if wlf is not base.wlf else f"WLF of {base.name}"
    text = (f"# Written by `rubberfriction material fit {args.dma}`; "
            f"format: forms/data/README.md\n{report}"
            f"# E_inf of the fit = {fit.E_inf:.6g} MPa; the compound uses the Mooney-Rivlin "
            f"E_inf = {base.E_inf:.6g} MPa, so its moduli are the fitted ones scaled by "
            f"{ratio:.4g}.\n{note_lines}"
            f'kind = "compound"\nname = "{name}"\n'
            f'description = "Prony series from {args.dma.name}; equilibrium and thermal data '
            f'of {base.name}, {wlf_of}"\n'
            f'source = "Prony: rubberfriction material fit {args.dma.name} --kind {args.kind}; '
            f'Mooney-Rivlin/thermal: {base.name}; {wlf_of}"\n\n'
            + _units_block(base.thermal is not None)
            + f'\n[hyperelastic]\nmodel = "mooney_rivlin"\nform = "{mr.form}"\n'
              f'volumetric = "{mr.volumetric}"\n'
              f"C10 = {mr.C10!r}  # MPa\nC01 = {mr.C01!r}  # MPa\nD1 = {mr.D1!r}  # 1/MPa\n"
            + "\n[prony]  # gamma_k = E_k/E0, tau_k in s at T_ref\n" + prony_toml(series)
            + _wlf_block(wlf) + _thermal_block(base.thermal))
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
