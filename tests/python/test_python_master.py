"""scripts/gauss_seidel.py (a Gauss-Seidel master on FMPy's FMU2Slave) against airring on the same FMUs.

The Python master reads the system file airring wrote into its run folder and repeats the algorithm
(order, extrapolation/interpolation polynomials as value + derivatives at T_N, initialization, grid
times), so the floating-point operations are the same and so are the results: the comparison finds
bit-identical time series. The asserted bound, 1e-12 of each column's largest magnitude, leaves room
only for a different libm in a future FMPy/Python build (both masters do nothing but +, -, *, / on the
coupling values; all the physics runs in the same FMU binaries).
"""
import pathlib
import sys

import numpy as np
import pytest

from airring_bin import ROOT, runup

sys.path.insert(0, str(ROOT / "scripts"))
import gauss_seidel  # noqa: E402

REL_BOUND = 1e-12


def load(path):
    header = pathlib.Path(path).read_text().splitlines()[0].split(",")
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def compare(run_dir, tmp_path):
    m = gauss_seidel.GaussSeidelMaster(run_dir / "system.toml", workdir=str(tmp_path))
    try:
        header, rows = m.run()
    finally:
        m.close()
    gauss_seidel.write_csv(tmp_path / "timeseries.csv", header, rows)
    h_rust, rust = load(run_dir / "timeseries.csv")
    h_py, py = load(tmp_path / "timeseries.csv")
    assert h_py == h_rust
    assert py.shape == rust.shape
    scale = np.maximum(np.max(np.abs(rust), axis=0), 1e-300)
    rel = np.max(np.abs(py - rust), axis=0) / scale
    return dict(zip(h_rust, rel)), rust, h_rust


@pytest.mark.parametrize(
    "flags",
    [
        # the default algorithm: Gauss-Seidel, rotor first, linear extrapolation and interpolation
        ["--stop", "0.004", "--macro-step", "10", "--output-interval", "10"],
        # quadratic polynomials (second input derivatives), from a higher speed
        ["--stop", "0.002", "--macro-step", "10", "--output-interval", "10", "--extrapolation-order", "2",
         "--interpolation-order", "2", "--f-max", "2000", "--t-ramp", "0.01"],
        # Jacobi with zero-order hold
        ["--stop", "0.002", "--macro-step", "10", "--output-interval", "20", "--jacobi",
         "--extrapolation-order", "0", "--mesh", "10x3"],
    ],
    ids=["gs-linear", "gs-quadratic", "jacobi-zoh"],
)
def test_python_master_matches_airring(flags, tmp_path):
    run_dir = runup(tmp_path / "rust", *flags)
    rel, rust, header = compare(run_dir, tmp_path)
    worst = max(rel.values())
    print(f"largest relative difference Python vs Rust master: {worst:.3g}")
    assert worst <= REL_BOUND, {k: v for k, v in rel.items() if v > REL_BOUND}
    # The run is not trivial: the journals move and the films carry the rotor.
    col = {h: i for i, h in enumerate(header)}
    assert np.ptp(rust[:, col["rotor.dy_C [m]"]]) > 1e-8
    assert np.max(np.abs(rust[:, col["film_C.Fy [N]"]])) > 0.1


def test_taylor_derivatives_match_polynomial_rs():
    p = lambda t: 3.0 - 2.0 * t + 0.7 * t * t  # noqa: E731
    pts = [(0.1, p(0.1)), (0.25, p(0.25)), (0.3, p(0.3))]
    for anchor in (0.3, 0.1, 0.25):
        d = gauss_seidel.taylor_derivatives(pts, anchor)
        assert abs(d[0] - (-2.0 + 1.4 * anchor)) < 1e-12 and abs(d[1] - 1.4) < 1e-9
    assert gauss_seidel.taylor_derivatives([(1.0, 2.0), (1.5, 3.0)], 1.5) == [2.0, 0.0]
