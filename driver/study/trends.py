"""The thesis' trend table: what it found, the comparison that tests it, and our row.

Each :class:`Trend` states the thesis' figure or sentence and one or more ratios of two
evidence values (:class:`Comparison`) with the direction the thesis found.  :func:`build_rows`
evaluates them on an :class:`~rubberfriction.driver.study.evidence.Evidence`: the ratio, whether
its sign agrees, whether it exceeds the samples' spread (the 95 % half widths of both values,
added in quadrature), whether it lies within a factor 1.5 of the thesis' ratio where the thesis
gives one, and, where ours disagrees, the evidence that says why (mu per scale, lowest-scale
contact, the compounds' loss tangent at the lowest scale's excitation frequency).  Nothing here
runs FE; the table is rebuilt from ``evidence.json`` alone.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from rubberfriction.driver.study.evidence import Evidence, PointValue

#: ratios within this factor of the thesis' ratio agree "in ratio" (issue text, thesis 6.4)
RATIO_FACTOR = 1.5


@dataclass(frozen=True)
class Comparison:
    """``num / den`` of one quantity; the thesis found it above one (``above``) or below."""

    label: str
    num: str  # evidence key (``case:compound@v``, ``spread:S1`` ...)
    den: str
    above: bool = True
    quantity: str = "mu"  # "mu" or "contact"
    counts: bool = True  # False: shown for information, not part of the row's sign


@dataclass(frozen=True)
class Trend:
    """One row of the thesis' trend table."""

    key: str
    title: str
    thesis: str  # the thesis' figure or sentence
    comparisons: tuple[Comparison, ...]
    thesis_ratio: float | None = None  # where the thesis gives a number
    notes_from: tuple[str, ...] = ()  # evidence notes (``<key>: ...``) shown on a disagreement


@dataclass
class ComparisonResult:
    label: str
    ratio: float
    uncertainty: float  # relative, from the two 95 % half widths (nan: one sample)
    sign: bool | None  # agrees with the thesis' direction (None: no evidence)
    significant: bool | None  # |ratio - 1| beyond the uncertainty (None: unknown)
    counts: bool
    missing: str = ""  # why there is no ratio


