#!/usr/bin/env python3
"""Run any of our FMUs (airfilm.fmu, rotor.fmu, oscillator.fmu) through FMPy from the command line.

    run_fmu.py FMU [--info] [--stop 0.01] [--step 1e-5] [--output-interval 1e-4]
               [--set "C=15 um" --set n_elem_phi=20 ...] [--input orbit.csv] [--out result.csv]
               [--vars Fx,Fy,eps]

--set takes SI numbers or "number unit" with any display unit the FMU declares (um, N/mm, g, Hz, ...).
--input is a CSV with a `time` column and one column per input variable (FMPy interpolates it; for the air
film e.g. time,dx,dy,vx,vy,omega). The result is written as CSV (time first), default FMU_NAME.csv.
"""
from __future__ import annotations

import argparse
import sys

import numpy as np
from fmpy import dump, read_model_description, simulate_fmu


def to_si(md, name: str, text: str):
    v = next((x for x in md.modelVariables if x.name == name), None)
    if v is None:
        raise SystemExit(f"the FMU has no variable '{name}'")
    if v.type == "Boolean":
        return text.strip().lower() in ("1", "true", "yes")
    if v.type == "Integer":
        return int(text)
    parts = text.split(None, 1)
    num = float(parts[0])
    if len(parts) == 1:
        return num
    unit = parts[1].strip()
    base = v.unit or (v.declaredType.unit if v.declaredType is not None else None)
    if unit == base:
        return num
    for u in md.unitDefinitions:
        if u.name == base:
            for d in u.displayUnits:
                if d.name == unit:
                    return (num - d.offset) / d.factor
    raise SystemExit(f"unit '{unit}' does not fit '{name}' [{base}]")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("fmu")
    ap.add_argument("--info", action="store_true", help="print the variables and exit")
    ap.add_argument("--stop", type=float, default=0.01, help="stop time [s]")
    ap.add_argument("--step", type=float, help="communication step [s] (default: FMPy's)")
    ap.add_argument("--output-interval", type=float, help="output interval [s] (default: the step)")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="start/parameter value")
    ap.add_argument("--input", help="CSV with a time column and input columns")
    ap.add_argument("--vars", help="comma-separated outputs to record (default: all outputs)")
    ap.add_argument("--out", help="result CSV")
    a = ap.parse_args(argv)
    if a.info:
        dump(a.fmu)
        return 0
    md = read_model_description(a.fmu)
    start = {}
    for s in a.set:
        name, _, value = s.partition("=")
        start[name.strip()] = to_si(md, name.strip(), value)
    inp = None
    if a.input:
        inp = np.genfromtxt(a.input, delimiter=",", names=True)
    res = simulate_fmu(a.fmu, fmi_type="CoSimulation", stop_time=a.stop, step_size=a.step,
                       output_interval=a.output_interval or a.step, start_values=start, input=inp,
                       output=a.vars.split(",") if a.vars else None)
    out = a.out or f"{md.modelName}.csv"
    names = res.dtype.names
    np.savetxt(out, np.column_stack([res[n] for n in names]), delimiter=",", header=",".join(names),
               comments="", fmt="%.17g")
    print(f"{len(res)} rows, t = {res['time'][0]} .. {res['time'][-1]} s -> {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
