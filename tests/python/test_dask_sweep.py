"""scripts/dask_sweep.py on a LocalCluster: two tiny run-ups, the same table as `airring sweep`."""
import pathlib
import subprocess
import sys

from airring_bin import ROOT, airring_exe

STUDY = """
name = "dask_tiny"
[fixed]
preset = "path1"
stop = 0.005
macro_step = 20
mesh = "8x2"
fmu_dir = "{fmu}"
[[grid]]
clearance = 20
dh = 40
c = [500, 1000]
d = 50
"""


def table(path):
    """Rows without the wall-time column."""
    return [line.rsplit(",", 1)[0] for line in pathlib.Path(path).read_text().splitlines()]


def test_dask_local_cluster_matches_airring_sweep(tmp_path):
    exe = airring_exe()
    study = tmp_path / "tiny.toml"
    study.write_text(STUDY.format(fmu=ROOT / "target" / "fmu"))
    out = tmp_path / "dask"
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "dask_sweep.py"), str(study), "--out", str(out),
                        "--workers", "2", "--airring", exe], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "2 runs, 0 already completed, 2 to run" in r.stderr
    rows = table(out / "study.csv")
    assert len(rows) == 3 and all(",completed," in x for x in rows[1:]), rows
    assert rows[1].startswith("C20_dH40_c500_d50,path1,20,40,500,50,")
    assert (out / "bifurcation_map.svg").exists() and (out / "bifurcation_map.png").exists()

    # airring sweep on the same folder: everything already done (same layout, same flags).
    r = subprocess.run([exe, "sweep", str(study), "--out", str(out)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert "2 already completed, 0 to run" in r.stderr
    assert table(out / "study.csv") == rows

    # And airring sweep from scratch gives the same table.
    ref = tmp_path / "ref"
    r = subprocess.run([exe, "sweep", str(study), "--out", str(ref), "--jobs", "2"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    assert table(ref / "study.csv") == rows


def test_dask_sweep_rejects_a_bad_shard(tmp_path):
    study = tmp_path / "tiny.toml"
    study.write_text(STUDY.format(fmu=ROOT / "target" / "fmu"))
    for bad in ["0/2", "3/2", "x"]:
        r = subprocess.run([sys.executable, str(ROOT / "scripts" / "dask_sweep.py"), str(study), "--out",
                            str(tmp_path / "o"), "--shard", bad, "--airring", airring_exe()],
                           capture_output=True, text=True, timeout=60)
        assert r.returncode != 0 and "--shard expects k/n" in r.stderr, (bad, r.stderr)
