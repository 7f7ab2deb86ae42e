"""Friction coefficient laws mu(p, v[, T]) for the contact module, and spline fits to data.

The laws are evaluated in C++ (``rubberfriction._contact``) together with their derivatives,
which enter the consistent contact tangent (thesis B.7-B.9).  Units: p in MPa, v in mm/s,
T in K.

* :func:`constant` -- Coulomb friction with a constant coefficient.
* :class:`SplineLaw` -- a tensor-product B-spline in (p, v) or (p, v, T), thesis eq. (6.6)
  written in the B-spline basis.  The velocity axis is usually fitted in log10(v) because
  friction data span decades of velocity (``v_axis="log10"``); the C++ side applies the same
  transform.  Outside the fitted range each argument is clamped (the law continues as a
  constant there, with zero derivative) rather than extrapolating a polynomial, and mu is
  clipped at ``mu_min`` (default 0).
* :func:`fit_mu_pv` / :func:`fit_mu_pvT` -- fits to gridded or scattered data with scipy.

Layout: knots and coefficients follow scipy's FITPACK ``tck`` convention (full knot vectors with
repeated end knots, coefficients in C order over the axes), so a ``RectBivariateSpline(...).tck``
can be passed straight through.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import interpolate

from rubberfriction import _contact

AXES = ("p", "v", "T")


def constant(mu: float) -> _contact.ConstantFriction:
    """Coulomb friction with constant mu (>= 0)."""
    return _contact.ConstantFriction(float(mu))


@dataclass
class SplineLaw:
    """Tensor-product B-spline mu over (p, v) or (p, v, T).

    knots: one full knot vector per axis; degrees: spline degree per axis; coefficients: array of
    shape (n_p, n_v[, n_T]) with n_i = len(knots[i]) - degrees[i] - 1; transforms: 'linear' or
    'log10' per axis (the spline argument is x or log10(max(x, log_floor))).
    """

    knots: list[np.ndarray]
    degrees: list[int]
    coefficients: np.ndarray
    transforms: list[str] = field(default_factory=lambda: ["linear", "log10"])
    log_floor: float = 1e-12
    mu_min: float = 0.0

    def __post_init__(self) -> None:
        self.knots = [np.asarray(k, dtype=float) for k in self.knots]
        self.degrees = [int(d) for d in self.degrees]
        self.coefficients = np.asarray(self.coefficients, dtype=float)
        if len(self.knots) not in (2, 3):
            raise ValueError(f"SplineLaw: need 2 (p, v) or 3 (p, v, T) axes, got {len(self.knots)}")
        if len(self.transforms) != len(self.knots):
            raise ValueError("SplineLaw: transforms needs one entry per axis")
        shape = tuple(len(k) - d - 1 for k, d in zip(self.knots, self.degrees))
        if self.coefficients.size != int(np.prod(shape)):
            raise ValueError(f"SplineLaw: coefficients have {self.coefficients.size} entries, "
                             f"expected {int(np.prod(shape))} = prod(len(knots) - degree - 1) = "
                             f"{shape}")
        self.coefficients = self.coefficients.reshape(shape)
        self._cpp = _contact.SplineFriction([k.tolist() for k in self.knots], self.degrees,
                                            self.coefficients.ravel(), list(self.transforms),
                                            self.log_floor, self.mu_min)

    @property
    def cpp(self) -> _contact.SplineFriction:
        """The C++ law handed to the contact module."""
        return self._cpp

    @property
    def depends_on_temperature(self) -> bool:
        return len(self.knots) == 3

    def __call__(self, p, v, T=293.15) -> np.ndarray:
        """mu at (p, v, T) (arrays broadcast)."""
        return self.evaluate(p, v, T)[..., 0]

    def evaluate(self, p, v, T=293.15) -> np.ndarray:
        """Array [..., 4]: mu, dmu/dp, dmu/dv, dmu/dT."""
        p, v, T = np.broadcast_arrays(np.asarray(p, float), np.asarray(v, float),
                                      np.asarray(T, float))
        out = self._cpp.evaluate_many(p.ravel(), v.ravel(), T.ravel())
        return out.reshape(p.shape + (4,))

    def to_dict(self) -> dict:
        """Plain data (for TOML/JSON/HDF5 storage and hashing)."""
        return {"knots": [k.tolist() for k in self.knots], "degrees": self.degrees,
                "coefficients": self.coefficients.ravel().tolist(),
                "shape": list(self.coefficients.shape), "transforms": list(self.transforms),
                "log_floor": self.log_floor, "mu_min": self.mu_min}

    @classmethod
    def from_dict(cls, d: dict) -> "SplineLaw":
        return cls(d["knots"], d["degrees"], np.reshape(d["coefficients"], d["shape"]),
                   d["transforms"], d.get("log_floor", 1e-12), d.get("mu_min", 0.0))


def _axis(values, transform: str, name: str, floor: float) -> np.ndarray:
    x = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name}: values must be finite")
    if transform == "log10":
        if np.any(x <= 0):
            raise ValueError(f"{name}: a log10 axis needs values > 0, got min {x.min()}")
        return np.log10(np.maximum(x, floor))
    if transform != "linear":
        raise ValueError(f"{name}: transform must be 'linear' or 'log10', got {transform!r}")
    return x


def fit_mu_pv(p, v, mu, *, v_axis: str = "log10", p_axis: str = "linear", degree: int = 3,
              smoothing: float | None = None, mu_min: float = 0.0) -> SplineLaw:
    """Fit a tensor-product spline mu(p, v).

    Gridded data: p (n_p,), v (n_v,) strictly increasing and mu (n_p, n_v): interpolating spline
    (smoothing None or 0) or smoothing spline with FITPACK's smoothing factor `smoothing`
    (``RectBivariateSpline``).  Scattered data: p, v, mu of equal length: smoothing spline
    ``SmoothBivariateSpline`` (smoothing None: FITPACK default).  The degree is lowered to fit
    the number of points per axis.
    """
    p, v, mu = np.asarray(p, float), np.asarray(v, float), np.asarray(mu, float)
    if not np.all(np.isfinite(mu)):
        raise ValueError("mu: values must be finite")
    sp, sv = _axis(p, p_axis, "p", 1e-12), _axis(v, v_axis, "v", 1e-12)
    if mu.ndim == 2:
        if mu.shape != (p.size, v.size):
            raise ValueError("mu: gridded data must have shape (len(p), len(v)) = "
                             f"{(p.size, v.size)}, got {mu.shape}")
        kx, ky = min(degree, p.size - 1), min(degree, v.size - 1)
        if kx < 1 or ky < 1:
            raise ValueError("need at least 2 values of p and of v")
        spl = interpolate.RectBivariateSpline(sp, sv, mu, kx=kx, ky=ky, s=smoothing or 0.0)
    else:
        if not (p.shape == v.shape == mu.shape):
            raise ValueError("scattered data: p, v and mu must have the same length")
        kx = ky = min(degree, 3)
        spl = interpolate.SmoothBivariateSpline(sp, sv, mu, kx=kx, ky=ky, s=smoothing)
    tx, ty, c = spl.tck
    kx, ky = spl.degrees
    return SplineLaw([tx, ty], [kx, ky], np.asarray(c).reshape(len(tx) - kx - 1, len(ty) - ky - 1),
                     [p_axis, v_axis], mu_min=mu_min)


def fit_mu_pvT(p, v, T, mu, *, v_axis: str = "log10", degree: int = 3,
               mu_min: float = 0.0) -> SplineLaw:
    """Interpolating tensor-product spline mu(p, v, T) through gridded data mu (n_p, n_v, n_T).

    The coefficients come from 1D interpolation along each axis in turn (the tensor-product
    interpolation problem is separable on a grid).
    """
    axes = [_axis(p, "linear", "p", 1e-12), _axis(v, v_axis, "v", 1e-12),
            _axis(T, "linear", "T", 1e-12)]
    mu = np.asarray(mu, float)
    shape = tuple(a.size for a in axes)
    if mu.shape != shape:
        raise ValueError(f"mu: gridded data must have shape (len(p), len(v), len(T)) = {shape}, "
                         f"got {mu.shape}")
    if not np.all(np.isfinite(mu)):
        raise ValueError("mu: values must be finite")
    knots, degrees, c = [], [], mu.copy()
    for axis, x in enumerate(axes):
        k = min(degree, x.size - 1)
        if k < 1:
            raise ValueError(f"need at least 2 values along axis {AXES[axis]}")
        spl = interpolate.make_interp_spline(x, c, k=k, axis=axis)
        knots.append(spl.t)
        degrees.append(k)
        c = np.asarray(spl.c)
        if axis != 0:  # make_interp_spline puts the interpolated axis first
            c = np.moveaxis(c, 0, axis)
    return SplineLaw(knots, degrees, c, ["linear", v_axis, "linear"], mu_min=mu_min)


def as_cpp_law(law):
    """Accept None, a float, a SplineLaw or a C++ law; return what the contact module takes."""
    if law is None:
        return None
    if isinstance(law, (int, float, np.floating)):
        return constant(float(law))
    if isinstance(law, SplineLaw):
        return law.cpp
    if isinstance(law, _contact.FrictionLaw):
        return law
    raise TypeError("friction: expected None, a number, a SplineLaw or a _contact.FrictionLaw, "
                    f"got {type(law)!r}")
