#!/usr/bin/env python3
"""A Gauss-Seidel co-simulation master on FMPy's low-level FMU2Slave, with the same algorithm as `airring`.

It reads an airring system file (e.g. the `system.toml` that `airring runup` writes into its run folder)
and reproduces master/src/cosim/{setup,gauss_seidel,polynomial}.rs and master/src/run/mod.rs step for step:

* set-up: every [[fmu]] is extracted and instantiated under its instance name, setupExperiment(0, stop),
  enterInitializationMode, parameters set in name order (a "number unit" string is converted to SI
  through the FMU's declared display units: si = (number - offset) / factor);
* connections in file order; a source's coupling outputs get slots in order of first use;
* initialization: two passes over the subsystems in `algorithm.order`, each setting its inputs from its
  sources' current outputs; then exitInitializationMode for all, and the coupling outputs at t = 0 are
  the first macro point of each history (at most 3 points kept);
* the macro step [T_N, T_N+1] (grid times T_N+1 = (N+1) H, step size T_N+1 - T_N): subsystems in order,
  consecutive subsystems that do not feed each other form a group (the two films). An input whose source
  has not stepped yet is *extrapolated* through the source's last k+1 macro points (k =
  extrapolation_order); an input whose source already stepped is *interpolated* through its last
  k+1 points (T_N+1, T_N, T_N-1; k = interpolation_order). The Lagrange polynomial goes to the FMU as
  value at T_N (fmi2SetReal) and derivatives at T_N (fmi2SetRealInputDerivatives), computed with the
  same divided differences (same floating-point operations) as polynomial.rs;
* Jacobi (`kind = "jacobi"`): one group, everything extrapolated;
* output samples k * interval recorded at the first macro point t >= k * interval - 1e-9 H.

Not reproduced: the roll-back on fmi2Discard (a discard stops this master with an error; the Rust master
would retry in halves) and checkpoints. The films of a group are stepped one after the other here,
in parallel threads in airring: they are independent instances, so the results are the same.

Usage: gauss_seidel.py SYSTEM.toml [--out DIR] [--stop SECONDS]
Writes DIR/timeseries.csv in airring's format (time [s], then "instance.variable [unit]" columns).
"""
from __future__ import annotations

import argparse
import pathlib
import sys
import tempfile
import tomllib
from dataclasses import dataclass, field

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

TIME_UNITS = {"s": 1.0, "": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}


def split_quantity(s: str) -> tuple[float, str]:
    s = s.strip()
    parts = s.split(None, 1)
    return float(parts[0]), (parts[1].strip() if len(parts) > 1 else "")


def seconds(v) -> float:
    if isinstance(v, bool):
        raise ValueError(f"expected a time, found {v!r}")
    if isinstance(v, (int, float)):
        return float(v)
    num, unit = split_quantity(v)
    return num * TIME_UNITS[unit]


def taylor_derivatives(points: list[tuple[float, float]], anchor: float) -> list[float]:
    """Derivatives 1 and 2 at `anchor` of the polynomial through `points` (polynomial.rs, same operations)."""
    if len(points) <= 1:
        return [0.0, 0.0]
    if len(points) == 2:
        (t0, u0), (t1, u1) = points
        return [(u1 - u0) / (t1 - t0), 0.0]
    (t0, u0), (t1, u1), (t2, u2) = points[:3]
    a = (u1 - u0) / (t1 - t0)
    a12 = (u2 - u1) / (t2 - t1)
    b = (a12 - a) / (t2 - t0)
    return [a + b * (2.0 * anchor - t0 - t1), 2.0 * b]


def taylor_value(u0: float, d: list[float], s: float) -> float:
    return u0 + s * (d[0] + s * d[1] / 2.0)


def var_unit(md, v) -> str | None:
    if v.unit:
        return v.unit
    if v.declaredType is not None and getattr(v.declaredType, "unit", None):
        return v.declaredType.unit
    return None


def to_si(md, v, num: float, unit: str) -> float:
    if unit == "":
        return num
    base = var_unit(md, v)
    if base is None:
        raise ValueError(f"'{v.name}' has no unit, cannot convert '{unit}'")
    if unit == base:
        return (num - 0.0) / 1.0
    for u in md.unitDefinitions:
        if u.name == base:
            for d in u.displayUnits:
                if d.name == unit:
                    return (num - d.offset) / d.factor
    raise ValueError(f"unit '{unit}' does not fit '{v.name}' [{base}]")


