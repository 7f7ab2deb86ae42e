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

from rubberfriction import validation as V
from rubberfriction.driver.verification import CASES, SolverFailure

# Admissible values of the verification options, by parameter name (the same name means the same
# quantity in every case): (lower bound, strict, upper bound, strict, what it is).  Checked before
# a case runs, so an impossible parameter is one line naming the option as typed
# (``--R -1: expected a radius > 0 mm``) rather than a failure deep inside a mesh or a solver.
_POSITIVE = {
    "R": "a radius", "E": "a Young's modulus", "P": "a load per unit depth",
    "a_over_R": "a half-width ratio a/R", "pressure": "a pressure", "velocity": "a velocity",
    "length": "a length", "height": "a height", "wavelength": "a wavelength",
    "amplitude": "an amplitude", "depth": "a depth", "L1": "a bar length", "L2": "a bar length",
    "k1": "a conductivity", "k2": "a conductivity", "width": "a width", "h0": "a conductance",
    "h1": "a conductance", "c_N": "a penalty", "grading": "a grading factor",
    "tolerance": "a tolerance", "p_ratio": "a pressure ratio", "n_contact": "an element count",
    "master_points": "a point count", "n_upper": "an element count",
    "n_lower": "an element count", "steps": "a step count", "step_length": "a step length",
    "steps_per_period": "a step count", "periods": "a number of periods",
    "mesh": "an element count",
    "elements_per_a": "element counts", "t_end": "an end time", "T0": "a temperature",
    "T_top": "a temperature", "T_bottom": "a temperature", "temperature": "a temperature",
    "block_length": "a length", "block_height": "a height", "h_x": "an element size",
    "first_layer": "a layer thickness", "n_steps": "a step count", "h_c": "a conductance",
    "elements": "an element count", "peclet": "Peclet numbers", "n": "cell counts",
    "G": "a shear modulus", "K": "a bulk modulus", "tau": "relaxation times",
    "dt_factor": "a time-step factor", "dt": "a time step", "slide": "a sliding distance",
}
_UNITS = {"R": "mm", "E": "MPa", "P": "N/mm", "pressure": "MPa", "velocity": "mm/s",
          "length": "mm", "height": "mm", "wavelength": "mm", "amplitude": "mm", "depth": "mm",
          "L1": "mm", "L2": "mm", "width": "mm", "step_length": "mm", "t_end": "s", "T0": "K",
          "T_top": "K", "T_bottom": "K", "temperature": "K", "block_length": "mm",
          "block_height": "mm", "h_x": "mm", "first_layer": "mm", "G": "MPa", "K": "MPa",
          "tau": "s", "dt": "s", "slide": "mm", "edge_radius": "mm"}
_NONNEGATIVE = {"mu": "a friction coefficient", "edge_radius": "a radius",
                "beta": "a stabilisation factor", "gamma": "Prony weights", "omega": "frequencies",
                "q": "a heat flux", "penetration": "a penetration"}
_FRACTIONS = {"kappa": "a heat-split fraction", "steep_fraction": "a fraction of the period"}


#: Options naming a material file (a shipped name or a TOML file).
_MATERIALS = ("compound", "road", "base")


def _choices() -> dict[str, tuple[str, ...]]:
    """The admissible words of the string options (from the FE layer that checks them too)."""
    from rubberfriction.driver.fe.contact import FRAMES, METHODS
    from rubberfriction.driver.fe.solid import ELEMENTS

    return {"method": tuple(METHODS), "element": tuple(ELEMENTS), "frame": tuple(FRAMES)}


def check_parameters(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Raise an :class:`InputError` ``--OPTION VALUE: expected ...`` for the first option whose
    value is impossible (a negative radius, a Poisson ratio of 0.5 or more, an unknown element
    or compound, ...)."""
    choices = _choices()
    for action in parser._actions:
        name, flag = action.dest, (action.option_strings or [""])[-1]
        value = getattr(args, name, None)
        if flag and isinstance(value, str) and name in choices and not action.choices:
            if value not in choices[name]:
                raise V.InputError(f"{flag} {value}: expected one of "
                                   f"{', '.join(choices[name])}"
                                   f"{V.suggest(value, choices[name])}")
        if flag and isinstance(value, str) and name in _MATERIALS:
            from rubberfriction.forms.material_files import load_compound, load_road

            try:  # read (and validated) here, so a bad file is named by its option
                (load_road if name == "road" else load_compound)(value)
            except ValueError as err:
                raise V.InputError(f"{flag} {value}: {err}") from None
        if not flag or value is None or isinstance(value, (bool, str)):
            continue
        unit = _UNITS.get(name, "")
        if name == "nu":
            V.option(flag, value, what="a Poisson ratio", above=-1.0, below=0.5)
        elif name in _POSITIVE:
            V.option(flag, value, what=_POSITIVE[name], above=0.0, unit=unit)
        elif name in _NONNEGATIVE:
            V.option(flag, value, what=_NONNEGATIVE[name], minimum=0.0, unit=unit)
        elif name in _FRACTIONS:
            V.option(flag, value, what=_FRACTIONS[name], minimum=0.0, maximum=1.0)


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
