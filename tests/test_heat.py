"""Heat equation (3.89) with implicit Euler (5.25) against the semi-infinite constant-flux solution.

A body x >= 0 at T0 receives a constant flux q at x = 0:
    T(0, t) - T0 = 2 q sqrt(t / (pi k rho c)).
The strip is long compared with the diffusion length, the mesh is graded toward the heated face.
Tolerance 1 % at t = 0.5 s and 2 s (implicit Euler error ~ dt / t plus spatial error).
"""

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import (ConstrainedNonlinearProblem, NewtonSettings,
                                             NewtonSolver)
from rubberfriction.forms.heat import heat_residual
from rubberfriction.forms.material_files import load_compound


def test_semi_infinite_constant_flux():
    th = load_compound("m1").thermal  # table C.3: rho c = 2.02 mJ/(mm^3 K), k = 0.2553 mW/(mm K)
    q, T0, L = 0.5, 293.15, 6.0  # mW/mm^2 into the body, K, mm (diffusion length at 2 s: 0.5 mm)
    n = 120
    m = dmesh.create_rectangle(MPI.COMM_SELF, [[0.0, 0.0], [1.0, 0.1]], [n, 1],
                               dmesh.CellType.quadrilateral)
    m.geometry.x[:, 0] = L * m.geometry.x[:, 0] ** 2  # graded: first element 4e-4 mm
    left = dmesh.locate_entities_boundary(m, 1, lambda x: np.isclose(x[0], 0.0))
    tags = dmesh.meshtags(m, 1, left.astype(np.int32), np.full(left.size, 1, np.int32))
    V = fem.FunctionSpace(m, ("Lagrange", 1))
    theta, theta_n = fem.Function(V), fem.Function(V)
    theta.x.array[:] = T0
    theta_n.x.array[:] = T0
    dt = fem.Constant(m, 0.0)
    ds = ufl.Measure("ds", domain=m, subdomain_data=tags)
    F = heat_residual(theta, theta_n, ufl.TestFunction(V), rho=th.rho, c=th.c, k=th.k, dt=dt,
                      flux_out=fem.Constant(m, -q), ds=ds(1))
    J = ufl.derivative(F, theta, ufl.TrialFunction(V))
    cmap = ConstraintMap(ConstraintSpec(V.dofmap.index_map.size_local))
    pb = ConstrainedNonlinearProblem(F, J, theta, cmap)
    newton = NewtonSolver(pb, NewtonSettings(rtol=1e-12, atol=1e-14))
    x0 = V.tabulate_dof_coordinates()[:, 0]
    surface = np.isclose(x0, 0.0)
    t, errors = 0.0, {}
    for step_dt, t_end in [(1e-4, 0.01), (1e-3, 0.5), (2e-3, 2.0)]:
        dt.value = step_dt
        while t < t_end - 1e-12:
            res = newton.solve()
            assert res.converged and res.iterations <= 2, res  # linear problem: one Newton step
            theta_n.x.array[:] = theta.x.array
            t += step_dt
        exact = 2.0 * q * np.sqrt(t / (np.pi * th.k * th.rho * th.c))
        errors[t_end] = abs(theta.x.array[surface].mean() - T0 - exact) / exact
    assert errors[0.5] < 0.01 and errors[2.0] < 0.01, errors
