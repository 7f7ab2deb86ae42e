"""Bulk viscoelasticity against the linear closed forms of a Prony series (eqs. 3.34, 3.72-3.78).

One element in homogeneous simple shear of small amplitude (finite strain = linear up to
O(gamma^2)), every node prescribed.  Two histories:

* ramp over t_ramp then hold:  sigma(t) = gamma0 G_inf [1 + sum_k g_k tau_k e^(-t/tau_k)
  (e^(t_ramp/tau_k) - 1) / t_ramp],  g_k = gamma_k / gamma_inf  (long-term Mooney-Rivlin moduli);
* harmonic shear gamma0 sin(omega t):  G', G'' from a least-squares fit of the stress (sin, cos
  and the known transients exp(-t/tau_k)), compared with eq. (3.34) in shear form
  (E = 3G for an incompressible material), and the viscous energy per cycle with pi gamma0^2 G'';
* harmonic shear of finite amplitude (``--finite-amplitude``, default 0.5): the viscous energy
  the history reports per cycle and the loop area against the closed form of the finite-strain
  model (``finite_shear_cycle_energy``), the energy balance of thesis eq. 2.8.
"""

from __future__ import annotations

import argparse

import numpy as np
import ufl
from dolfinx import mesh as dmesh
from mpi4py import MPI

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import NewtonSettings, NewtonSolver
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import check
from rubberfriction.forms import jit
from rubberfriction.forms.kinematics import deformation_gradient
from rubberfriction.forms.compound import Compound, MooneyRivlin, PronySeries, prony_complex_modulus


class ShearCell:
    """One Q1P0 element in homogeneous simple shear gamma(t)."""

    def __init__(self, hyperelastic: MooneyRivlin, gamma, tau, scheme: str = "linear"):
        m = dmesh.create_unit_square(MPI.COMM_SELF, 1, 1, dmesh.CellType.quadrilateral)
        tags = dmesh.meshtags(m, 1, np.array([], np.int32), np.array([], np.int32))
        mat = Compound(name="shear-cell", hyperelastic=hyperelastic,
                       prony=PronySeries(np.asarray(gamma, float), np.asarray(tau, float)),
                       wlf=None, thermal=None)
        self.sp = SolidProblem(m, tags, mat, SolidSettings(viscous_scheme=scheme))
        spec = ConstraintSpec(self.sp.W.dofmap.index_map.size_local)
        d = self.sp.displacement_dofs()
        spec.fix(d.ravel(), 0.0)
        self.cmap = ConstraintMap(spec)
        self.ux, self.z = d[:, 0], self.sp.node_X[:, 1]
        pb = self.sp.nonlinear_problem(self.cmap)
        self.newton = NewtonSolver(pb, NewtonSettings(rtol=1e-12, atol=1e-15))
        u, _ = self.sp.split()
        F = deformation_gradient(u)
        sigma = F * self.sp.second_piola() * F.T / ufl.det(F)
        self._tau_xy = jit.expression(sigma[0, 1], self.sp.rule.points)  # homogeneous: any point

    def step(self, gamma: float, dt: float) -> tuple[float, float]:
        """Advance one step to shear gamma; returns (shear stress, viscous energy of the step)."""
        for dof, z in zip(self.ux, self.z):
            self.cmap.fixed_roots[int(self.cmap.roots[dof])] = gamma * z
        self.sp.prepare_step(dt)
        res = self.newton.solve()
        if not res.converged:
            raise RuntimeError(f"shear cell: Newton failed: {res.reason}")
        dE = self.sp.commit_step()
        return float(self._tau_xy.eval(np.array([0], np.int32)).mean()), dE


def ramp_hold(hyperelastic: MooneyRivlin, gamma, tau, *, dt: float, t_ramp: float, t_end: float,
              gamma0: float = 1e-5, scheme: str = "linear") -> dict:
    """Max relative stress error over a ramp-and-hold history sampled every dt."""
    G_inf = hyperelastic.mu
    g = np.asarray(gamma, float) / (1.0 - np.sum(gamma))
    tau = np.asarray(tau, float)
    cell = ShearCell(hyperelastic, gamma, tau, scheme)
    times, fe, exact = [], [], []
    for i in range(1, int(round(t_end / dt)) + 1):
        t = i * dt
        s, _ = cell.step(gamma0 * min(t / t_ramp, 1.0), dt)
        if t >= t_ramp - 1e-12:
            times.append(t)
            fe.append(s)
            exact.append(gamma0 * G_inf * (1.0 + np.sum(g * tau * np.exp(-t / tau)
                                                        * np.expm1(t_ramp / tau)) / t_ramp))
    fe, exact = np.array(fe), np.array(exact)
    err = np.abs(fe - exact) / np.abs(exact)
    return {"t": np.array(times), "stress": fe, "exact": exact, "max_rel_error": float(err.max())}