@dataclass
class Link:
    to_vr: int
    source: int
    slot: int


@dataclass
class Sub:
    name: str
    slave: FMU2Slave
    md: object
    can_interpolate: bool
    inputs: list[Link] = field(default_factory=list)
    coupling_vrs: list[int] = field(default_factory=list)
    history: list[tuple[float, list[float]]] = field(default_factory=list)

    def slot(self, vr: int) -> int:
        if vr not in self.coupling_vrs:
            self.coupling_vrs.append(vr)
        return self.coupling_vrs.index(vr)

    def read_coupling(self) -> list[float]:
        return list(self.slave.getReal(self.coupling_vrs))

    def push(self, t: float, v: list[float]) -> None:
        if len(self.history) == 3:
            self.history.pop(0)
        self.history.append((t, v))


class GaussSeidelMaster:
    def __init__(self, system_path, stop_time: float | None = None, workdir: str | None = None):
        system_path = pathlib.Path(system_path)
        with open(system_path, "rb") as f:
            self.sys = tomllib.load(f)
        base = system_path.parent
        alg = self.sys["algorithm"]
        self.h = seconds(alg["macro_step"])
        self.stop = seconds(alg["stop_time"]) if stop_time is None else float(stop_time)
        out = self.sys.get("output", {})
        self.interval = seconds(out["interval"]) if "interval" in out else self.h * 10.0
        self.jacobi = alg.get("kind", "gauss-seidel") == "jacobi"
        if alg.get("kind", "gauss-seidel") not in ("gauss-seidel", "jacobi"):
            raise ValueError(f"unknown algorithm kind {alg['kind']!r}")
        self.extrap = int(alg.get("extrapolation_order", 1))
        self.interp = int(alg.get("interpolation_order", 1))
        self._tmp = tempfile.TemporaryDirectory(dir=workdir)

        self.subs: list[Sub] = []
        for k, e in enumerate(self.sys["fmu"]):
            path = pathlib.Path(e["path"])
            if not path.is_absolute():
                path = base / path
            md = read_model_description(str(path))
            unzip = extract(str(path), unzipdir=str(pathlib.Path(self._tmp.name) / f"{k}_{e['name']}"))
            slave = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                              modelIdentifier=md.coSimulation.modelIdentifier, instanceName=e["name"])
            slave.instantiate(visible=False, loggingOn=False)
            slave.setupExperiment(startTime=0.0, stopTime=self.stop)
            slave.enterInitializationMode()
            variables = {v.name: v for v in md.modelVariables}
            for pname in sorted(e.get("parameters", {})):
                value = e["parameters"][pname]
                v = variables[pname]
                if v.type == "Boolean":
                    slave.setBoolean([v.valueReference], [bool(value)])
                elif v.type == "Integer":
                    slave.setInteger([v.valueReference], [int(value)])
                else:
                    if isinstance(value, str):
                        si = to_si(md, v, *split_quantity(value))
                    else:
                        si = float(value)
                    slave.setReal([v.valueReference], [si])
            self.subs.append(Sub(e["name"], slave, md, bool(md.coSimulation.canInterpolateInputs)))

        names = [s.name for s in self.subs]

        def port(p: str) -> tuple[int, int]:
            inst, var = p.split(".", 1)
            i = names.index(inst)
            v = next(x for x in self.subs[i].md.modelVariables if x.name == var)
            return i, v.valueReference

        links = []
        for c in self.sys.get("connection", []):
            si, svr = port(c["from"])
            di, dvr = port(c["to"])
            links.append((di, Link(dvr, si, self.subs[si].slot(svr))))
        for di, l in links:
            self.subs[di].inputs.append(l)

        order = [names.index(n) for n in alg["order"]] if "order" in alg else list(range(len(self.subs)))
        if self.jacobi:
            self.groups = [order]
        else:
            self.groups = []
            for i in order:
                last = self.groups[-1] if self.groups else None
                if last is not None and not any(l.source in last for l in self.subs[i].inputs):
                    last.append(i)
                else:
                    self.groups.append([i])

        self.recorded = []
        for name in out.get("variables", []):
            i, vr = port(name)
            inst, var = name.split(".", 1)
            v = next(x for x in self.subs[i].md.modelVariables if x.name == var)
            self.recorded.append((i, vr, name, var_unit(self.subs[i].md, v) or ""))

        # Initialization: settle the inputs in order, twice.
        for _ in range(2):
            for i in order:
                s = self.subs[i]
                vrs, vals = [], []
                for l in s.inputs:
                    src = self.subs[l.source]
                    vrs.append(l.to_vr)
                    vals.append(src.slave.getReal([src.coupling_vrs[l.slot]])[0])
                if vrs:
                    s.slave.setReal(vrs, vals)
        for s in self.subs:
            s.slave.exitInitializationMode()
            s.push(0.0, s.read_coupling())
        self.t = 0.0

    def set_inputs(self, i: int, t: float, h: float, stepped: list[bool]) -> None:
        s = self.subs[i]
        vrs, values, der_vrs, orders, der_values = [], [], [], [], []
        for l in s.inputs:
            hist = self.subs[l.source].history
            n = len(hist)
            if stepped[l.source]:
                anchor_idx, order = n - 2, self.interp
            else:
                anchor_idx, order = n - 1, self.extrap
            used = min(order + 1, n)
            pts = [(p[0], p[1][l.slot]) for p in hist[n - used:]]
            u0 = hist[anchor_idx][1][l.slot]
            assert hist[anchor_idx][0] == t
            d = taylor_derivatives(pts, t)
            vrs.append(l.to_vr)
            if s.can_interpolate:
                values.append(u0)
                for k in range(used - 1):
                    der_vrs.append(l.to_vr)
                    orders.append(k + 1)
                    der_values.append(d[k])
            else:
                values.append(taylor_value(u0, d, h / 2.0))
        s.slave.setReal(vrs, values)
        if der_vrs:
            s.slave.setRealInputDerivatives(der_vrs, orders, der_values)

    def step(self, h: float) -> None:
        t = self.t
        stepped = [False] * len(self.subs)
        for group in self.groups:
            for i in group:
                self.set_inputs(i, t, h, stepped)
            for i in group:
                status = self.subs[i].slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
                if status not in (0, None):
                    raise RuntimeError(f"{self.subs[i].name}: fmi2DoStep returned {status} at t = {t} s")
            for i in group:
                self.subs[i].push(t + h, self.subs[i].read_coupling())
                stepped[i] = True
        self.t = t + h

    def record(self) -> list[float]:
        return [self.subs[i].slave.getReal([vr])[0] for i, vr, _, _ in self.recorded]

    def run(self, progress: bool = False) -> tuple[list[str], list[list[float]]]:
        """Runs to the stop time; returns the header and the output rows (time first)."""
        n_steps = round(self.stop / self.h)
        header = ["time [s]"] + [f"{n} [{u or '1'}]" for _, _, n, u in self.recorded]
        rows = []
        k_out = 0
        step_index = 0
        while True:
            t = self.t
            while k_out * self.interval <= t + 1e-9 * self.h:
                rows.append([t] + self.record())
                k_out += 1
            if step_index >= n_steps:
                break
            target = (step_index + 1) * self.h
            self.step(target - t)
            step_index += 1
            if progress and step_index % 1000 == 0:
                print(f"t = {self.t:.4f} s / {self.stop} s", file=sys.stderr)
        return header, rows

    def close(self) -> None:
        for s in self.subs:
            try:
                s.slave.terminate()
                s.slave.freeInstance()
            except Exception:  # noqa: BLE001 - best effort on the way out
                pass
        self._tmp.cleanup()


def write_csv(path, header, rows) -> None:
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(repr(float(x)) for x in r) + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("system", help="airring system file (TOML), e.g. RUN/system.toml")
    ap.add_argument("--out", default=".", help="output folder for timeseries.csv")
    ap.add_argument("--stop", type=float, help="stop time [s] (default: the system file's)")
    ap.add_argument("--progress", action="store_true")
    a = ap.parse_args(argv)
    m = GaussSeidelMaster(a.system, a.stop)
    try:
        header, rows = m.run(progress=a.progress)
    finally:
        m.close()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out / "timeseries.csv", header, rows)
    print(f"{len(rows)} samples to t = {rows[-1][0]} s -> {out / 'timeseries.csv'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
