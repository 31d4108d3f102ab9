"""FMPy checks of every packed FMU: validation, simulation, and the low-level FMU2Slave API."""
import math

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.validation import validate_fmu

from conftest import fmu_path

SHIPPED = ["oscillator", "airfilm", "rotor"]


@pytest.mark.parametrize("name", SHIPPED)
def test_validate_finds_no_problems(name):
    problems = validate_fmu(fmu_path(name))
    assert problems == [], problems


@pytest.mark.parametrize("name", SHIPPED)
def test_model_description_declares_capabilities(name):
    md = read_model_description(fmu_path(name))
    cs = md.coSimulation
    assert cs.canInterpolateInputs and cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canHandleVariableCommunicationStepSize and cs.maxOutputDerivativeOrder >= 1
    assert not cs.needsExecutionTool


def test_simulate_oscillator_matches_closed_form():
    # Constant force F = 2 N from t = 0: x = F/k (1 - cos w t), k = 4 pi^2, m = 1.
    res = simulate_fmu(fmu_path("oscillator"), stop_time=1.0, output_interval=0.01, start_values={"F": 2.0, "x0": 0.0})
    w = 2 * math.pi
    exact = 2.0 / w**2 * (1 - np.cos(w * res["time"]))
    assert np.max(np.abs(res["x"] - exact)) < 1e-12


def _slave(name, instance="s"):
    path = fmu_path(name)
    md = read_model_description(path)
    from fmpy import extract

    unzipdir = extract(path)
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    return slave, vrs


def test_fmu2slave_lifecycle_state_and_input_derivatives():
    s, vr = _slave("oscillator")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    a, h = 3.0, 0.05
    t = 0.0
    state = None
    for n in range(20):
        t = n * h
        if n == 10:
            state = s.getFMUState()
            blob = s.serializeFMUState(state)
        s.setReal([vr["F"]], [a * t])
        s.setRealInputDerivatives([vr["F"]], [1], [a])
        s.doStep(t, h)
    x_end = s.getReal([vr["x"]])[0]
    w = 2 * math.pi
    exact = a / w**2 * (1.0 - math.sin(w * 1.0) / w)
    assert abs(x_end - exact) < 1e-13

    # Roll back to t = 0.5 and repeat: bit-identical.
    s.setFMUState(s.deSerializeFMUstate(blob))
    for n in range(10, 20):
        t = n * h
        s.setReal([vr["F"]], [a * t])
        s.setRealInputDerivatives([vr["F"]], [1], [a])
        s.doStep(t, h)
    assert s.getReal([vr["x"]])[0] == x_end
    s.freeFMUState(state)
    s.terminate()
    s.freeInstance()


def test_simulate_airfilm_displaced_journal_is_pushed_back():
    # Journal 6 um below the ring centre at 1000 Hz: after the film builds up, Fy > 0 (restoring).
    res = simulate_fmu(
        fmu_path("airfilm"),
        stop_time=2e-3,
        step_size=1e-5,
        output_interval=1e-4,
        start_values={"dy": -6e-6, "omega": 6283.185307179586},
        output=["Fx", "Fy", "eps", "h_min", "p_max"],
    )
    assert np.all(np.isfinite(res["Fy"]))
    assert res["Fy"][-1] > 1.0
    assert abs(res["eps"][-1] - 0.3) < 1e-12
    assert res["p_max"][-1] > 101325.0


def test_simulate_rotor_run_up_speed():
    res = simulate_fmu(fmu_path("rotor"), stop_time=0.01, step_size=1e-5, output_interval=1e-3, output=["omega", "y_JC"])
    expected = 2 * math.pi * 2000.0 * res["time"] / 3.0
    assert np.max(np.abs(res["omega"] - expected)) < 1e-9 * expected.max()
    assert res["y_JC"][-1] < 0.0  # no film forces connected: the rotor falls under gravity


def test_rotor_with_contact_is_held_by_its_rings():
    # No film forces connected: with contact = true the rotor's own contact law catches the
    # journals in the bore (C = 20 um, dH = 40 um: at most C + dH from the ring centre, less the
    # tiny penetration); without it they fall through (~0.5 g t^2 = 2 mm in 20 ms).
    out = ["dx_C", "dy_C", "dx_T", "dy_T", "F_contact_C", "F_contact_T"]
    kw = dict(stop_time=0.02, step_size=1e-5, output_interval=1e-4, output=out)
    held = simulate_fmu(fmu_path("rotor"), start_values={"contact": True}, **kw)
    free = simulate_fmu(fmu_path("rotor"), **kw)
    for side in "CT":
        r = np.hypot(held[f"dx_{side}"], held[f"dy_{side}"])
        assert r.max() < 60e-6
        assert r.max() > 19e-6  # it did reach the bore
        assert held[f"F_contact_{side}"].max() > 1.0
        assert np.all(free[f"F_contact_{side}"] == 0.0)
        assert free[f"dy_{side}"][-1] < -1e-3


def test_airfilm_input_derivatives_and_state_through_fmu2slave():
    s, vr = _slave("airfilm")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.setReal([vr["omega"]], [2 * math.pi * 1000.0])
    s.exitInitializationMode()
    h = 1e-5
    v = -0.05  # m/s: the journal moves down at 50 mm/s
    state = None
    for n in range(10):
        t = n * h
        if n == 5:
            state = s.getFMUState()
        s.setReal([vr["dy"], vr["vy"]], [v * t, v])
        s.setRealInputDerivatives([vr["dy"]], [1], [v])
        s.doStep(t, h)
    fy = s.getReal([vr["Fy"]])[0]
    assert fy > 0.0  # squeeze + wedge oppose the downward motion
    s.setFMUState(state)
    for n in range(5, 10):
        t = n * h
        s.setReal([vr["dy"], vr["vy"]], [v * t, v])
        s.setRealInputDerivatives([vr["dy"]], [1], [v])
        s.doStep(t, h)
    assert s.getReal([vr["Fy"]])[0] == fy
    s.freeFMUState(state)
    s.terminate()
    s.freeInstance()