def _drive(hyperelastic: MooneyRivlin, gamma, tau, scheme: str, omega: float, gamma0: float,
           per_cycle: int, cycles: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The FE shear cell driven by gamma0 sin(omega t) for ``cycles`` cycles of ``per_cycle``
    steps: the step end times, the shear stress and the viscous energy of each step."""
    cell = ShearCell(hyperelastic, gamma, tau, scheme)
    dt = 2.0 * np.pi / omega / per_cycle
    t = dt * np.arange(1, per_cycle * cycles + 1)
    stress, energy = np.empty_like(t), np.empty_like(t)
    for i, ti in enumerate(t):
        stress[i], energy[i] = cell.step(gamma0 * np.sin(omega * ti), dt)
    return t, stress, energy


def harmonic_shear(hyperelastic: MooneyRivlin, gamma, tau, *, omega: float, per_cycle: int = 200,
                   cycles: int = 6, gamma0: float = 1e-5, scheme: str = "linear") -> dict:
    """G', G'' and energy per cycle from the FE response to gamma0 sin(omega t)."""
    G_inf = hyperelastic.mu
    g = np.asarray(gamma, float) / (1.0 - np.sum(gamma))
    tau = np.asarray(tau, float)
    G = complex(prony_complex_modulus(omega, G_inf, G_inf * g, tau))
    G_storage, G_loss = G.real, G.imag
    t, stress, energy = _drive(hyperelastic, gamma, tau, scheme, omega, gamma0, per_cycle,
                               cycles)
    A = np.column_stack([np.sin(omega * t), np.cos(omega * t)] + [np.exp(-t / tk) for tk in tau])
    coef = np.linalg.lstsq(A, stress, rcond=None)[0]
    gam = gamma0 * np.sin(omega * t[-per_cycle - 1:])
    sig = stress[-per_cycle - 1:]
    return {"G_storage": coef[0] / gamma0, "G_loss": coef[1] / gamma0,
            "G_storage_exact": G_storage, "G_loss_exact": G_loss,
            "energy_per_cycle": float(energy[-per_cycle:].sum()),
            "loop_area": float(np.sum(0.5 * (sig[1:] + sig[:-1]) * np.diff(gam))),
            "energy_exact": float(np.pi * gamma0**2 * G_loss)}


def _shear_C(gamma: np.ndarray) -> np.ndarray:
    """C = F^T F of plane-strain simple shear u_x = gamma z, shape (..., 3, 3) (J = 1)."""
    C = np.zeros(np.shape(gamma) + (3, 3))
    C[..., 0, 0] = C[..., 2, 2] = 1.0
    C[..., 0, 1] = C[..., 1, 0] = gamma
    C[..., 1, 1] = 1.0 + gamma**2
    return C


def finite_shear_cycle_energy(hyperelastic: MooneyRivlin, gamma, tau, *, omega: float,
                              gamma0: float, samples: int = 256) -> float:
    """Energy dissipated per cycle and unit volume by the finite-strain model (eqs. 3.73-3.78)
    in the periodic steady state of simple shear gamma0 sin(omega t), in closed form.

    With J = 1, Cbar = C and the equilibrium part conservative, the cycle work is that of the
    non-equilibrium stress: W = sum_k g_k/2 oint H^k : dC/dt dt, where the steady branch history
    of H' = -H/tau_k + d DEV{Sbar}/dt has, harmonic by harmonic, H_n = i n w tau_k /
    (1 + i n w tau_k) DEV{Sbar}_n.  DEV{Sbar}(C(t)) of Mooney-Rivlin in simple shear is a
    polynomial of degree 6 in gamma: its Fourier series ends at the 6th harmonic, so
    ``samples`` >= 16 equally spaced samples of a period give every integral exactly (to
    round-off).  At small gamma0 it is pi gamma0^2 G'' (``harmonic_shear``)."""
    if samples < 16:
        raise ValueError(f"samples = {samples}: need >= 16 for the 6th harmonic")
    g = np.asarray(gamma, float) / (1.0 - np.sum(gamma))
    t = 2.0 * np.pi / omega * np.arange(samples) / samples
    gam = gamma0 * np.sin(omega * t)
    C = _shear_C(gam)
    Ci = np.linalg.inv(C)
    trC = np.trace(C, axis1=-2, axis2=-1)
    c10, c01 = hyperelastic.C10, hyperelastic.C01
    Sbar = 2.0 * ((c10 + c01 * trC)[:, None, None] * np.eye(3) - c01 * C)
    S_dev = Sbar - np.einsum("tij,tij->t", Sbar, C)[:, None, None] / 3.0 * Ci
    dC = np.zeros_like(C)  # dC/dt = dC/dgamma gamma'
    dgam = gamma0 * omega * np.cos(omega * t)
    dC[:, 0, 1] = dC[:, 1, 0] = dgam
    dC[:, 1, 1] = 2.0 * gam * dgam
    n = np.fft.fftfreq(samples, 1.0 / samples)  # harmonic numbers
    S_hat = np.fft.fft(S_dev, axis=0)
    work = 0.0
    for gk, tk in zip(g, np.asarray(tau, float)):
        x = 1j * n * omega * tk
        H = np.fft.ifft((x / (1.0 + x))[:, None, None] * S_hat, axis=0).real
        work += 0.5 * gk * float(np.mean(np.einsum("tij,tij->t", H, dC)))
    return work * 2.0 * np.pi / omega


def finite_harmonic_shear(hyperelastic: MooneyRivlin, gamma, tau, *, omega: float,
                          gamma0: float, per_cycle: int = 64, cycles: int = 4,
                          scheme: str = "linear") -> dict:
    """The FE cell in simple shear gamma0 sin(omega t) at any amplitude: over the last cycle,
    the viscous energy the history reports (``ViscoelasticHistory.commit_step``) and the loop
    area oint sigma_xz dgamma (the work of the boundary, sigma_xz = P_xz for simple shear),
    per unit volume (the cell is the unit square)."""
    t, stress, energy = _drive(hyperelastic, gamma, tau, scheme, omega, gamma0, per_cycle,
                               cycles)
    gam = gamma0 * np.sin(omega * t[-per_cycle - 1:])
    sig = stress[-per_cycle - 1:]
    return {"energy_per_cycle": float(energy[-per_cycle:].sum()),
            "loop_area": float(np.sum(0.5 * (sig[1:] + sig[:-1]) * np.diff(gam))),
            "energy_exact": finite_shear_cycle_energy(hyperelastic, gamma, tau, omega=omega,
                                                      gamma0=gamma0)}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--C10", type=float, default=0.174, help="MPa (default: compound m1)")
    p.add_argument("--C01", type=float, default=0.300, help="MPa")
    p.add_argument("--D1", type=float, default=0.0208, help="1/MPa")
    p.add_argument("--gamma", type=float, nargs="+", default=[0.5, 0.3], help="Prony gamma_k")
    p.add_argument("--tau", type=float, nargs="+", default=[0.01, 0.1], help="Prony tau_k [s]")
    p.add_argument("--dt-factor", type=float, default=0.1, help="dt = factor * tau_min")
    p.add_argument("--scheme", default="linear", choices=["linear", "midpoint"],
                   help="history update: exact for linear-in-time Sbar (default) "
                        "or the midpoint rule (3.76)")
    p.add_argument("--finite-amplitude", type=float, default=0.5,
                   help="simple-shear amplitude of the finite-strain energy check at omega = "
                        "1/tau_min: dissipation and loop area per cycle against the closed form "
                        "(0: skip)")
    p.add_argument("--omega", type=float, nargs="*", default=None,
                   help="frequencies [rad/s] for harmonic shear (default: 0.1, 1, 10 / tau_min)")


def run(args: argparse.Namespace) -> dict:
    hyp = MooneyRivlin(args.C10, args.C01, args.D1)
    if len(args.gamma) != len(args.tau):
        raise SystemExit("--gamma and --tau need the same number of terms")
    tmin, tmax = min(args.tau), max(args.tau)
    dt = args.dt_factor * tmin
    r = ramp_hold(hyp, args.gamma, args.tau, dt=dt, t_ramp=dt, t_end=3.0 * tmax, scheme=args.scheme)
    checks = [check("relaxation max rel. error", r["max_rel_error"], 0.0, None)]
    checks[0]["rel_error"] = r["max_rel_error"]
    checks[0]["tolerance"], checks[0]["passed"] = 0.01, r["max_rel_error"] <= 0.01
    for w in args.omega or [0.1 / tmin, 1.0 / tmin, 10.0 / tmin]:
        h = harmonic_shear(hyp, args.gamma, args.tau, omega=w, scheme=args.scheme)
        checks += [check(f"G' at omega={w:g}", h["G_storage"], h["G_storage_exact"], 0.01),
                   check(f"G'' at omega={w:g}", h["G_loss"], h["G_loss_exact"], 0.01),
                   check(f"energy/cycle omega={w:g}", h["energy_per_cycle"], h["energy_exact"],
                         0.01)]
    amp = getattr(args, "finite_amplitude", 0.5)
    if amp > 0.0:  # the energy balance at finite strain: dissipation = loop area = closed form
        w = 1.0 / tmin
        cycles = max(4, int(np.ceil(12.0 * tmax * w / (2.0 * np.pi))) + 1)  # transient < e^-12
        f = finite_harmonic_shear(hyp, args.gamma, args.tau, omega=w, gamma0=amp, cycles=cycles,
                                  scheme=args.scheme)
        checks += [check(f"dissipation/cycle, gamma0={amp:g}", f["energy_per_cycle"],
                         f["energy_exact"], 0.01),
                   check(f"loop area/cycle, gamma0={amp:g}", f["loop_area"], f["energy_exact"],
                         0.01)]
    return {"case": "relaxation", "parameters": {"C10": args.C10, "C01": args.C01, "D1": args.D1,
                                                 "gamma": args.gamma, "tau": args.tau, "dt": dt,
                                                 "scheme": args.scheme},
            "checks": checks, "notes": ["shear moduli; E = 3 G for an incompressible material"]}
