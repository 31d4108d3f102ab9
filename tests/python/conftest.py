"""Shared fixtures: the packed FMUs built by `cargo xtask fmus`."""
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "target" / "fmu"


def fmu_path(name: str) -> str:
    """The FMI 2.0 FMU `name`, or its FMI 3.0 twin with name "fmi3/NAME"."""
    p = FMU_DIR / f"{name}.fmu"
    if not p.exists():
        pytest.fail(f"{p} is missing: run `cargo xtask fmus` first")
    return str(p)
