"""Material data files: the TOML schema of compounds and roads and their loaders.

Every file states its units in a ``[units]`` table (the project's mm, s, t, N, MPa, mJ, K;
temperatures K or degC, converted to kelvin here and nowhere else) and its ``kind`` (compound or
road).  A bare name resolves to a shipped file ``forms/data/<name>.toml``; the format is in
``forms/data/README.md``.  Errors name the file, the table and key, the value and what is
expected.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from rubberfriction import validation as V
from rubberfriction.forms.compound import (
    WLF,
    ZERO_CELSIUS,
    Compound,
    MooneyRivlin,
    PronySeries,
    Road,
    Thermal,
)
from rubberfriction.forms.prony import fit_prony, read_dma_csv

DATA_DIR = Path(__file__).resolve().parent / "data"
DEFAULT_COMPOUND = "tread_default"


# Every file states these units in a [units] table; only the project units are accepted (a
# file in other units must be converted), except temperature: "K" or "degC".
BASE_UNITS = {"length": ("mm",), "time": ("s",), "mass": ("t",), "force": ("N",),
              "stress": ("MPa",), "energy": ("mJ",), "temperature": ("K", "degC")}
THERMAL_UNITS = {"density": ("t/mm^3",), "specific_heat": ("mJ/(tK)",),
                 "conductivity": ("mW/(mmK)",)}


def resolve_data_path(name_or_path: str | Path) -> Path:
    """A bare name resolves to ``forms/data/<name>.toml``; anything else is a file path."""
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or text.endswith(".toml") or "/" in text or "\\" in text:
        path = Path(name_or_path).expanduser()
    else:
        path = DATA_DIR / f"{text}.toml"
    if not path.is_file():
        known = ", ".join(available()) or "none"
        raise ValueError(f"material file {text!r} not found (looked at {path}); shipped names: "
                         f"{known}")
    return path


def available(kind: str | None = None) -> list[str]:
    """Names of the shipped data files (optionally only ``kind`` = "compound" or "road")."""
    names = []
    for path in sorted(DATA_DIR.glob("*.toml")):
        with path.open("rb") as fh:
            if kind is None or tomllib.load(fh).get("kind") == kind:
                names.append(path.stem)
    return names


def read_toml(path: Path) -> dict[str, Any]:
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"{path}: not valid TOML: {err}") from None


def check_units(path: Path, doc: dict, thermal: bool) -> str:
    """Validate the [units] table; return the temperature unit ("K" or "degC")."""
    if "units" not in doc:
        raise ValueError(f"{path}: missing [units] table; every material file must state its units "
                         f"({', '.join(f'{k} = {v[0]!r}' for k, v in BASE_UNITS.items())})")
    expected = dict(BASE_UNITS, **(THERMAL_UNITS if thermal else {}))
    units = V.table(f"{path} [units]", doc["units"], set(BASE_UNITS) | set(THERMAL_UNITS),
                    set(expected))
    for key, accepted in expected.items():
        value = str(units[key]).replace(" ", "")
        if value not in accepted:
            expect = " or ".join(map(repr, accepted))
            raise ValueError(f"{path} [units].{key} = {units[key]!r}: expected {expect} "
                             "(convert the data to the project units)")
    return str(units["temperature"])


def to_kelvin(value: Any, unit: str, where: str) -> float:
    value = V.real(f"{where}.temperature", value, unit)
    return value + ZERO_CELSIUS if unit == "degC" else value


def _kind(path: Path, doc: dict, expected: str) -> None:
    if doc.get("kind") != expected:
        raise ValueError(f"{path}: kind = {doc.get('kind')!r}; expected kind = {expected!r}")


COMPOUND_KEYS = {"kind", "name", "description", "source", "units", "hyperelastic", "prony", "wlf",
                 "thermal"}


def load_compound(name_or_path: str | Path, _seen: tuple[Path, ...] = ()) -> Compound:
    """Load a compound from a TOML file (``forms/data/<name>.toml`` for a bare name).

    Sections: ``[units]`` (required), ``[hyperelastic]`` (Mooney-Rivlin C10, C01, D1, form,
    volumetric),
    ``[prony]``, ``[wlf]``, ``[thermal]``.  The Prony series is given in one of three ways:

    * inline: ``gamma = [...]``, ``tau = [...]`` (tau in s at the WLF reference temperature);
    * by reference: ``same_as = "tread_default"`` uses that compound's gamma and tau (gamma is
      dimensionless, so E0 = E_inf / gamma_inf follows from this compound's own E_inf);
      ``tau_factor = f`` multiplies every tau_k by f (the spectrum moved along the frequency
      axis by -log10 f decades at the reference temperature);
    * from a DMA master curve: ``fit_from = "my_dma.csv"`` (relative to the TOML file) with fit
      options ``n_terms``, ``columns`` (three column names or indices: frequency, E', E''),
      ``freq_unit`` ("Hz" or "rad/s"), ``T`` (temperature of the master curve, in the file's
      temperature unit) and ``E_inf`` ("fit": fitted as an unknown, only gamma is used;
      "hyperelastic": fixed to the Mooney-Rivlin E_inf).  The fitted relaxation times are
      shifted from T to the WLF reference temperature.  Replacing the default spectrum by a
      user's DMA data is thus the one-line change ``fit_from = "path.csv"``.

    ``[wlf]`` gives ``c1``, ``c2`` (K), ``T_ref`` or ``same_as = "<compound>"``.
    """
    path = resolve_data_path(name_or_path).resolve()
    if path in _seen:
        raise ValueError(f"{path}: circular same_as reference "
                         f"({' -> '.join(p.stem for p in _seen)})")
    doc = read_toml(path)
    _kind(path, doc, "compound")
    T_unit = check_units(path, doc, "thermal" in doc)
    V.table(str(path), doc, COMPOUND_KEYS, {"kind", "name", "units", "hyperelastic", "source"})
    hyper = _load_hyperelastic(path, doc["hyperelastic"])
    wlf, wlf_note = _load_wlf(path, doc.get("wlf"), T_unit, _seen + (path,))
    prony, note = _load_prony(path, doc.get("prony"), T_unit, hyper, wlf, _seen + (path,))
    thermal = _load_thermal(path, doc["thermal"]) if "thermal" in doc else None
    return Compound(name=V.text(f"{str(path)}.name", doc["name"], empty_ok=False),
                    hyperelastic=hyper, prony=prony, wlf=wlf, thermal=thermal,
                    description=V.text(f"{str(path)}.description", doc.get("description", "")),
                    source=V.text(f"{str(path)}.source", doc["source"]) + note + wlf_note)


def _load_hyperelastic(path: Path, table: Any) -> MooneyRivlin:
    t = V.table(f"{path} [hyperelastic]", table,
                {"model", "form", "C10", "C01", "D1", "volumetric", "note"},
                {"model", "C10", "C01", "D1"})
    if t["model"] != "mooney_rivlin":
        raise ValueError(f"{path} [hyperelastic].model = {t['model']!r}: expected 'mooney_rivlin'")
    try:
        return MooneyRivlin(t["C10"], t["C01"], t["D1"], t.get("form", "split"),
                            t.get("volumetric", "quadratic"))
    except ValueError as err:
        raise ValueError(f"{path} [hyperelastic]: {err}") from None


def _load_wlf(path: Path, table: Any, T_unit: str,
              seen: tuple[Path, ...]) -> tuple[WLF | None, str]:
    if table is None:
        return None, ""
    t = V.table(f"{path} [wlf]", table, {"c1", "c2", "T_ref", "same_as", "note"})
    if "same_as" in t:
        V.table(f"{path} [wlf]", t, {"same_as", "note"})
        ref = load_compound(_sibling(path, t["same_as"]), seen)
        if ref.wlf is None:
            raise ValueError(f"{path} [wlf].same_as = {t['same_as']!r}: that compound has "
                             "no WLF data")
        return ref.wlf, f" [WLF: same as {ref.name}]"
    V.table(f"{path} [wlf]", t, set(t), {"c1", "c2", "T_ref"})
    return WLF(t["c1"], t["c2"], to_kelvin(t["T_ref"], T_unit, f"{path} [wlf].T_ref")), ""


def _sibling(path: Path, ref: Any) -> str | Path:
    """A same_as reference: a bare name resolves next to the referring file."""
    ref = V.text(f"{str(path)}.same_as", ref, empty_ok=False)
    candidate = path.parent / f"{ref}.toml"
    return candidate if "/" not in ref and candidate.is_file() else ref


PRONY_KEYS = {"gamma", "tau", "same_as", "tau_factor", "fit_from", "n_terms", "columns",
              "freq_unit", "T", "E_inf", "note", "generator"}


def _load_prony(path: Path, table: Any, T_unit: str, hyper: MooneyRivlin, wlf: WLF | None,
                seen: tuple[Path, ...]) -> tuple[PronySeries | None, str]:
    if table is None:
        return None, ""
    t = V.table(f"{path} [prony]", table, PRONY_KEYS)
    ways = [k for k in ("gamma", "same_as", "fit_from") if k in t]
    if len(ways) != 1:
        raise ValueError(f"{path} [prony]: give exactly one of gamma/tau (inline), same_as, "
                         f"fit_from; got {ways}")
    if "gamma" in t:
        V.table(f"{path} [prony]", t, {"gamma", "tau", "note", "generator"}, {"gamma", "tau"})
        return PronySeries(t["gamma"], t["tau"]), ""
    if "same_as" in t:
        V.table(f"{path} [prony]", t, {"same_as", "tau_factor", "note"})
        ref = load_compound(_sibling(path, t["same_as"]), seen)
        if ref.prony is None:
            raise ValueError(f"{path} [prony].same_as = {t['same_as']!r}: that compound has no "
                             "Prony series")
        if "tau_factor" not in t:
            return ref.prony, f" [Prony series: same gamma_k, tau_k as {ref.name}]"
        factor = V.positive(f"{path} [prony].tau_factor", t["tau_factor"], "-")
        return (ref.prony.shifted(factor),
                f" [Prony series: gamma_k of {ref.name}, its tau_k x {factor:.6g}]")
    return _fit_prony_from_file(path, t, T_unit, hyper, wlf)


def _fit_prony_from_file(path: Path, t: dict, T_unit: str, hyper: MooneyRivlin,
                         wlf: WLF | None) -> tuple[PronySeries, str]:
    where = f"{path} [prony]"
    V.table(where, t, {"fit_from", "n_terms", "columns", "freq_unit", "T", "E_inf", "note"},
            {"fit_from", "freq_unit", "T"})
    csv = Path(V.text(f"{where}.fit_from", t["fit_from"], empty_ok=False)).expanduser()
    csv = csv if csv.is_absolute() else path.parent / csv
    columns = tuple(t.get("columns", ("f", "E_stor", "E_loss")))
    omega, E1, E2 = read_dma_csv(csv, freq_unit=t["freq_unit"], columns=columns)
    mode = t.get("E_inf", "fit")
    if mode not in ("fit", "hyperelastic"):
        raise ValueError(f"{where}.E_inf = {mode!r}: expected 'fit' or 'hyperelastic'")
    fixed = hyper.E if mode == "hyperelastic" else None
    fit = fit_prony(omega, E1, E2, n_terms=t.get("n_terms"), E_inf=fixed)
    T_data = to_kelvin(t["T"], T_unit, f"{where}.T")
    series = fit.series
    if wlf is not None and T_data != wlf.T_ref:
        series = series.shifted(1.0 / float(wlf.aT(T_data)))  # tau_ref = tau(T) / a(T), eq. 3.37
    note = (f" [Prony series fitted from {csv.name} at {T_data:g} K: "
            f"E_inf(fit) = {fit.E_inf:.4g} MPa vs E_inf(MR) = {hyper.E:.4g} MPa; "
            f"max rel. error E' {fit.rel_error_storage.max:.2%}, "
            f"E'' {fit.rel_error_loss.max:.2%}]")
    return series, note


def _load_thermal(path: Path, table: Any) -> Thermal:
    t = V.table(f"{path} [thermal]", table, {"rho", "c", "k", "note"}, {"rho", "c", "k"})
    return Thermal(t["rho"], t["c"], t["k"])


ROAD_KEYS = {"kind", "name", "description", "source", "units", "elastic", "thermal"}


def load_road(name_or_path: str | Path) -> Road:
    """Load a road material (``kind = "road"``): ``[elastic]`` E (MPa), nu; ``[thermal]``."""
    path = resolve_data_path(name_or_path).resolve()
    doc = read_toml(path)
    _kind(path, doc, "road")
    check_units(path, doc, "thermal" in doc)
    V.table(str(path), doc, ROAD_KEYS, {"kind", "name", "units", "elastic", "source"})
    el = V.table(f"{path} [elastic]", doc["elastic"], {"E", "nu", "note"}, {"E", "nu"})
    thermal = _load_thermal(path, doc["thermal"]) if "thermal" in doc else None
    return Road(name=doc["name"], E=el["E"], nu=el["nu"], thermal=thermal,
                description=doc.get("description", ""), source=doc["source"])
