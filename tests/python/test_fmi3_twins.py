"""The FMI 3.0 Co-Simulation twins (target/fmu/fmi3/*.fmu, issue #15 item 3) in FMPy: validation,
the same variables as the FMI 2.0 FMUs, the same results, several instances side by side, FMU
state get/set/serialize, output derivatives, and the FMI 3.0 value-reference mapping."""
import shutil

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from conftest import fmu_path

NAMES = ["airfilm", "rotor"]
# FMI 3.0 value references are unique across types: Int32 = 1e6 + the FMI 2.0 Integer's, Boolean =
# 2e6 + the FMI 2.0 Boolean's (fmi3/src/value_refs.rs); Float64 keep theirs.
OFFSET = {"Real": 0, "Float64": 0, "Integer": 1_000_000, "Int32": 1_000_000, "Boolean": 2_000_000}


@pytest.mark.parametrize("name", NAMES)
def test_validate_finds_no_problems(name):
    assert validate_fmu(fmu_path(f"fmi3/{name}")) == []


@pytest.mark.parametrize("name", NAMES)
def test_same_variables_as_the_fmi2_fmu(name):
    md2 = read_model_description(fmu_path(name))
    md3 = read_model_description(fmu_path(f"fmi3/{name}"))
    assert md3.fmiVersion == "3.0"
    cs = md3.coSimulation
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canHandleVariableCommunicationStepSize
    v2 = {v.name: v for v in md2.modelVariables}
    v3 = {v.name: v for v in md3.modelVariables if v.name != "time"}
    assert set(v2) == set(v3)
    def unit(v):
        # FMI 3.0 twins state units through declared types (TypeDefinitions).
        t = v.declaredType
        return (v.unit or (t.unit if t else None), v.displayUnit or (t.displayUnit if t else None))

    for n, a in v2.items():
        b = v3[n]
        assert (a.causality, a.variability, (a.unit, a.displayUnit)) == (b.causality, b.variability, unit(b)), n
        assert b.valueReference == a.valueReference + OFFSET[a.type], n
        assert OFFSET[b.type] == OFFSET[a.type], (n, a.type, b.type)
        if a.start is not None:
            assert float(a.start) == float(b.start) if a.type != "Boolean" else a.start == b.start
    refs = [v.valueReference for v in md3.modelVariables]
    assert len(refs) == len(set(refs)), "unique value references"


def test_simulate_equals_the_fmi2_fmus():
    """FMPy's simulate_fmu of each twin equals the FMI 2.0 FMU (constant inputs: no input
    derivatives on either side); required 1e-9 relative, reached bit for bit."""
    cases = [
        ("rotor", dict(stop_time=0.01, step_size=1e-5, output_interval=1e-3,
                       output=["omega", "y_JC", "x_JT", "y_RT", "spin_angle"])),
        ("airfilm", dict(stop_time=2e-3, step_size=1e-5, output_interval=1e-4,
                         start_values={"dx": 5e-6, "dy": -3e-6, "omega": 2000.0},
                         output=["Fx", "Fy", "eps", "h_min", "p_max", "friction_torque", "power_loss"])),
    ]
    for name, kw in cases:
        a = simulate_fmu(fmu_path(name), **kw)
        b = simulate_fmu(fmu_path(f"fmi3/{name}"), **kw)
        for n in kw["output"]:
            scale = max(np.max(np.abs(a[n])), 1e-300)
            assert np.max(np.abs(a[n] - b[n])) <= 1e-9 * scale, (name, n)
            assert np.array_equal(a[n], b[n]), (name, n)


def _slave(name, instance):
    path = fmu_path(f"fmi3/{name}")
    md = read_model_description(path)
    unzipped = extract(path)
    s = FMU3Slave(guid=md.instantiationToken, unzipDirectory=unzipped,
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance)
    s.instantiate()
    return s, {v.name: v.valueReference for v in md.modelVariables}, unzipped


