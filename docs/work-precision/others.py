"""The scipy and SUNDIALS half of the work-precision table: prints one tab-separated
`WP` row per problem, tool and tolerance, in the format of the Rust half
(`bgdsl-runtime/tests/stiff_work_precision.rs`):

    WP problem tool method rtol atol steps rejected rhs jacobians lu wall_s digits k status

`rhs` counts the evaluations of `f` outside Jacobians; every tool gets the exact
Jacobian (complex step, see `problems.py`). Steps are the accepted steps; scipy and
CVODE do not report rejected steps or (CVODE) factorizations through these bindings:
`-`. Wall time is the best of three runs (one when a run takes over a second), with
the right-hand side in Python: it measures the tool with a Python model, not the
numerical method alone.

Usage: python3 others.py [PROBLEM ...]
"""

import sys
import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp

from problems import NONSTIFF, PROBLEMS, accuracy, jacobian

RTOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]


def run_scipy(method, f, jac, y0, t_end, rtol, atol):
    implicit = method in ("Radau", "BDF", "LSODA")
    sol = solve_ivp(f, (0.0, t_end), y0, method=method, rtol=rtol, atol=atol,
                    **({"jac": jac} if implicit else {}))
    if not sol.success:
        return None, sol.message
    work = (len(sol.t) - 1, "-", sol.nfev, sol.njev, sol.nlu)
    return (sol.y[:, -1], work), None


def run_cvode(f, jac, y0, t_end, rtol, atol):
    import sksundae as sun

    def rhs(t, y, yp):
        yp[:] = f(t, y)

    def jacfn(t, y, yp, jj):
        jj[:, :] = jac(t, y)

    solver = sun.cvode.CVODE(rhs, method="BDF", rtol=rtol, atol=atol, jacfn=jacfn,
                             max_num_steps=10**7)
    sol = solver.solve(np.array([0.0, t_end]), np.asarray(y0, dtype=float))
    if not sol.success:
        return None, sol.message
    work = (len(sol.t) - 1, "-", sol.nfev, sol.njev, "-")
    return (sol.y[-1, :], work), None


EXPLICIT = [
    ("scipy", "RK45", lambda *a: run_scipy("RK45", *a)),
    ("scipy", "DOP853", lambda *a: run_scipy("DOP853", *a)),
]

TOOLS = [
    ("scipy", "Radau", lambda *a: run_scipy("Radau", *a)),
    ("scipy", "BDF", lambda *a: run_scipy("BDF", *a)),
    ("scipy", "LSODA", lambda *a: run_scipy("LSODA", *a)),
    ("sundials", "CVODE-BDF", run_cvode),
]


def rows(name):
    f, y0, t_end, ref, c = PROBLEMS[name]
    jac = jacobian(f)
    y0 = np.asarray(y0, dtype=float)
    for rtol in RTOLS:
        atol = c * rtol
        for tool, method, run in EXPLICIT if name in NONSTIFF else TOOLS:
            best, result, error = float("inf"), None, None
            for _ in range(3):
                started = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    try:
                        result, error = run(f, jac, y0, t_end, rtol, atol)
                    except Exception as e:  # a tool's own failure is a row
                        result, error = None, repr(e)
                elapsed = time.perf_counter() - started
                if result is None:
                    break
                best = min(best, elapsed)
                if elapsed > 1.0:
                    break
            if result is None:
                status = "failed: " + str(error).replace("\t", " ").replace("\n", " ")
                cells = ["-"] * 5 + ["nan", "nan", "nan"]
            else:
                x, work = result
                digits, k = accuracy(x, ref, rtol, atol, c)
                status = "ok"
                cells = [str(w) for w in work] + [f"{best:.6e}", f"{digits:.3f}", f"{k:.3e}"]
            print("\t".join(["WP", name, tool, method, f"{rtol:e}", f"{atol:e}"] + cells
                            + [status]), flush=True)


if __name__ == "__main__":
    for name in sys.argv[1:] or PROBLEMS:
        rows(name)
