"""Shared fixtures: the packed FMUs built by `cargo xtask fmus`."""
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "target" / "fmu"


def fmu_path(name: str) -> str:
    p = FMU_DIR / f"{name}.fmu"
    if not p.exists():
        pytest.fail(f"{p} is missing: run `cargo xtask fmus` first")
    return str(p)
