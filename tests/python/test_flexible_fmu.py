"""rotor.fmu as a flexible rotor in FMPy: the shaft written as the FMU guide documents it
(resources/shaft.json, typed here, not by airring), added to a copy of the packed rotor.fmu.
The FMU validates, and its free fall (no film forces) is the closed form: the journals fall as
-g t^2 / 2, the rings settle on their mounts."""
import json
import math
import pathlib
import shutil
import zipfile

from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from conftest import fmu_path


def steel_element(length_m, od_m):
    return {
        "length_m": length_m,
        "id_left_m": 0.0,
        "od_left_m": od_m,
        "id_right_m": 0.0,
        "od_right_m": od_m,
        "material": {"name": "steel", "rho_kg_m3": 7810.0, "e_pa": 211e9, "g_pa": 81.2e9},
        "shear_effects": True,
        "rotary_inertia": True,
        "gyroscopic": True,
        "shear_coefficient": "cowper",
        "axial_force_n": 0.0,
        "torque_n_m": 0.0,
        "alpha_1_s": 0.0,
        "beta_s": 0.0,
    }


def flexible_rotor_fmu(tmp_path: pathlib.Path) -> str:
    spec = {
        "shaft": {
            "elements": [steel_element(0.015, 0.012 if 5 <= i < 15 else 0.018) for i in range(20)],
            "disks": [
                {"node": 1, "mass_kg": 0.3, "id_kg_m2": 1.8e-4, "ip_kg_m2": 3.0e-4, "tag": "turbine"},
                {"node": 19, "mass_kg": 0.25, "id_kg_m2": 1.5e-4, "ip_kg_m2": 2.5e-4, "tag": "compressor"},
            ],
            "point_masses": [],
            "supports": [],
            "rings": [],
        },
        "bearing_nodes": [15, 5],
    }
    out = tmp_path / "rotor_flexible.fmu"
    shutil.copy(fmu_path("rotor"), out)
    with zipfile.ZipFile(out, "a") as z:
        z.writestr("resources/shaft.json", json.dumps(spec))
    return str(out)


def test_flexible_rotor_fmu_validates(tmp_path):
    assert validate_fmu(flexible_rotor_fmu(tmp_path)) == []


def test_flexible_rotor_falls_freely(tmp_path):
    g = 9.81
    res = simulate_fmu(
        flexible_rotor_fmu(tmp_path),
        stop_time=0.01,
        step_size=1e-4,
        output_interval=1e-3,
        start_values={"f_max": 0.0, "g": g},
        output=["y_JC", "y_JT", "y_RC", "y_RT"],
    )
    t = res["time"]
    for name in ("y_JC", "y_JT"):
        exact = -0.5 * g * t**2
        err = max(abs(a - b) for a, b in zip(res[name], exact))
        # Free fall of the whole shaft: its bending under the uniform load is nil at rest.
        assert err <= 1e-3 * abs(exact[-1]), (name, err)
    # The rings (50 g on 1000 N/mm) oscillate about their sag -m g / c.
    sag = -0.05 * g / 1e6
    assert all(2.5 * sag <= y <= 0.5 * abs(sag) for y in res["y_RC"]), res["y_RC"]
    assert not any(math.isnan(v) for v in res["y_RT"])
