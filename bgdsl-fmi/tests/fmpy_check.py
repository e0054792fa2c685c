"""Checks bgdsl FMUs with FMPy, an FMI importer written by others.

Run by `bgdsl-fmi/tests/fmpy.rs` as `python3 fmpy_check.py CONFIG.json`. The config
(written by the Rust test) lists:

- "validate": FMU files for `fmpy.validation.validate_fmu`; every problem it reports
  is printed as `PROBLEM <fmu>: <text>` and fails the check;
- "runs": simulations, each {"fmu", "fmi_type" ("ModelExchange" or "CoSimulation"),
  "stop_time", "output_interval", "relative_tolerance" (or null), "start_values"
  {name: value}, "outputs" [names], "csv"}; each result is written to "csv" as
  `time,<outputs...>` with every number in Python's round-trip `repr`;
- "misuse": FMU files whose Co-Simulation interface is called wrongly on purpose
  (an unknown value reference, a step before initialisation, setting an output, a
  step from the wrong time): each call must raise FMPy's `FMICallException` with
  status fmi2Error, the FMU's logger must have said why, and the instance must go on
  working afterwards.

Prints one line per check and exits with status 1 if any failed.
"""

import csv
import json
import shutil
import sys

import fmpy
from fmpy import read_model_description, extract
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2Error,
)
from fmpy.validation import validate_fmu


def validate(path):
    problems = validate_fmu(path)
    for problem in problems:
        print(f"PROBLEM {path}: {problem}")
    if not problems:
        print(f"VALID {path}")
    return not problems


def simulate(run):
    result = fmpy.simulate_fmu(
        run["fmu"],
        fmi_type=run["fmi_type"],
        solver="CVode",
        start_time=0.0,
        stop_time=run["stop_time"],
        output_interval=run["output_interval"],
        relative_tolerance=run["relative_tolerance"],
        start_values=run["start_values"],
        output=run["outputs"],
        validate=True,
    )
    names = ["time"] + run["outputs"]
    with open(run["csv"], "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(names)
        for row in result:
            writer.writerow([repr(float(row[name])) for name in names])
    print(f"SIMULATED {run['fmi_type']} {run['fmu']} -> {run['csv']} ({len(result)} rows)")
    return True


def misuse(path):
    """Calls the FMU wrongly through FMPy's own bindings and checks each call fails
    with fmi2Error and a logged reason."""
    messages = []

    def logger(env, instance_name, status, category, message):
        messages.append((status, category.decode(), message.decode()))

    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(logger)
    md = read_model_description(path)
    directory = extract(path)
    ok = True
    try:
        fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=directory,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="misuse",
        )
        fmu.instantiate(callbacks=callbacks)
        vrs = {v.name: v.valueReference for v in md.modelVariables}
        outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        bad_vr = max(vrs.values()) + 1000

        def expect_error(what, call, needle):
            nonlocal ok
            before = len(messages)
            try:
                call()
            except FMICallException as e:
                said = [m for (_, _, m) in messages[before:]]
                if e.status == fmi2Error and any(needle in m for m in said):
                    print(f"REFUSED {path}: {what}: {said[-1]}")
                    return
                print(f"FAILED {path}: {what}: status {e.status}, messages {said}")
                ok = False
                return
            print(f"FAILED {path}: {what}: the call succeeded")
            ok = False

        expect_error("step before initialisation", lambda: fmu.doStep(0.0, 0.1), "fmi2DoStep")
        expect_error(
            "setting an output",
            lambda: fmu.setReal([vrs[outputs[0]]], [1.0]),
            outputs[0],
        )
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmu.doStep(0.0, 0.01)
        expect_error("unknown value reference", lambda: fmu.getReal([bad_vr]), str(bad_vr))
        expect_error(
            "step from the wrong time",
            lambda: fmu.doStep(0.5, 0.01),
            "currentCommunicationPoint",
        )
        fmu.doStep(0.01, 0.01)  # still usable after the refused calls
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(directory, ignore_errors=True)
    return ok


def main():
    with open(sys.argv[1]) as f:
        config = json.load(f)
    print(f"FMPY {fmpy.__version__}")
    ok = True
    for path in config["validate"]:
        ok &= validate(path)
    for run in config["runs"]:
        ok &= simulate(run)
    for path in config["misuse"]:
        ok &= misuse(path)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
