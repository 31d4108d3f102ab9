#!/usr/bin/env python3
"""Simulate an SSP archive written by `airring export-ssp` with FMPy's own SSP runner.

    run_ssp.py SYSTEM.ssp [--stop S] [--step S] [--out result.csv]

Defaults: the stop time of the SSD's DefaultExperiment and the macro step of its
`org.airring.algorithm` annotation.

What FMPy 0.3.32's `fmpy.ssp.simulation.simulate_ssp` does (read from its source), and what this
script adds:
- it instantiates every component, calls fmi2SetupExperiment(startTime) without a stop time, sets the
  `parameter_set` it is *given* (it ignores the SSD's ParameterBindings), and enters and leaves
  initialization mode at once, with the inputs at their start values;
- every connector value starts at 0.0; each step sets every component's inputs to the connector values,
  steps the components one after the other in document order (fmi2DoStep(t, h), no input derivatives),
  reads their outputs, and only then copies outputs to inputs: a Jacobi scheme with zero-order hold;
  the first step therefore sees 0.0 on every input, not the outputs at t = 0;
- time advances as a running sum t += h while t < stop (so one extra step may occur), and a result row
  is labelled with the time at the *start* of the step that produced its values;
- Boolean parameters go through `value != 0.0`, so the string "false" would set true.
This script passes the SSD's inline ParameterBindings to simulate_ssp as that parameter set (Python
bool/int/float values, which avoids the Boolean pitfall) and labels each row with the time at the end
of its step (t + h, computed as FMPy computes its next t).
"""
from __future__ import annotations

import argparse
import sys
import zipfile
import xml.etree.ElementTree as ET

from fmpy.ssp.ssd import Parameter, ParameterSet, read_ssd
from fmpy.ssp.simulation import simulate_ssp

NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
}


def parameter_set(ssd) -> ParameterSet:
    """The components' inline parameter bindings as one set with hierarchical names ("film_C.C")."""
    out = ParameterSet(name="bindings")
    for comp in ssd.system.elements:
        for binding in getattr(comp, "parameterBindings", []):
            for ps in binding.parameterValues:
                for p in ps.parameters:
                    if p.type == "Real":
                        value = float(p.value)
                    elif p.type == "Integer":
                        value = int(p.value)
                    elif p.type == "Boolean":
                        value = p.value.strip() in ("true", "1")
                    else:
                        raise SystemExit(f"{comp.name}.{p.name}: {p.type} parameters are not supported")
                    out.parameters.append(Parameter(name=f"{comp.name}.{p.name}", type=p.type, value=value))
    return out


def experiment(ssp) -> tuple[float | None, float | None]:
    """(stop time, macro step) from DefaultExperiment and the airring annotation, if present."""
    with zipfile.ZipFile(ssp) as z:
        root = ET.fromstring(z.read("SystemStructure.ssd"))
    stop = step = None
    de = root.find("ssd:DefaultExperiment", NS)
    if de is not None and de.get("stopTime"):
        stop = float(de.get("stopTime"))
    for a in root.iterfind("ssd:System/ssd:Annotations/ssc:Annotation", NS):
        if a.get("type") == "org.airring.algorithm":
            alg = a.find("Algorithm")
            if alg is not None and alg.get("macroStep"):
                step = float(alg.get("macroStep"))
    return stop, step


def simulate(ssp, stop: float | None = None, step: float | None = None):
    """Runs FMPy's SSP runner; returns (header, rows) with "time" first, times at the step ends."""
    default_stop, default_step = experiment(ssp)
    stop = stop if stop is not None else default_stop
    step = step if step is not None else default_step
    if stop is None or step is None:
        raise SystemExit("no stop time / step in the SSP: pass --stop and --step")
    ssd = read_ssd(ssp)  # validates against the SSP 1.0 schema
    result = simulate_ssp(ssp, stop_time=stop, step_size=step, parameter_set=parameter_set(ssd))
    names = list(result.dtype.names)
    header = ["time"] + names[1:]
    rows = [[float(r[0]) + step] + [float(x) for x in list(r)[1:]] for r in result]
    return header, rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("ssp")
    ap.add_argument("--stop", type=float, help="stop time [s]")
    ap.add_argument("--step", type=float, help="macro step [s]")
    ap.add_argument("--out", help="result CSV (default: SSP name + .csv)")
    a = ap.parse_args(argv)
    header, rows = simulate(a.ssp, a.stop, a.step)
    out = a.out or a.ssp.rsplit(".", 1)[0] + ".csv"
    with open(out, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(repr(x) for x in r) + "\n")
    print(f"{len(rows)} steps -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
