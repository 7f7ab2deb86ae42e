"""Registry of the analytical verification cases (``rubberfriction verify CASE``).

name -> (module, one-line description).  A module provides ``add_arguments(parser)`` and
``run(args) -> dict`` (see ``driver/cli/verify.py`` for the result layout) and plain functions
with keyword parameters that the tests call directly.
"""

CASES: dict[str, tuple[str, str]] = {
    "hertz": ("rubberfriction.driver.verification.hertz",
              "plane-strain cylinder on a rigid flat (Hertz)"),
    "westergaard": ("rubberfriction.driver.verification.westergaard",
                    "elastic block on a rigid periodic sinusoid (Westergaard)"),
    "patch": ("rubberfriction.driver.verification.patch",
              "contact patch test on non-matching meshes"),
    "sliding-block": ("rubberfriction.driver.verification.sliding_block",
                      "Coulomb sliding block, Fx/Fz = mu (constant mu and a mu(p, v) law)"),
    "thermal-bars": ("rubberfriction.driver.verification.thermal_bars",
                     "thermal contact: two bars through a conductance, "
                     "frictional heat split kappa"),
    "periodic-sliding": ("rubberfriction.driver.verification.periodic_sliding",
                         "elastic layer sliding over 3 periods of a wrapped periodic sinusoid"),
    "viscoelastic-sinusoid": ("rubberfriction.driver.verification.viscoelastic_sinusoid",
                              "viscoelastic block sliding over a sinusoid in full contact"),
    "sawtooth": ("rubberfriction.driver.verification.sawtooth",
                 "sawtooth anisotropy, sharp vs smooth"),
    "flash-flux": ("rubberfriction.driver.verification.heat_cases",
                   "uniform frictional power into a resting block: "
                   "surface temperature vs 2 q sqrt(t / (pi k rho c))"),
    "two-body-conduction": ("rubberfriction.driver.verification.heat_cases",
                            "two conducting half-spaces heated at the interface: "
                            "temperature and heat split by effusivity"),
    "moving-heat-source": ("rubberfriction.driver.verification.heat_cases",
                           "steady road temperature under a sliding block "
                           "vs Jaeger's moving band source"),
    "pressure-modes": ("rubberfriction.driver.verification.pressure_modes",
                       "spurious pressure modes of Q1P0 and the stabilised Q1P0s "
                       "in a confined block"),
    "bem-pressure": ("rubberfriction.driver.verification.bem_pressure",
                     "frictionless pressure branch on a self-affine profile vs a periodic FFT BEM"),
    "relaxation": ("rubberfriction.driver.verification.relaxation",
                   "bulk stress relaxation and harmonic shear vs the Prony closed form"),
}


class SolverFailure(RuntimeError):
    """A verification case whose nonlinear solve did not converge for the parameters given: the
    ``verify`` command prints its message as one line and exits with status 1 (no traceback)."""


def check(quantity: str, computed: float, analytical: float,
          tolerance: float | None = None) -> dict:
    """One computed-vs-analytical line of a verification result."""
    rel = abs(computed - analytical) / abs(analytical) if analytical != 0 else abs(computed)
    out = {"quantity": quantity, "computed": float(computed), "analytical": float(analytical),
           "rel_error": float(rel), "tolerance": tolerance}
    if tolerance is not None:
        out["passed"] = bool(rel <= tolerance)
    return out


def case_function(functions: dict, parser, module: str):
    """The case function of a sub-command parser (its last program word names the case)."""
    name = parser.prog.split()[-1]
    if name not in functions:
        raise ValueError(f"{module}: unknown case {name!r} (expected one of {sorted(functions)})")
    return functions[name]


def add_keyword_arguments(parser, fn) -> None:
    """One --option per keyword parameter of `fn` (booleans and `law` are not options)."""
    import inspect

    for name, prm in inspect.signature(fn).parameters.items():
        default = prm.default
        flag = "--" + name.replace("_", "-")
        if isinstance(default, bool) or default is inspect.Parameter.empty or name == "law":
            continue
        if isinstance(default, tuple):
            parser.add_argument(flag, dest=name, type=type(default[0]), nargs="+",
                                default=list(default),
                                help=f"(default: {' '.join(map(str, default))})")
        elif default is None:  # an `int | None` parameter takes whole numbers, any other floats
            kind = (int if str(prm.annotation).replace(" ", "") in ("int|None", "Optional[int]")
                    else float)
            parser.add_argument(flag, dest=name, type=kind, default=None,
                                help="(default: automatic)")
        else:
            parser.add_argument(flag, dest=name, type=type(default), default=default,
                                help=f"(default: {default})")


def call_with_arguments(fn, args) -> dict:
    """Call `fn` with the parsed options named like its keyword parameters."""
    import inspect

    kwargs = {}
    for name in inspect.signature(fn).parameters:
        if hasattr(args, name):
            v = getattr(args, name)
            kwargs[name] = tuple(v) if isinstance(v, list) else v
    return fn(**kwargs)
