"""Compilation of every UFL form and expression of the project with one set of JIT options.

The stresses of eqs. (3.77), (3.78) scale with J^(-2/3); FFCx writes that factor as a call
``pow(J, -2/3)`` in every generated term that uses it: 57 calls per quadrature point in the
Jacobian of the viscoelastic Q1P0 form, 13 in its residual.  Under C's default ``math_errno``
semantics pow may set ``errno``, so the C compiler must make every call.  ``-fno-math-errno``
(nothing here reads ``errno``) lets it evaluate each distinct call once: the generated values are
bitwise the same and the bulk assembly is faster (docs/performance.md; ``rubberfriction bench
bulk``).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np
from dolfinx import fem

#: C compiler flags of the generated kernels (dolfinx's default is -O2 -g0)
COMPILE_ARGS: tuple[str, ...] = ("-O2", "-g0", "-fno-math-errno")


def jit_params() -> dict[str, Any]:
    """dolfinx ``jit_params`` with :data:`COMPILE_ARGS` (a fresh dict: dolfinx may modify it)."""
    return {"cffi_extra_compile_args": list(COMPILE_ARGS)}


def form(ufl_form: Any) -> fem.FormMetaClass:
    """``dolfinx.fem.form`` compiled with the project's JIT options."""
    return fem.form(ufl_form, jit_params=jit_params())


def expression(ufl_expr: Any, points: np.ndarray) -> fem.Expression:
    """``dolfinx.fem.Expression`` at reference points, compiled with the project's JIT options."""
    return fem.Expression(ufl_expr, points, jit_params=jit_params())


#: dolfinx's own flags (before this module): for benchmarks that show what COMPILE_ARGS buys
DOLFINX_DEFAULT_ARGS: tuple[str, ...] = ("-O2", "-g0")


@contextlib.contextmanager
def compile_args(args: Sequence[str]) -> Iterator[None]:
    """Forms and expressions made inside the block are compiled with ``args`` (benchmarks)."""
    global COMPILE_ARGS
    saved, COMPILE_ARGS = COMPILE_ARGS, tuple(args)
    try:
        yield
    finally:
        COMPILE_ARGS = saved
