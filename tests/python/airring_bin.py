"""The `airring` executable for the Python tests: $AIRRING, else the newer of target/release/airring and target/debug/airring."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def airring_exe() -> str:
    """$AIRRING, else the most recently built of target/release/airring and target/debug/airring:
    `cargo xtask test` builds the debug one, and a release binary left from an earlier build must
    not be tested in its place (it would compare the packed FMUs with older library code)."""
    env = os.environ.get("AIRRING")
    if env:
        if pathlib.Path(env).exists():
            return env
        pytest.fail(f"AIRRING={env} does not exist")
    built = [c for c in (ROOT / "target" / "release" / "airring", ROOT / "target" / "debug" / "airring") if c.exists()]
    if built:
        return str(max(built, key=lambda c: c.stat().st_mtime))
    pytest.fail("airring not found: `cargo build --release -p master` (or set AIRRING=/path/to/airring)")


def runup(out, *args) -> pathlib.Path:
    """`airring runup ARGS --out OUT --quiet` with the FMUs of target/fmu; returns OUT."""
    cmd = [airring_exe(), "runup", *map(str, args), "--out", str(out), "--quiet", "--fmu-dir", str(ROOT / "target" / "fmu")]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    return pathlib.Path(out)
