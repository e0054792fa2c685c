"""Checks what the starter template's program wrote, against the scale's closed form.

Run by `.ci/starter` as `python3 starter_check.py KIND PATH`:

- `results DIR`: DIR/scale.csv (the run of scenarios/load.yaml, default parameters);
- `sweep DIR`: DIR/sweep.csv (scenarios/damping_sweep.yaml): the peak reading of
  each damping;
- `fmu FILE`: FMPy's `validate_fmu` finds no problem in the FMU, its
  Co-Simulation run with `damping` set to 80 N s/m through `start_values` follows the
  closed form, and a negative damping is refused (the template's rules, in the FMU).

The scale is a damped oscillator stepped by its load (see examples/starter/src/lib.rs):
with m = pan + load, w = sqrt(k / m), z = c / (2 sqrt(k m)) < 1 and
wd = w sqrt(1 - z^2), the tared reading is

    load (1 - exp(-z w t) (cos(wd t) + z / sqrt(1 - z^2) sin(wd t)))

and its peak, at t = pi / wd, load (1 + exp(-z pi / sqrt(1 - z^2))) (any textbook's
step response of a second-order system, e.g. Ogata, Modern Control Engineering,
section 5-3). Above critical damping it never exceeds the load.
Prints one line per check; exits 1 if any failed.
"""

import csv
import math
import sys

PAN, LOAD, K, G = 0.5, 2.0, 5000.0, 9.81
MASS = PAN + LOAD


def ratio(c):
    return c / (2.0 * math.sqrt(K * MASS))


def reading(t, c):
    w = math.sqrt(K / MASS)
    z = ratio(c)
    wd = w * math.sqrt(1.0 - z * z)
    decay = math.exp(-z * w * t)
    return LOAD * (1.0 - decay * (math.cos(wd * t) + z / math.sqrt(1.0 - z * z) * math.sin(wd * t)))


def peak(c):
    z = ratio(c)
    return LOAD * (1.0 + math.exp(-z * math.pi / math.sqrt(1.0 - z * z)))


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def check(ok, what):
    print(("OK     " if ok else "FAILED ") + what)
    return ok


def results(folder):
    data = rows(f"{folder}/scale.csv")
    # The stiff solver's default tolerances: 5e-6 kg seen; 1e-4 kg is 0.005 % of the load.
    error = max(abs(float(r["reading"]) - reading(float(r["t"]), 40.0)) for r in data)
    ok = check(len(data) == 1001, f"scale.csv has 1001 samples (0 to 1 s every 1 ms): {len(data)}")
    return check(error < 1e-4, f"the reading follows the closed form within 1e-4 kg: {error:.2e}") and ok


def sweep(folder):
    data = rows(f"{folder}/sweep.csv")
    ok = check([float(r["damping"]) for r in data] == [20.0, 40.0, 80.0, 160.0, 320.0],
               "sweep.csv has the five dampings in order")
    for r in data:
        c, found = float(r["damping"]), float(r["peak_reading"])
        if ratio(c) < 1.0:
            # Sampled every 0.1 ms: the sampled peak is within w^2 dt^2 / 2 (1e-5) of it.
            expected = peak(c)
            ok = check(abs(found - expected) < 1e-4 * LOAD,
                       f"damping {c}: peak {found:.6f} kg, closed form {expected:.6f}") and ok
        else:
            ok = check(LOAD - 1e-3 < found <= LOAD + 1e-4 * LOAD,
                       f"damping {c} (over critical): peak {found:.6f} kg, not above the load") and ok
    return ok


def fmu(path):
    import fmpy
    from fmpy.validation import validate_fmu

    problems = validate_fmu(path)
    ok = check(not problems, f"FMPy {fmpy.__version__} validates {path}: {problems}")
    damping = 80.0
    result = fmpy.simulate_fmu(path, fmi_type="CoSimulation", stop_time=1.0, output_interval=1e-3,
                               start_values={"damping": damping}, output=["reading"])
    error = max(abs(row["reading"] - reading(row["time"], damping)) for row in result)
    ok = check(len(result) == 1001, f"FMPy's run has 1001 rows: {len(result)}") and ok
    ok = check(error < 1e-4, f"FMPy's run (damping {damping}) follows the closed form within 1e-4 kg: {error:.2e}") and ok
    # The FMU keeps the scale's rules (its `check`, as `run` does): fmi2SetReal refuses.
    try:
        fmpy.simulate_fmu(path, fmi_type="CoSimulation", stop_time=0.1, start_values={"damping": -40.0})
        refused = False
    except Exception as e:  # FMPy raises its FMICallException for the refused call
        refused = "fmi2SetReal" in str(e)
    return check(refused, "the FMU refuses a negative damping (fmi2SetReal fails)") and ok


if __name__ == "__main__":
    kind, path = sys.argv[1], sys.argv[2]
    sys.exit(0 if {"results": results, "sweep": sweep, "fmu": fmu}[kind](path) else 1)
