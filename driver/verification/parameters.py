"""The admissible values of the ``rubberfriction verify`` options, checked before a case runs.

Shared by the command line (``driver/cli/verify.py``) and the Python API (``rf.verify``), so an
impossible parameter is one line naming the option (``--R -1: expected a radius > 0 mm``) rather
than a failure deep inside a mesh or a solver.
"""

from __future__ import annotations

import argparse

from rubberfriction import validation as V

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
