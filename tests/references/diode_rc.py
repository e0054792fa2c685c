#!/usr/bin/env python3
"""Reference for tests/tests/loops.rs `diode_loop_follows_the_lambert_w_reference`.

Circuit: a source E in series with a resistor R, a diode (i = Is (exp(v_D / Vt) - 1))
and a capacitor C, all carrying one current i. With v the capacitor's voltage, the loop
current solves i = Is (exp((E - v - R i) / Vt) - 1); with u = i + Is,

    (R u / Vt) exp(R u / Vt) = (R Is / Vt) exp((E - v + R Is) / Vt),

so i(v) = (Vt / R) W((R Is / Vt) exp((E - v + R Is) / Vt)) - Is, W the principal
branch of Lambert's W. The reduced ODE C dv/dt = i(v) is integrated with mpmath's
Taylor-series solver (odefun) at 30 significant digits and cross-checked against
scipy's DOP853 at rtol 1e-13; the script fails if they differ by more than 1e-11
relative to the largest voltage.

Rerun (needs Python 3 with mpmath and scipy: `pip install mpmath scipy`):

    python3 tests/references/diode_rc.py

and paste the printed table into REFERENCE in tests/tests/loops.rs.
"""
import mpmath as mp
from scipy.integrate import solve_ivp
from scipy.special import lambertw
import math

E, R, IS, VT, C, V0 = 1.5, 100.0, 1e-9, 0.05, 10e-6, 0.0
T_END, SAMPLES = 2e-3, 21

mp.mp.dps = 30


def current_mp(v):
    arg = (R * IS / VT) * mp.exp((E - v + R * IS) / VT)
    return (VT / R) * mp.lambertw(arg) - IS


def current_f64(v):
    arg = (R * IS / VT) * math.exp((E - v + R * IS) / VT)
    return (VT / R) * lambertw(arg).real - IS


def main():
    times = [T_END * k / (SAMPLES - 1) for k in range(SAMPLES)]
    solution = mp.odefun(lambda t, v: current_mp(v) / C, 0, mp.mpf(V0))
    exact = [solution(mp.mpf(t)) for t in times]
    check = solve_ivp(lambda t, v: [current_f64(v[0]) / C], (0.0, T_END), [V0],
                      method="DOP853", rtol=1e-13, atol=1e-16, t_eval=times)
    scale = max(abs(float(v)) for v in exact)
    worst = max(abs(float(a) - b) for a, b in zip(exact, check.y[0]))
    assert worst <= 1e-11 * scale, f"mpmath and DOP853 differ by {worst}"
    print(f"// max |mpmath - DOP853| = {worst:.1e} V")
    print("// (t s, capacitor voltage V, loop current A), each the f64 nearest the")
    print("// 30-digit value, written in the fewest digits that read back to it")
    for t, v in zip(times, exact):
        print(f"    ({round(t, 12)!r}, {float(v)!r}, {float(current_mp(v))!r}),")


if __name__ == "__main__":
    main()
