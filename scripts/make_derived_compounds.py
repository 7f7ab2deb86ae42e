"""Write forms/data/c1.toml .. c6.toml: thesis table 6.1's compounds derived from one DMA curve.

Usage (from the repository root; re-runnable, the output is committed):

    PYTHONPATH=... /usr/bin/python3 scripts/make_derived_compounds.py [--out DIR] [--no-plot]

Chain (rubberfriction.forms.derive; docs/compounds.md explains each step):

1. DMA fit: the pyvisco master curve (tests/data/pyvisco_freq_master.csv, referenced to -5 degC
   by its shift-factor table) -> fit_prony (one tau per decade, E_inf fitted) and fit_wlf on the
   table; series and WLF re-referenced to 20 degC, the thesis' master temperature.
2. Level anchor: all moduli scaled so that E_inf equals the long-term modulus of the base
   compound c6 (f0, h0, Tg0) from its Mooney-Rivlin constants (table 6.1).
3. Per compound, the offsets of its table row: filler (+35 phr: stretch and Guth-Gold factor),
   hardness (+10 ShA: Gent's ratio from h0 = Gent's Shore A of c6's E_inf), glass transition
   (-20 K: WLF shift).
4. Long-term modulus: the table's own Mooney-Rivlin E_inf replaces the derived one (the FE
   model's equilibrium part is the Mooney-Rivlin law); the derived Maxwell moduli E_k are kept
   absolute, so gamma_k = E_k / (E_inf(MR) + sum E_k).  Both E_inf values are in the file.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rubberfriction.forms import derive as D
from rubberfriction.forms.compound import ZERO_CELSIUS, MooneyRivlin
from rubberfriction.forms.material_files import load_compound
from rubberfriction.forms.prony import (fit_prony, fit_wlf, prony_toml, read_dma_csv,
                                        read_shift_factors)

ROOT = Path(__file__).resolve().parents[1]
DMA = ROOT / "tests" / "data" / "pyvisco_freq_master.csv"
SHIFT = ROOT / "tests" / "data" / "pyvisco_freq_master_shift_factors.csv"
T_MASTER_C = 20.0      # thesis 6.5.1: master temperature of its DMA curves
BASE = "c6"            # f0, h0, Tg0: no offset in table 6.1
FILLER_PHR = 35.0      # table 6.1: f0 + 35
FILLER_STRETCH = 1.25  # log-tau spread factor of the filled compounds (illustrative, see docs)
HARDNESS_DH = 10.0     # table 6.1: h0 + 10 ShA
TG_DT = -20.0          # table 6.1: Tg0 - 20 (K)


@dataclass(frozen=True)
class Row:
    """One row of thesis table 6.1: offsets (filler?, hardness?, Tg offset) and C10, C01, D1."""

    name: str
    filler: bool
    hard: bool
    dTg: float
    C10: float
    C01: float
    D1: float

    def label(self) -> str:
        f = "f0 + 35" if self.filler else "f0"
        h = "h0 + 10" if self.hard else "h0"
        t = f"Tg0 - {-self.dTg:g}" if self.dTg else "Tg0"
        return f"{f} phr, {h} ShA, Tg = {t} degC"


TABLE_6_1 = (Row("c1", True, True, 0.0, 0.136, 0.518, 0.031),
             Row("c2", False, True, 0.0, 0.246, 0.489, 0.027),
             Row("c3", True, False, 0.0, 0.174, 0.309, 0.042),
             Row("c4", True, True, TG_DT, 0.150, 0.623, 0.026),
             Row("c5", False, True, TG_DT, 0.327, 0.613, 0.021),
             Row("c6", False, False, 0.0, 0.219, 0.318, 0.038))


@dataclass(frozen=True)
class Derived:
    """A compound of the table: its row, the derived spectrum (before the long-term modulus is
    replaced), the spectrum as shipped and the step descriptions."""

    row: Row
    derived: D.Spectrum
    shipped: D.Spectrum
    steps: tuple[str, ...]


@dataclass(frozen=True)
class Build:
    base: D.Spectrum          # the DMA fit at 20 degC, level-anchored (= compound c6)
    fit_note: str
    anchor: float
    h0: float
    hardness_factor: float
    phi: float
    filler_factor: float
    compounds: tuple[Derived, ...]


def mr_E(row: Row) -> float:
    """Long-term Young's modulus of the row's Mooney-Rivlin constants, MPa."""
    return MooneyRivlin(row.C10, row.C01, row.D1).E


def build() -> Build:
    """The whole derivation (pure; no files written)."""
    omega, E1, E2 = read_dma_csv(DMA, freq_unit="Hz")
    wfit = fit_wlf(*read_shift_factors(SHIFT))
    fit = fit_prony(omega, E1, E2)
    series = fit.series.pruned()
    at_data = D.Spectrum(fit.E_inf, series.moduli(fit.E_inf), series.tau, wfit.wlf)
    at20 = D.to_reference(at_data, T_MASTER_C + ZERO_CELSIUS)
    rows = {r.name: r for r in TABLE_6_1}
    anchor = mr_E(rows[BASE]) / at20.E_inf
    base = D.scale_moduli(at20, anchor)
    h0 = D.gent_shore(base.E_inf)
    s_h = D.hardness_factor(h0, HARDNESS_DH)
    phi = D.filler_volume_fraction(FILLER_PHR)
    m_f = D.guth_gold(phi)
    fit_note = (f"fit_prony ({len(fit.series)} tau, one per decade, E_inf fitted = "
                f"{fit.E_inf:.6g} MPa; max rel. error E' {fit.rel_error_storage.max:.1%}, E'' "
                f"{fit.rel_error_loss.max:.1%}) on {DMA.name} at -5 degC; fit_wlf on {SHIFT.name}: "
                f"c1 = {wfit.wlf.c1:.6g}, c2 = {wfit.wlf.c2:.6g} K at -5 degC (rms residual "
                f"{wfit.rms_residual:.3g}); re-referenced to {T_MASTER_C:g} degC")
    out = []
    for row in TABLE_6_1:
        sp, steps = base, [f"level anchor: moduli x {anchor:.6g} (E_inf = {BASE}'s Mooney-Rivlin "
                           f"E_inf = {base.E_inf:.6g} MPa)"]
        if row.filler:
            sp = D.apply_filler(sp, FILLER_STRETCH, m_f)
            steps.append(f"filler +{FILLER_PHR:g} phr: log-tau stretch {FILLER_STRETCH:g} about "
                         f"the loss peak, E_k x {m_f:.6g} (Guth-Gold, phi = {phi:.4f})")
        if row.hard:
            sp = D.scale_moduli(sp, s_h)
            steps.append(f"hardness +{HARDNESS_DH:g} ShA: moduli x {s_h:.6g} (Gent, h0 = "
                         f"{h0:.4g} ShA)")
        if row.dTg:
            F = D.tg_shift_factor(sp.wlf, row.dTg)
            sp = D.shift_glass_transition(sp, row.dTg)
            steps.append(f"glass transition {row.dTg:+g} K: tau x {F:.6g} (WLF)")
        shipped = D.with_long_term(sp, mr_E(row))
        steps.append(f"long-term modulus: E_inf = {shipped.E_inf:.6g} MPa from table 6.1's "
                     f"Mooney-Rivlin constants (derived {sp.E_inf:.6g} MPa, ratio "
                     f"{shipped.E_inf / sp.E_inf:.4f}); E_k kept")
        out.append(Derived(row, sp, shipped, tuple(steps)))
    return Build(base, fit_note, anchor, h0, s_h, phi, m_f, tuple(out))


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def compound_toml(b: Build, c: Derived) -> str:
    """The text of one compound file."""
    r, sp = c.row, c.shipped
    series = sp.series()
    w = sp.wlf
    steps = "".join(f"#   {i + 1}. {s}\n" for i, s in enumerate(c.steps))
    return (
        f"# Rubber compound {r.name}: GENERATED by scripts/make_derived_compounds.py (do not edit;"
        " re-run it).\n"
        "# See README.md for the format and docs/compounds.md for the derivation.\n"
        f"# Thesis table 6.1 row: {r.label()}; C10 = {r.C10}, C01 = {r.C01} MPa, "
        f"D1 = {r.D1} 1/MPa.\n"
        f"# Prony series and WLF: {b.fit_note}; then\n{steps}"
        'kind = "compound"\n'
        f'name = "{r.name}"\n'
        f"description = {_q('Table 6.1 compound (wet friction validation, ch. 6.5.1): ' + r.label() + '; spectrum derived from a DMA master curve (docs/compounds.md).')}\n"  # noqa: E501
        f"source = {_q('thesis (shared/reference/thesis.md) table 6.1 (Mooney-Rivlin, property offsets); Prony/WLF: pyvisco DMA master curve (NREL/pyvisco, BSD-3) transformed by rubberfriction.forms.derive, see the comments')}\n"  # noqa: E501
        "\n[units]  # project units (CONTRIBUTING.md); temperatures in this file are degC\n"
        'length = "mm"\ntime = "s"\nmass = "t"\nforce = "N"\nstress = "MPa"\nenergy = "mJ"\n'
        'temperature = "degC"\n'
        "\n[hyperelastic]  # table 6.1, long-term (equilibrium) response (thesis ch. 3.3.3)\n"
        'model = "mooney_rivlin"\n'
        'form = "split"  # eq. (3.58) with + C01 (see rubberfriction.forms.compound.MooneyRivlin)\n'
        f"C10 = {r.C10}  # MPa\nC01 = {r.C01}  # MPa\n"
        f"D1 = {r.D1}  # 1/MPa (the thesis tables print the header \"(MPa)\"; D1 = 2/K)\n"
        f"\n[prony]  # at T_ref = {T_MASTER_C:g} degC; gamma_k = E_k/E0 with E_inf from [hyperelastic]\n"  # noqa: E501
        f"note = {_q('; '.join(c.steps))}\n"
        + prony_toml(series)
        + f"\n[wlf]  # the DMA table's WLF re-referenced to {T_MASTER_C:g} degC"
        + (f", glass transition {r.dTg:+g} K" if r.dTg else "") + "\n"
        f"c1 = {w.c1!r}  # -\nc2 = {w.c2!r}  # K\nT_ref = {w.T_ref - ZERO_CELSIUS:.10g}  # degC\n"
        f"note = {_q('fit_wlf on ' + SHIFT.name + (f', moved by dT = {r.dTg:g} K (forms.derive.shift_glass_transition)' if r.dTg else ''))}\n"  # noqa: E501
    )


def plot(out_dir: Path, path: Path) -> None:
    """E'(f) and tan delta(f) at 20 degC of the written compounds."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f = np.logspace(-2, 10, 400)
    T = T_MASTER_C + ZERO_CELSIUS
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for row in TABLE_6_1:
        c = load_compound(out_dir / f"{row.name}.toml")
        E = c.complex_modulus(2 * math.pi * f, T)
        style = "-" if not row.dTg else "--"
        a1.loglog(f, E.real, style, label=f"{row.name}: {row.label()}")
        a2.semilogx(f, E.imag / E.real, style)
    a1.set_ylabel("E' (MPa)")
    a2.set_ylabel("tan delta")
    a2.set_xlabel("frequency (Hz) at 20 degC")
    a1.legend(fontsize=7)
    a1.set_title("compounds c1..c6 derived from the pyvisco DMA curve (cf. thesis fig. 6.18)")
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "forms" / "data")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img" / "compounds.png")
    ap.add_argument("--no-plot", action="store_true")
    args = ap.parse_args(argv)
    b = build()
    args.out.mkdir(parents=True, exist_ok=True)
    for c in b.compounds:
        (args.out / f"{c.row.name}.toml").write_text(compound_toml(b, c))
        print(f"{c.row.name}: " + "; ".join(c.steps))
    if not args.no_plot:
        plot(args.out, args.img)
        print(f"plot: {args.img}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
