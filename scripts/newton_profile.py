"""Newton iterations per solve of one stored run, run again (developer profile).

See docs/performance.md.

    /usr/bin/python3 scripts/newton_profile.py FOLDER KEY [FIELD=VALUE ...]

FOLDER is a campaign's output folder, KEY a run key prefix (samples.csv, column key); FIELD=VALUE
overrides scalar fields of the run's SlidingSpec (as ``rerun --set``).  Prints the run's mu, the
number of Newton solves (converged and failed, i.e. cut back), the histogram of iterations per
converged solve, the line-search backtracks, the reasons of failed solves, the Newton solves per
sliding step (sub-steps and guard re-solves: 1 where every step is solved whole) and a few
residual histories (each normalised by its first residual).
"""

from __future__ import annotations

import collections
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from rubberfriction.driver.fe import newton
from rubberfriction.driver.multiscale.specs import find_key, stored_spec
from rubberfriction.driver.runtime.store import Store
from rubberfriction.driver.sliding import steps
from rubberfriction.driver.sliding.run import run_sliding


def main(argv: list[str]) -> int:
    folder, prefix, *sets = argv
    store = Store(Path(folder) / "store")
    spec = stored_spec(store.load(find_key(store, prefix)), Path(folder) / "compounds")
    changes = {}
    for item in sets:
        name, value = item.split("=", 1)
        old = getattr(spec, name)
        changes[name] = value in ("1", "true") if isinstance(old, bool) else type(old)(value)
    spec = dataclasses.replace(spec, **changes)
    log = []
    solve = newton.NewtonSolver.solve

    def logged(self, *args, **kwargs):
        res = solve(self, *args, **kwargs)
        log.append((res.converged, res.iterations, list(res.residuals), res.backtracks,
                    res.reason))
        return res

    newton.NewtonSolver.solve = logged
    per_step = []  # Newton solves per sliding step
    step_solve = steps.StepControl.solve

    def counted(self, *args, **kwargs):
        before = len(log)
        out = step_solve(self, *args, **kwargs)
        if kwargs.get("adaptive"):
            per_step.append(len(log) - before)
        return out

    steps.StepControl.solve = counted
    t0 = time.perf_counter()
    res = run_sliding(spec)
    wall = time.perf_counter() - t0
    ok = [e for e in log if e[0]]
    bad = [e for e in log if not e[0]]
    its = np.array([e[1] for e in ok])
    st = res.stats
    print(f"{res.status}: mu_force {res.mu_force:.6g}, {wall:.1f} s, {st.get('steps', 0):.0f} "
          f"steps, {st.get('periods', float('nan')):g} periods, {st.get('cutbacks', 0):.0f} "
          "cut-backs")
    print(f"solves: {len(ok)} converged ({its.sum()} iterations, mean {its.mean():.2f}), "
          f"{len(bad)} failed ({sum(e[1] for e in bad)} iterations), "
          f"{sum(e[3] for e in log)} line-search backtracks")
    starts = {k: int(st.get(f"{k}_used", 0)) for k in ("predictor", "extrapolation", "period")}
    print("Newton starts used (else the last state):", starts)
    print("iterations per converged solve:", sorted(collections.Counter(its.tolist()).items()))
    print("failed solves:", collections.Counter(e[4][:24] for e in bad).most_common(4))
    print("Newton solves per sliding step:", sorted(collections.Counter(per_step).items()))
    for e in ok[len(ok) // 2: len(ok) // 2 + 6]:
        r = np.array(e[2])
        print(f"  {e[1]:2d} iterations:", " ".join(f"{x:.1e}" for x in r / max(r[0], 1e-300)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
