"""``rubberfriction verify CASE [options] [--json FILE]``: analytical benchmarks as a product
feature.

Each case module (registered in ``rubberfriction.driver.verification.CASES``) provides
``add_arguments(parser)`` for the user's parameters and ``run(args) -> dict`` returning
``{"case": ..., "parameters": {...}, "checks": [{"quantity", "computed", "analytical",
"rel_error", "tolerance"}], ...}``.  The tests call the same functions with fixed parameters.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys

from rubberfriction.driver.verification import CASES, SolverFailure
from rubberfriction.driver.verification.parameters import check_parameters


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("verify", help="run an analytical verification case with your parameters")
    cases = p.add_subparsers(dest="case", metavar="CASE")
    for name, (module_name, help_text) in CASES.items():
        module = importlib.import_module(module_name)
        cp = cases.add_parser(name, help=help_text, description=help_text)
        module.add_arguments(cp)
        cp.add_argument("--json", metavar="FILE", help="write the result as JSON")
        cp.set_defaults(func=_run_case(module, cp))


def _run_case(module, parser: argparse.ArgumentParser):
    def run(args: argparse.Namespace) -> int:
        check_parameters(parser, args)  # an impossible one: one line, exit status 2
        try:
            result = module.run(args)
        except SolverFailure as err:  # no equilibrium found for these parameters: one line
            print(f"verify {args.case}: {err}", file=sys.stderr)
            return 1
        print_result(result)
        if args.json:
            with open(args.json, "w") as f:
                json.dump(result, f, indent=2, default=float)
            print(f"written: {args.json}")
        return 0 if all(c.get("passed", True) for c in result.get("checks", [])) else 1

    return run


def print_result(result: dict, out=None) -> None:
    out = out if out is not None else sys.stdout  # looked up per call (redirected streams)
    print(f"verification case: {result.get('case')}", file=out)
    for k, v in result.get("parameters", {}).items():
        print(f"  {k} = {v}", file=out)
    print(f"  {'quantity':<28} {'computed':>14} {'analytical':>14} {'rel. error':>11} {'tol':>8}",
          file=out)
    for c in result.get("checks", []):
        tol = c.get("tolerance")
        mark = "" if c.get("passed", True) else "  <-- outside tolerance"
        print(f"  {c['quantity']:<28} {c['computed']:>14.6g} {c['analytical']:>14.6g} "
              f"{c['rel_error']:>11.3e} {tol if tol is not None else '':>8}{mark}", file=out)
    for line in result.get("notes", []):
        print(f"  note: {line}", file=out)