def test_two_films_side_by_side_state_and_output_derivatives():
    (a, vr, da), (b, _, db) = _slave("airfilm", "a"), _slave("airfilm", "b")
    try:
        for s, dx in ((a, 5e-6), (b, -4e-6)):
            s.enterInitializationMode(startTime=0.0)
            s.setFloat64([vr["dx"], vr["omega"]], [dx, 3000.0])
            s.exitInitializationMode()
        h = 1e-5
        for k in range(20):
            for s in (a, b):
                event, terminate, early, last = s.doStep(k * h, h)
                assert not (event or terminate or early) and last == pytest.approx((k + 1) * h)
        fa, fb = a.getFloat64([vr["Fx"]])[0], b.getFloat64([vr["Fx"]])[0]
        assert fa < 0 < fb, "each instance keeps its own journal position"
        # State: save, step on, restore, step again: the same outputs bit for bit; and the
        # serialized state restores another instance to the same point.
        st = a.getFMUState()
        blob = a.serializeFMUState(st)
        for k in range(20, 30):
            a.doStep(k * h, h)
        f1 = a.getFloat64([vr["Fx"], vr["Fy"]])
        a.setFMUState(st)
        for k in range(20, 30):
            a.doStep(k * h, h)
        assert a.getFloat64([vr["Fx"], vr["Fy"]]) == f1
        st_b = b.deserializeFMUState(blob)
        b.setFMUState(st_b)
        for k in range(20, 30):
            b.doStep(k * h, h)
        assert b.getFloat64([vr["Fx"], vr["Fy"]]) == f1
        a.freeFMUState(st)
        b.freeFMUState(st_b)
        # Output derivatives: the first derivatives of Fx and Fy, exactly what the FMI 2.0 FMU
        # returns after the same calls (one model behind both ABIs), and a force that is still
        # building up (d Fx / dt != 0).
        d3 = a.getOutputDerivatives([vr["Fx"], vr["Fy"]], [1, 1])
        assert d3 == _fmi2_output_derivatives(30, h)
        assert all(np.isfinite(d3)) and d3[0] != 0.0
        for s in (a, b):
            s.terminate()
    finally:
        for s, d in ((a, da), (b, db)):
            s.freeInstance()
            shutil.rmtree(d, ignore_errors=True)


def _fmi2_output_derivatives(n_steps, h):
    """dFx/dt, dFy/dt of the FMI 2.0 air film after the twin test's calls (instance a)."""
    from fmpy.fmi2 import FMU2Slave
    path = fmu_path("airfilm")
    md = read_model_description(path)
    d = extract(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier="airfilm", instanceName="a2")
    try:
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        s.setReal([vr["dx"], vr["omega"]], [5e-6, 3000.0])
        s.exitInitializationMode()
        for k in range(n_steps):
            s.doStep(k * h, h)
        out = s.getRealOutputDerivatives([vr["Fx"], vr["Fy"]], [1, 1])
        s.terminate()
        return list(out)
    finally:
        s.freeInstance()
        shutil.rmtree(d, ignore_errors=True)


def test_int32_and_boolean_parameters_reach_the_model():
    """The mapped value references work end to end: a finer mesh (Int32 n_elem_phi) changes the
    film force, and the rotor's contact Boolean holds its journals in the bore."""
    s, vr, d = _slave("airfilm", "mesh24")
    try:
        s.enterInitializationMode(startTime=0.0)
        s.setInt32([vr["n_elem_phi"]], [24])
        assert s.getInt32([vr["n_elem_phi"]]) == [24]
        s.setFloat64([vr["dx"], vr["omega"]], [5e-6, 3000.0])
        s.exitInitializationMode()
        s.doStep(0.0, 1e-4)
        f24 = s.getFloat64([vr["Fx"]])[0]
        s.terminate()
    finally:
        s.freeInstance()
        shutil.rmtree(d, ignore_errors=True)
    s, vr, d = _slave("airfilm", "mesh20")
    try:
        s.enterInitializationMode(startTime=0.0)
        s.setFloat64([vr["dx"], vr["omega"]], [5e-6, 3000.0])
        s.exitInitializationMode()
        s.doStep(0.0, 1e-4)
        f20 = s.getFloat64([vr["Fx"]])[0]
        s.terminate()
    finally:
        s.freeInstance()
        shutil.rmtree(d, ignore_errors=True)
    assert f20 != f24 and abs(f20 - f24) < 0.05 * abs(f20)
    out = ["dx_C", "dy_C"]
    held = simulate_fmu(fmu_path("fmi3/rotor"), stop_time=0.02, step_size=1e-5, output_interval=1e-4,
                        start_values={"contact": True}, output=out)
    assert np.hypot(held["dx_C"], held["dy_C"]).max() < 60e-6
