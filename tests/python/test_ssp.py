"""`airring export-ssp` writes a run-up system as an SSP 1.0 archive; FMPy's own SSP runner
(`fmpy.ssp.simulation.simulate_ssp`, through scripts/run_ssp.py) simulates it, and the result matches
`airring run` in its Jacobi mode with the same macro step and zero-order hold (extrapolation order 0).

FMPy's algorithm is that Jacobi scheme (scripts/run_ssp.py describes it) with two documented
differences, both at round-off level for this system:
- FMPy's first step feeds 0.0 to every input, airring the outputs at t = 0. Here those are exactly 0
  (rotor centred at rest at zero speed) except the film forces, 2e-31 N: the round-off of integrating
  the ambient pressure over the lobes;
- FMPy's communication points are a running sum t += h, airring's the products k h, so they differ in
  the last bits and the FMUs' internal steps end at times that differ by as much.
Measured: 2e-14 of each column's largest magnitude over 3 ms (300 steps). The asserted bound is
1e-12; another algorithm (first-order extrapolation) differs by more than 1e-6, as the second test shows.
"""
import pathlib
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssd

from airring_bin import ROOT, airring_exe, runup

sys.path.insert(0, str(ROOT / "scripts"))
import run_ssp  # noqa: E402

REL_BOUND = 1e-12
# 3 ms of the path-1 run-up ramped to 2000 Hz in 10 ms (600 Hz at the end), coarse film mesh.
FLAGS = ["--stop", "0.003", "--macro-step", "10", "--output-interval", "10", "--f-max", "2000", "--t-ramp", "0.01",
         "--mesh", "10x3", "--jacobi",
         # FMPy's runner steps with the fixed macro step: no coupling-error control on our side either.
         "--step-control", "off"]


def export(system, out):
    r = subprocess.run([airring_exe(), "export-ssp", str(system), "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return out


def relative_differences(run_dir, header, rows):
    """Per recorded column of airring's timeseries.csv: max |FMPy - airring| / max |airring|."""
    names = [h.split(" [")[0] for h in (run_dir / "timeseries.csv").read_text().splitlines()[0].split(",")]
    rust = np.loadtxt(run_dir / "timeseries.csv", delimiter=",", skiprows=1)
    py = np.array(rows)
    # FMPy's row k holds the values at t_(k+1); airring's row 0 is t = 0.
    n = len(rust) - 1
    assert len(py) >= n, (len(py), n)
    assert np.allclose(py[:n, 0], rust[1:, 0], rtol=1e-12, atol=0)
    col = {h: i for i, h in enumerate(header)}
    rel = {}
    for j, name in enumerate(names[1:], start=1):
        a, b = rust[1:, j], py[:n, col[name]]
        rel[name] = float(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300))
    return rel, rust, names


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ssp")
    run_dir = runup(tmp / "jacobi", *FLAGS, "--extrapolation-order", "0")
    ssp = export(run_dir / "system.toml", tmp / "runup.ssp")
    header, rows = run_ssp.simulate(str(ssp))
    return run_dir, ssp, header, rows, tmp


def test_fmpy_ssp_runner_matches_airring_jacobi(exported):
    run_dir, ssp, header, rows, _ = exported
    ssd = read_ssd(str(ssp))  # schema-valid SSP 1.0
    assert [c.name for c in ssd.system.elements] == ["rotor", "film_C", "film_T"]
    with zipfile.ZipFile(ssp) as z:
        assert sorted(z.namelist()) == ["SystemStructure.ssd", "resources/airfilm.fmu", "resources/rotor.fmu"]
        text = z.read("SystemStructure.ssd").decode()
    # Display units of the system file arrive in SI: C = "20 um", c_C = "1000 N/mm".
    assert '<ssv:Parameter name="C"><ssv:Real value="2e-5"/>' in text
    assert '<ssv:Parameter name="c_C"><ssv:Real value="1000000.0"/>' in text

    rel, rust, names = relative_differences(run_dir, header, rows)
    worst = max(rel.values())
    print(f"largest relative difference FMPy SSP runner vs airring Jacobi: {worst:.3g}")
    assert worst <= REL_BOUND, {k: v for k, v in rel.items() if v > REL_BOUND}
    # Not trivial: the journals drop and the films carry the rotor.
    col = {n: i for i, n in enumerate(names)}
    assert np.ptp(rust[:, col["rotor.dy_C"]]) > 1e-6
    assert np.max(np.abs(rust[:, col["film_C.Fy"]])) > 1.0


def test_the_comparison_sees_another_algorithm(exported):
    _, _, header, rows, tmp = exported
    other = runup(tmp / "jacobi-linear", *FLAGS, "--extrapolation-order", "1")
    rel, _, _ = relative_differences(other, header, rows)
    print("FMPy vs airring Jacobi with linear extrapolation:", rel["film_C.Fy"], rel["rotor.dy_C"])
    assert rel["film_C.Fy"] > 1e-6 and rel["rotor.dy_C"] > 1e-6, rel


def test_export_refuses_a_bad_connection_with_file_and_line(exported, tmp_path):
    run_dir = exported[0]
    text = (run_dir / "system.toml").read_text().replace('to = "film_C.dx"', 'to = "film_C.Fx"', 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    line = text.splitlines().index('to = "film_C.Fx"') + 1
    r = subprocess.run([airring_exe(), "export-ssp", str(bad), "--out", str(tmp_path / "x.ssp")],
                       capture_output=True, text=True)
    assert r.returncode != 0
    assert f"bad.toml:{line}: connection.to: 'film_C.Fx' is not an input" in r.stderr, r.stderr
    assert not pathlib.Path(tmp_path / "x.ssp").exists()


def test_boolean_and_integer_parameters_are_exported_typed(exported, tmp_path):
    """A Boolean goes into the SSD as "true"; run_ssp.py hands FMPy a Python bool (FMPy's own
    `value != 0.0` would turn the string "false" into true)."""
    run_dir = exported[0]
    # The generated file has one [fmu.parameters] table per instance; film_C's comes first.
    text = (run_dir / "system.toml").read_text().replace("n_elem_z = 3\n", "n_elem_z = 3\nstart_steady = true\n", 1)
    sysfile = tmp_path / "steady.toml"
    sysfile.write_text(text)
    ssp = export(sysfile, tmp_path / "steady.ssp")
    with zipfile.ZipFile(ssp) as z:
        ssd = z.read("SystemStructure.ssd").decode()
    assert '<ssv:Parameter name="start_steady"><ssv:Boolean value="true"/>' in ssd
    assert '<ssv:Parameter name="n_elem_phi"><ssv:Integer value="10"/>' in ssd
    params = {p.name: p.value for p in run_ssp.parameter_set(read_ssd(str(ssp))).parameters}
    assert params["film_C.start_steady"] is True and "film_T.start_steady" not in params and params["film_C.n_elem_phi"] == 10
