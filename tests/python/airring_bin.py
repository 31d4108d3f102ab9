"""The `airring` executable for the Python tests: $AIRRING, else target/release/airring, else target/debug/airring."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def airring_exe() -> str:
    env = os.environ.get("AIRRING")
    candidates = [pathlib.Path(env)] if env else []
    candidates += [ROOT / "target" / "release" / "airring", ROOT / "target" / "debug" / "airring"]
    for c in candidates:
        if c.exists():
            return str(c)
    pytest.fail("airring not found: `cargo build --release -p master` (or set AIRRING=/path/to/airring)")


def runup(out, *args) -> pathlib.Path:
    """`airring runup ARGS --out OUT --quiet` with the FMUs of target/fmu; returns OUT."""
    cmd = [airring_exe(), "runup", *map(str, args), "--out", str(out), "--quiet", "--fmu-dir", str(ROOT / "target" / "fmu")]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    return pathlib.Path(out)
