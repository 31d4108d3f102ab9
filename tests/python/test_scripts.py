"""scripts/plot_run.py on a tiny run and scripts/run_fmu.py on the packed FMUs."""
import subprocess
import sys

import numpy as np

from airring_bin import ROOT, runup
from conftest import fmu_path


def test_plot_run_on_a_tiny_runup(tmp_path):
    run = runup(tmp_path / "run", "--stop", "0.005", "--macro-step", "20", "--mesh", "8x2")
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "plot_run.py"), str(run)], capture_output=True,
                       text=True, env={"MPLBACKEND": "Agg", "PATH": "/usr/bin:/bin"}, timeout=120)
    assert r.returncode == 0, r.stderr
    for stem in ("eps", "orbits", "journal_y", "forces"):
        for ext in ("pdf", "png"):
            p = run / "plots" / f"{stem}.{ext}"
            assert p.exists() and p.stat().st_size > 5000, p
    assert (run / "plots" / "eps.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_run_fmu_oscillator_and_units(tmp_path):
    out = tmp_path / "osc.csv"
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "run_fmu.py"), fmu_path("oscillator"), "--stop", "1",
                        "--step", "0.01", "--set", "F=2", "--set", "x0=0", "--out", str(out)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    w = 2 * np.pi
    assert np.max(np.abs(data["x"] - 2.0 / w**2 * (1 - np.cos(w * data["time"])))) < 1e-12


def test_run_fmu_airfilm_with_display_units(tmp_path):
    out = tmp_path / "film.csv"
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "run_fmu.py"), fmu_path("airfilm"), "--stop", "0.001",
                        "--step", "1e-5", "--output-interval", "1e-4", "--set", "C=15 um", "--set", "n_elem_phi=8",
                        "--set", "n_elem_z=2", "--set", "omega=3000", "--set", "dy=-5 um", "--vars", "Fx,Fy,eps",
                        "--out", str(out)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data.dtype.names == ("time", "Fx", "Fy", "eps")
    # eps = |d| / C with dy = -5 um and C = 15 um: the unit conversion reached the FMU.
    assert abs(data["eps"][-1] - 5.0 / 15.0) < 1e-9
    assert data["Fy"][-1] > 0.0  # the film pushes the journal back up
