"""The reference results packed in each FMU (FMI 2.0 and its FMI 3.0 twin) (documentation/reference/, FMI Cross-Check layout:
<model>_in.csv, <model>.opt, <model>_ref.csv, ReadMe.md, written by
scripts/make_reference_results.py) equal a fresh FMPy simulation of that FMU with those inputs and
options."""
import pathlib
import sys
import zipfile

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import make_reference_results as mrr  # noqa: E402


@pytest.mark.parametrize("version", ["", "fmi3"])
@pytest.mark.parametrize("model", ["airfilm", "rotor"])
def test_packed_reference_results_match_a_fresh_simulation(model, version, tmp_path):
    # The FMI 3.0 twins carry the FMI 2.0 FMUs' reference results: the same model gives FMPy the
    # same numbers through either interface.
    fmu = ROOT / "target" / "fmu" / version / f"{model}.fmu"
    if not fmu.exists():
        pytest.fail(f"{fmu} is missing: run `cargo xtask fmus` first")
    with zipfile.ZipFile(fmu) as z:
        names = [n for n in z.namelist() if n.startswith("documentation/reference/")]
        for suffix in ["_in.csv", ".opt", "_ref.csv"]:
            assert f"documentation/reference/{model}{suffix}" in names, names
        assert "documentation/reference/ReadMe.md" in names
        for n in names:
            (tmp_path / pathlib.Path(n).name).write_bytes(z.read(n))
    ref = mrr.read_csv(tmp_path / f"{model}_ref.csv")
    fresh = mrr.simulate(fmu, tmp_path, model)
    assert len(fresh) == len(ref)
    assert np.array_equal(fresh["time"], ref["time"])
    for name in ref.dtype.names[1:]:
        scale = max(np.max(np.abs(ref[name])), 1e-300)
        # The same FMU and inputs: equal to round-off (1e-9 of the column's range allows for
        # another machine's libm).
        assert np.max(np.abs(fresh[name] - ref[name])) <= 1e-9 * scale, name
    # The reference is not trivial: every output moves.
    for name in ref.dtype.names[1:]:
        assert np.ptp(ref[name]) > 0.0, name
