"""Averages over surface samples and what more samples buy (thesis eq. 6.12, 6.13, 6.4.2).

Sample statistics (:func:`sample_stats`): mean, standard deviation, 95 % confidence interval
of the mean (Student t) over the samples that succeeded; failed samples are excluded *visibly*
(each average says how many samples it used) and a scale with too many failures is flagged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import stats

from rubberfriction.driver.runtime.store import Outcome


@dataclass(frozen=True)
class SampleStats:
    """Average over surface samples with its spread; ``values`` keeps NaN for failed samples."""

    values: tuple[float, ...]
    mean: float
    std: float  # sample standard deviation (ddof = 1), NaN for one sample
    ci95: float  # half width of the 95 % confidence interval of the mean (Student t), NaN for one
    n_used: int
    n_failed: int

    @property
    def n_total(self) -> int:
        return self.n_used + self.n_failed

    @property
    def failed_fraction(self) -> float:
        return self.n_failed / self.n_total if self.n_total else 0.0

    def as_dict(self, prefix: str) -> dict[str, float]:
        return {prefix: self.mean, f"{prefix}_std": self.std, f"{prefix}_ci95": self.ci95,
                f"{prefix}_n_used": self.n_used, f"{prefix}_n_failed": self.n_failed}


def sample_stats(values: Sequence[float]) -> SampleStats:
    """Mean, standard deviation and 95 % CI over the finite values (eq. 6.12 / 6.13 averages).

    Non-finite values are failed samples: excluded from the average and counted in n_failed.
    """
    v = np.asarray(values, dtype=float)
    ok = v[np.isfinite(v)]
    n = int(ok.size)
    mean = float(ok.mean()) if n else math.nan
    std = float(ok.std(ddof=1)) if n > 1 else math.nan
    ci = float(stats.t.ppf(0.975, n - 1) * std / math.sqrt(n)) if n > 1 else math.nan
    return SampleStats(tuple(float(x) for x in v), mean, std, ci, n, int(v.size - n))


#: a run whose stabilising dashpots carry more than this share of its window's friction work
#: (``SlidingResult.stabilisation_share``, driver.fe.stabilisation) is not averaged.  The
#: tolerance ABAQUS applies to its adaptive stabilisation (stabilisation over strain energy) is
#: 0.05 too; below it the stabilisation moves mu far less than the samples of a scale scatter
#: (docs/performance.md)
STABILISATION_TOL = 0.05
#: a run whose contact shrank to fewer contact elements than this (SlidingResult.contact_elements)
#: rests on single nodes: its contact is narrower than the scale's mesh resolves, the reason an
#: overstabilised run gives (the light loads of the stability sweep, docs/scales.md)
UNRESOLVED_CONTACT = 2.0


def overstabilised(outcome: Outcome) -> bool:
    """A successful run whose stabilisation carries more than STABILISATION_TOL of its friction."""
    return outcome.ok and outcome.value("stabilisation_share") > STABILISATION_TOL


def usable(outcome: Outcome) -> bool:
    """A run whose values enter averages: it succeeded, under the converged time homogenisation
    reached a stationary window (an unconverged run is never averaged), and its stabilisation
    carries at most STABILISATION_TOL of its friction."""
    return outcome.ok and outcome.value("converged") != 0.0 and not overstabilised(outcome)


def unconverged(outcomes: Sequence[Outcome]) -> int:
    """How many of the runs succeeded but did not reach a stationary window in their budget."""
    return sum(o.ok and o.value("converged") == 0.0 for o in outcomes)


def outcome_stats(outcomes: Sequence[Outcome], name: str) -> SampleStats:
    """Sample statistics of one result scalar (failed and unconverged runs count as failed
    samples)."""
    return sample_stats([o.value(name) if usable(o) else math.nan for o in outcomes])


def first_line(reason: str) -> str:
    return reason.splitlines()[0] if reason else "no reason"


def why_unusable(outcome: Outcome) -> str:
    """Why a run does not enter averages: its failure, or why a successful run is left out."""
    if not outcome.ok:
        return first_line(outcome.reason)
    if outcome.value("converged") == 0.0:  # the run's own reason if it stopped early
        return first_line(outcome.reason) if outcome.reason else \
            "no stationary window within the sliding budget"
    if overstabilised(outcome):
        share = f"{100 * outcome.value('stabilisation_share'):.2g} % of the friction work"
        n = outcome.value("contact_elements")
        if n == 0.0:
            return ("contact lost: at times no contact element carried the load (the block fell "
                    "from one asperity tip to the next, a jump quasi-static equilibrium cannot "
                    f"follow); the stabilisation held it and carried {share}")
        if n < UNRESOLVED_CONTACT:
            return (f"unresolved contact: at times {n:.2g} contact elements carried the load "
                    f"(the real contact at this load is narrower than the mesh resolves); the "
                    f"stabilisation carried {share}")
        return f"stabilisation carried {share} (tolerance {100 * STABILISATION_TOL:.0f} %)"
    return "usable"


def mean_contact_pressure(outcomes: Sequence[Outcome]) -> SampleStats:
    """Pressure passed to the next scale, eq. (6.12), from each sample's eq. (6.11) value."""
    return outcome_stats(outcomes, "mean_pressure")


def friction_average(outcomes: Sequence[Outcome], quantity: str = "mu_force") -> SampleStats:
    """Sample-averaged homogenised coefficient of friction, eq. (6.13) (``mu_force``: eq. 6.2)."""
    return outcome_stats(outcomes, quantity)


@dataclass
class SampleCountStudy:
    """Spread of the n-sample mean over random evaluation orders (thesis fig. 6.13 b).

    From N single-sample results mu_1..mu_N: for ``orders`` random permutations, the running mean
    of the first n; ``S[n-1]`` is its standard deviation over the permutations, ``S_exact`` the
    closed form for drawing n of N without replacement, sigma/sqrt(n) sqrt((N-n)/(N-1)) with the
    population standard deviation sigma, against which the Monte Carlo value is checked.
    ``mean_ref`` is the average over all N (the thesis' reference mu_avg^ref).
    """

    values: np.ndarray
    n: np.ndarray
    S: np.ndarray
    S_exact: np.ndarray
    mean_ref: float
    examples: np.ndarray  # (3, N) running means of three random orders (fig. 6.13 b, k = 1..3)
    n_failed: int = 0


def sample_count_study(values: Sequence[float], orders: int = 1000,
                       seed: int = 0) -> SampleCountStudy:
    """S(n), n = 1..N, of the sample mean over ``orders`` random orders (failed = NaN dropped)."""
    v = np.asarray(values, dtype=float)
    ok = v[np.isfinite(v)]
    N = ok.size
    if N < 2:
        raise ValueError(f"a sample-count study needs at least two successful samples, got {N}")
    rng = np.random.default_rng(seed)
    perms = np.argsort(rng.random((orders, N)), axis=1)
    running = np.cumsum(ok[perms], axis=1) / np.arange(1, N + 1)
    n = np.arange(1, N + 1)
    sigma = ok.std(ddof=0)
    S_exact = sigma / np.sqrt(n) * np.sqrt((N - n) / (N - 1))
    return SampleCountStudy(ok, n, running.std(axis=0, ddof=1), S_exact, float(ok.mean()),
                            running[:3],
                            int(v.size - N))