@dataclass
class TrendRow:
    key: str
    title: str
    thesis: str
    thesis_ratio: float | None
    comparisons: list[ComparisonResult]
    verdict: str  # "agrees" | "partly" | "disagrees" | "missing"
    ratio_ok: bool | None  # within RATIO_FACTOR of the thesis' ratio (None: no thesis ratio)
    why: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def trends(v_low: float, v_high: float, v_cmp: float, flash: str = "m1") -> tuple[Trend, ...]:
    """The eight rows (issue "thesis validation", item 4), at the study's velocities (mm/s)."""
    def m(c: str, case: str = "materials", v: float = v_cmp) -> str:
        return f"{case}:{c}@{v:g}"

    return (
        Trend("speed", "mu(v) rises above 0.1 m/s without temperature, falls with it",
              "8.5.3, fig. 8.18 b: 'an increasing coefficient of friction over velocity without "
              "thermal effects is converted to a decreasing trend if thermal effects are "
              "included'",
              (Comparison(f"isothermal mu({v_high:g}) / mu({v_low:g})",
                          m(flash, "flash", v_high), m(flash, "flash", v_low), True),
               Comparison(f"flash temperature mu({v_high:g}) / mu({v_low:g})",
                          m(flash, "flash_hot", v_high), m(flash, "flash_hot", v_low), False))),
        Trend("glass", "higher glass transition, higher mu at 20 degC",
              "6.5.1, fig. 6.20: 'the expected higher coefficient of friction for high Tg "
              "compounds is achieved for both filler levels' (c1 vs c4, c2 vs c5)",
              (Comparison("c1 / c4", m("c1"), m("c4")), Comparison("c2 / c5", m("c2"), m("c5"))),
              notes_from=("materials",)),
        Trend("hardness", "softer compound, higher mu",
              "6.5.1, fig. 6.21: reproduced for c6 vs c2 over the whole velocity range, for c3 "
              "vs c1 above 0.5 m/s",
              (Comparison("c6 / c2", m("c6"), m("c2")), Comparison("c3 / c1", m("c3"), m("c1"))),
              notes_from=("materials",)),
        Trend("filler", "more filler, higher mu (captured for c1 vs c2 only)",
              "6.5.1, fig. 6.22: the c2-c1 ranking 'is captured properly', the other two pairs "
              "(c3-c6, c4-c5) 'not predicted' (finite linear viscoelasticity, no Payne effect)",
              (Comparison("c1 / c2", m("c1"), m("c2")),
               Comparison("c3 / c6", m("c3"), m("c6"), counts=False),
               Comparison("c4 / c5", m("c4"), m("c5"), counts=False)),
              notes_from=("materials",)),
        Trend("rough", "the rougher surface gives higher mu",
              "6.5.2, fig. 6.25: 'the correct prediction of the surface ranking is achieved' "
              "(surface 2 rougher, c3)",
              (Comparison("rougher / base road, c3", m("c3", "rough"), m("c3")),)),
        Trend("sawtooth", "sharp sawtooth about +40 % over the smooth one",
              "6.4.1, fig. 6.11: 'the sharp sawtooth profile reveals an approximately 40 % larger "
              "generated coefficient of friction'",
              (Comparison("sharp / smooth", "sawtooth:sharp", "sawtooth:smooth"),),
              thesis_ratio=1.4),
        Trend("samples", "the spread of one sample about 3x that of ten",
              "6.4.2, fig. 6.13 b: S(1) = 0.047 down to S(10) = 0.015 (287 samples)",
              (Comparison("S(1) / S(10)", "spread:S1", "spread:S10"),),
              thesis_ratio=0.047 / 0.015),
        Trend("polish", "polishing lowers mu and raises the contact area",
              "6.5.3, fig. 6.28 b-c: mu decreases, the microscopic contact area increases over "
              "the polishing runs",
              (Comparison("polished / base road, mu, c3", m("c3", "polished"), m("c3"), False),
               Comparison("polished / base road, lowest-scale contact, c3",
                          m("c3", "polished"), m("c3"), True, quantity="contact"))),
    )


def _value(ev: Evidence, key: str, quantity: str) -> tuple[float, float, str]:
    """(value, 95 % half width, why missing) of an evidence key."""
    case, _, rest = key.partition(":")
    if case == "spread":
        if ev.spread is None:
            return math.nan, math.nan, "no sample-spread study"
        return (ev.spread.S1 if rest == "S1" else ev.spread.S10), math.nan, ""
    if case == "sawtooth":
        st = ev.sawtooth
        if st is None or not st.ok:
            return math.nan, math.nan, st.reason if st else "no sawtooth runs"
        return (st.sharp if rest == "sharp" else st.smooth), math.nan, ""
    pv = ev.points.get(key)
    if pv is None:
        return math.nan, math.nan, f"{key}: not run"
    if not pv.ok:
        return math.nan, math.nan, f"{key}: failed ({pv.reason or 'no reason recorded'})"
    if quantity == "contact":
        return pv.contact, math.nan, ""
    return pv.mu, pv.ci95, ""


def compare(ev: Evidence, c: Comparison) -> ComparisonResult:
    a, da, why_a = _value(ev, c.num, c.quantity)
    b, db, why_b = _value(ev, c.den, c.quantity)
    missing = "; ".join(w for w in (why_a, why_b) if w)
    if missing or not (math.isfinite(a) and math.isfinite(b)) or b == 0.0:
        return ComparisonResult(c.label, math.nan, math.nan, None, None, c.counts,
                                missing or "no finite value")
    ratio = a / b
    unc = math.hypot(da / a, db / b) if math.isfinite(da) and math.isfinite(db) else math.nan
    sign = (ratio > 1.0) == c.above
    significant = abs(ratio - 1.0) > unc if math.isfinite(unc) else None
    return ComparisonResult(c.label, ratio, unc, sign, significant, c.counts)


