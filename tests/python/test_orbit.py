"""FMPy's own master (`fmpy.simulate_fmu`) drives airfilm.fmu alone along a prescribed journal orbit
from a CSV file; `airring orbit` drives the air-film library (no FMI) along the same file with the
input treatment of FMPy 0.3.32's simulateCS (see master/src/film_orbit.rs).

Both run the same floating-point operations (the same linear interpolation of the table at the same
communication points, the same film code), so the forces agree to the last bit: the measured
difference is 0. The asserted bound, 1e-12 of the largest force, is round-off level on purpose: a
different input treatment (another interpolation, inputs set after instead of before the step,
derivatives on or off) moves the forces by about 2 % of their size, as the third test shows.
"""
import ctypes
import pathlib
import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.util import read_csv
import fmpy.simulation

from airring_bin import ROOT, airring_exe
from conftest import fmu_path

REL_BOUND = 1e-12
OUTPUTS = ["Fx", "Fy", "eps", "h_min", "p_max", "F_contact"]
STOP_S = 5e-3
STEP_S = 1e-5


def write_orbit(path, clearance_m=20e-6, eps=0.3, whirl_hz=400.0, speed_hz=1000.0, sample_s=25e-6):
    """Circular forward whirl of the journal; samples every 25 us (between communication points, so
    the interpolation matters)."""
    e, w = eps * clearance_m, 2 * np.pi * whirl_hz
    t = np.arange(int(round(STOP_S / sample_s)) + 1) * sample_s
    c, s = np.cos(w * t), np.sin(w * t)
    cols = [t, e * c, e * s, -e * w * s, e * w * c, np.full_like(t, 2 * np.pi * speed_hz)]
    with open(path, "w") as f:
        f.write("time,dx,dy,vx,vy,omega\n")
        for row in zip(*cols):
            f.write(",".join(repr(float(x)) for x in row) + "\n")
    return path


def airring_orbit(orbit, out, *args):
    cmd = [airring_exe(), "orbit", "--input", str(orbit), "--out", str(out), "--stop", str(STOP_S), "--step", "10", *args]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    return np.loadtxt(out, delimiter=",", skiprows=1)


def fmpy_orbit(orbit, start_values, set_input_derivatives=False):
    return simulate_fmu(fmu_path("airfilm"), start_time=0.0, stop_time=STOP_S, output_interval=STEP_S,
                        input=read_csv(orbit), output=OUTPUTS, start_values=start_values,
                        set_input_derivatives=set_input_derivatives)


@pytest.fixture
def sized_derivative_buffer(monkeypatch):
    """FMPy 0.3.32's Input allocates the derivative buffer for exactly 9 inputs (`(value_type * 9)()`),
    so `set_input_derivatives=True` raises "ValueError: Can only assign sequence of same size" for
    airfilm.fmu's 5 inputs. This resizes that buffer and changes nothing else."""
    original = fmpy.simulation.Input.__init__

    def init(self, *args, **kwargs):
        original(self, *args, **kwargs)
        if getattr(self, "continuous", None):
            self.continuous = [c._replace(derivatives=(ctypes.c_double * len(c.vrs))()) for c in self.continuous]

    monkeypatch.setattr(fmpy.simulation.Input, "__init__", init)


def compare(rust, py):
    assert rust.shape == (len(py), 1 + len(OUTPUTS))
    assert np.array_equal(rust[:, 0], py["time"]), "different communication points"
    rel = {}
    for k, name in enumerate(OUTPUTS):
        scale = max(np.max(np.abs(rust[:, k + 1])), 1e-300)
        rel[name] = float(np.max(np.abs(py[name] - rust[:, k + 1])) / scale)
    return rel


def test_simulate_fmu_orbit_matches_library(tmp_path):
    orbit = write_orbit(tmp_path / "orbit.csv")
    rust = airring_orbit(orbit, tmp_path / "forces.csv")
    py = fmpy_orbit(orbit, start_values={})
    rel = compare(rust, py)
    print("largest relative difference FMPy/airfilm.fmu vs library:", rel)
    assert max(rel.values()) <= REL_BOUND, rel
    # Not trivial: the whirling journal at 1000 Hz carries several newtons.
    assert np.max(np.hypot(rust[:, 1], rust[:, 2])) > 3.0
    assert abs(np.max(rust[:, 3]) - 0.3) < 1e-9


def test_with_input_derivatives_and_parameters(tmp_path, sized_derivative_buffer):
    orbit = write_orbit(tmp_path / "orbit.csv", clearance_m=25e-6)
    rust = airring_orbit(orbit, tmp_path / "forces.csv", "--input-derivatives",
                         "--param", "C=25 um", "--param", "start_steady=true", "--param", "n_elem_phi=16")
    py = fmpy_orbit(orbit, {"C": 25e-6, "start_steady": True, "n_elem_phi": 16}, set_input_derivatives=True)
    rel = compare(rust, py)
    print("largest relative difference with input derivatives:", rel)
    assert max(rel.values()) <= REL_BOUND, rel
    # start_steady: the film carries the journal from the first step on.
    assert np.hypot(rust[0, 1], rust[0, 2]) > 1.0


def test_the_comparison_sees_a_different_input_treatment(tmp_path):
    """Derivatives on (library) against off (FMU): the bound above must catch such a difference."""
    orbit = write_orbit(tmp_path / "orbit.csv")
    rust = airring_orbit(orbit, tmp_path / "forces.csv", "--input-derivatives")
    py = fmpy_orbit(orbit, start_values={})
    rel = compare(rust, py)
    print("derivatives on vs off:", rel)
    assert min(rel["Fx"], rel["Fy"]) > 1e4 * REL_BOUND, rel


def test_bad_input_is_refused_with_the_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("time,dx,dy,vx,vy,omega\n0,0,0,0,0,0\n1e-5,0,0,0,0,0\n1e-5,1e-6,0,0,0,0\n")
    r = subprocess.run([airring_exe(), "orbit", "--input", str(bad), "--out", str(tmp_path / "o.csv")],
                       capture_output=True, text=True)
    assert r.returncode != 0
    assert "bad.csv:4: time 0.00001 s does not increase strictly" in r.stderr, r.stderr
    assert not pathlib.Path(tmp_path / "o.csv").exists()
