#!/usr/bin/env python3
"""Reference results of airfilm.fmu and rotor.fmu in the FMI Cross-Check layout.

For each FMU, in modelDescriptions/reference/<model>/:
  <model>_in.csv   the input signals (time first),
  <model>.opt      StartTime, StopTime, StepSize, RelTol (as the FMI Cross-Check reads them),
  <model>_ref.csv  the outputs FMPy's simulate_fmu gives with those inputs and options,
  ReadMe.md        what the case is and how it was produced.
`cargo xtask fmus` packs these files into each FMU under documentation/reference/;
tests/python/test_reference_results.py simulates every packed FMU afresh and compares.

    python scripts/make_reference_results.py [--fmu-dir target/fmu]

Run it again when the physics changes on purpose (the test fails until then).
"""
from __future__ import annotations

import argparse
import math
import pathlib
import zipfile
import xml.etree.ElementTree as ET

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "modelDescriptions" / "reference"

# One case per FMU: (stop time [s], step [s], outputs recorded, start values).
AIRFILM_OUTPUTS = ["Fx", "Fy", "eps", "h_min", "p_max", "friction_torque", "power_loss"]
ROTOR_OUTPUTS = ["dx_C", "dy_C", "dx_T", "dy_T", "x_JC", "y_JC", "x_RC", "y_RC", "omega"]
CASES = {
    "airfilm": dict(stop=0.002, step=1e-5, outputs=AIRFILM_OUTPUTS,
                    start={"n_elem_phi": 8, "n_elem_z": 2}),
    "rotor": dict(stop=0.01, step=2e-5, outputs=ROTOR_OUTPUTS, start={}),
}
REL_TOL = 1e-4


def start_value(fmu: pathlib.Path, name: str) -> float:
    with zipfile.ZipFile(fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    for v in root.iter("ScalarVariable"):
        if v.get("name") == name:
            return float(v[0].get("start"))
    raise KeyError(name)


def airfilm_inputs(t: np.ndarray, fmu: pathlib.Path) -> dict[str, np.ndarray]:
    """A forward whirl of radius 0.3 C at 400 Hz about a journal 0.25 C below the centre, at
    1000 Hz rotor speed."""
    c = start_value(fmu, "C")
    e, w = 0.3 * c, 2 * math.pi * 400.0
    return {
        "dx": e * np.cos(w * t),
        "dy": -0.25 * c + e * np.sin(w * t),
        "vx": -e * w * np.sin(w * t),
        "vy": e * w * np.cos(w * t),
        "omega": np.full_like(t, 2 * math.pi * 1000.0),
    }


def rotor_inputs(t: np.ndarray, fmu: pathlib.Path) -> dict[str, np.ndarray]:
    """Film forces that carry the rotor's weight (each journal its static share), with a 200 Hz
    rotating force of 1 N at the compressor bearing."""
    m, g = start_value(fmu, "m"), start_value(fmu, "g")
    z_cm, z_c, z_t = (start_value(fmu, n) for n in ("z_cm", "z_JC", "z_JT"))
    f_c = m * g * (z_cm - z_t) / (z_c - z_t)
    f_t = m * g - f_c
    w = 2 * math.pi * 200.0
    return {
        "F_C_x": np.cos(w * t),
        "F_C_y": f_c + np.sin(w * t),
        "F_T_x": np.zeros_like(t),
        "F_T_y": np.full_like(t, f_t),
    }


INPUTS = {"airfilm": airfilm_inputs, "rotor": rotor_inputs}


def read_opt(path: pathlib.Path) -> dict[str, float]:
    out = {}
    for line in path.read_text().splitlines():
        if "," in line:
            k, v = line.split(",", 1)
            out[k.strip()] = float(v)
    return out


def read_csv(path: pathlib.Path) -> np.ndarray:
    """A CSV with a header row of names as a structured array (time first)."""
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="")


def simulate(fmu: pathlib.Path, folder: pathlib.Path, model: str) -> np.ndarray:
    """FMPy's simulate_fmu of `fmu` with the case in `folder` (inputs, options, the outputs the
    reference names): what the reference holds, and what the test compares it with."""
    import fmpy

    opt = read_opt(folder / f"{model}.opt")
    inputs = read_csv(folder / f"{model}_in.csv")
    ref_names = (folder / f"{model}_ref.csv").read_text().splitlines()[0].split(",")[1:] \
        if (folder / f"{model}_ref.csv").exists() else CASES[model]["outputs"]
    return fmpy.simulate_fmu(
        str(fmu),
        start_time=opt["StartTime"],
        stop_time=opt["StopTime"],
        step_size=opt["StepSize"],
        output_interval=opt["StepSize"],
        relative_tolerance=opt["RelTol"],
        start_values=CASES[model]["start"],
        input=inputs,
        output=ref_names,
    )


def write_csv(path: pathlib.Path, names: list[str], columns: list[np.ndarray]) -> None:
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for row in zip(*columns):
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def make(fmu_dir: pathlib.Path) -> None:
    for model, case in CASES.items():
        fmu = fmu_dir / f"{model}.fmu"
        folder = OUT / model
        folder.mkdir(parents=True, exist_ok=True)
        # Inputs sampled at every communication point (FMPy interpolates linearly in between).
        t = np.arange(round(case["stop"] / case["step"]) + 1) * case["step"]
        sig = INPUTS[model](t, fmu)
        write_csv(folder / f"{model}_in.csv", ["time", *sig], [t, *sig.values()])
        (folder / f"{model}.opt").write_text(
            f"StartTime, 0.0\nStopTime, {case['stop']!r}\nStepSize, {case['step']!r}\nRelTol, {REL_TOL!r}\n")
        ref = folder / f"{model}_ref.csv"
        if ref.exists():
            ref.unlink()
        r = simulate(fmu, folder, model)
        write_csv(ref, ["time", *case["outputs"]], [r["time"], *(r[n] for n in case["outputs"])])
        (folder / "ReadMe.md").write_text(
            f"# {model}.fmu reference results\n\n"
            f"FMI Cross-Check layout: `{model}_in.csv` (inputs), `{model}.opt` (start, stop, step, "
            f"relative tolerance), `{model}_ref.csv` (outputs at every communication point).\n\n"
            f"Produced by `scripts/make_reference_results.py` with FMPy's `simulate_fmu` "
            f"(step size = output interval = StepSize, inputs interpolated linearly between the "
            f"samples of `{model}_in.csv`, start values {case['start'] or 'the defaults'}); "
            f"`tests/python/test_reference_results.py` simulates the packed FMU afresh and compares.\n\n"
            + ("A forward whirl of radius 0.3 C at 400 Hz about a journal 0.25 C below the centre, "
               "rotor at 1000 Hz, coarse mesh 8x2.\n" if model == "airfilm" else
               "Film forces carrying the rotor's weight (each journal its static share) and a 1 N "
               "force rotating at 200 Hz at the compressor bearing; speed ramp of the defaults.\n"))
        print(f"{folder}: {len(t)} input rows, {len(r)} result rows")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu-dir", default=str(ROOT / "target" / "fmu"))
    make(pathlib.Path(ap.parse_args().fmu_dir))