def _verdict(results: list[ComparisonResult]) -> str:
    counted = [r for r in results if r.counts]
    if any(r.sign is None for r in counted):
        return "missing"
    agree = sum(bool(r.sign) for r in counted)
    return "agrees" if agree == len(counted) else "disagrees" if agree == 0 else "partly"


def _scale_line(ev: Evidence, c: Comparison) -> str:
    a, b = ev.points.get(c.num), ev.points.get(c.den)
    if not (isinstance(a, PointValue) and isinstance(b, PointValue)):
        return ""
    parts = [f"{s} {a.scale_mu[s] / b.scale_mu[s]:.3f}" for s in a.scale_mu
             if s in b.scale_mu and b.scale_mu[s]]
    contact = (f"; lowest-scale contact {a.contact:.3g} vs {b.contact:.3g}"
               if math.isfinite(a.contact) and math.isfinite(b.contact) else "")
    return f"{c.label}: mu_i ratio per scale {', '.join(parts)}{contact}" if parts else ""


def build_rows(ev: Evidence, table: tuple[Trend, ...]) -> list[TrendRow]:
    """The table's rows from the evidence (see the module docstring)."""
    rows = []
    for t in table:
        results = [compare(ev, c) for c in t.comparisons]
        verdict = _verdict(results)
        ratio_ok = None
        if t.thesis_ratio is not None and results and math.isfinite(results[0].ratio):
            r = results[0].ratio
            ratio_ok = t.thesis_ratio / RATIO_FACTOR <= r <= t.thesis_ratio * RATIO_FACTOR
        why = [r.missing for r in results if r.missing]
        if verdict in ("disagrees", "partly") or ratio_ok is False:
            for c, r in zip(t.comparisons, results):
                if r.counts and (r.sign is False or ratio_ok is False):
                    why.append(_scale_line(ev, c) or f"{c.label}: {r.ratio:.3f}")
            why += [n for n in ev.notes if n.split(":")[0] in t.notes_from]
        why += [n for n in ev.notes if n.split(":")[0] == t.key]
        for r in results:
            if r.counts and r.sign is not None and r.significant is False:
                why.append(f"{r.label}: {r.ratio:.3f} is within the samples' spread "
                           f"(+-{100 * r.uncertainty:.1f} %)")
        rows.append(TrendRow(t.key, t.title, t.thesis, t.thesis_ratio, results, verdict,
                             ratio_ok, [w for w in why if w]))
    return rows


def table_text(rows: list[TrendRow], header: str) -> str:
    """The table as text: one block per row (thesis, our ratios, verdict, why)."""
    out = [header, ""]
    n_sign = sum(r.verdict == "agrees" for r in rows)
    for r in rows:
        out.append(f"[{r.verdict:>9}] {r.key}: {r.title}")
        out.append(f"            thesis: {r.thesis}")
        for c in r.comparisons:
            if c.missing:
                txt = f"no ratio ({c.missing})"
            else:
                unc = f" +- {100 * c.uncertainty:.1f} %" if math.isfinite(c.uncertainty) else ""
                txt = (f"{c.ratio:.3f}{unc}, sign {'agrees' if c.sign else 'disagrees'}"
                       f"{'' if c.counts else ' (for information)'}")
            out.append(f"            ours: {c.label} = {txt}")
        if r.thesis_ratio is not None:
            out.append(f"            ratio {r.thesis_ratio:.2g} in the thesis: "
                       + {True: "ours within a factor 1.5", False: "ours beyond a factor 1.5",
                          None: "no ratio of ours"}[r.ratio_ok])
        out += [f"            why: {w}" for w in r.why]
    out.append("")
    out.append(f"{n_sign} of {len(rows)} trends agree in sign")
    return "\n".join(out)
