"""A flexible rotor in AirRing against ROSS itself (ross-rotordynamics 2.3.0, the version
tests/python/requirements.txt pins): the same rotor, built in ROSS and saved by `Rotor.save`, read by
`airring modal --rotor` from ROSS's own file (not retyped).

The rotor: a stepped 240 mm shaft of 20 Timoshenko elements, a compressor and a turbine disk, two
linear bearings with cross-coupled stiffness (which makes forward modes unstable: negative log
decrements are compared too). Compared: the lateral eigenfrequencies (0.5 %) and log decrements
(5 %) at 0, 1000 and 2000 Hz, the critical speeds, and the unbalance response amplitude (2 %) at
five speeds. ROSS models axial and torsional motion as well; its modes are sorted into lateral and
other by where their eigenvector lives."""
import json
import math
import subprocess
import warnings

import numpy as np
import pytest

from airring_bin import airring_exe

import ross as rs

SPEEDS_HZ = [0.0, 1000.0, 2000.0]
UNBALANCE_SPEEDS_HZ = [150.0, 400.0, 900.0, 1400.0, 2000.0]
UNBALANCE_NODE = 1
UNBALANCE_G_MM = 10.0


def build_rotor():
    steel = rs.Material(name="Steel", rho=7810, E=211e9, G_s=81.2e9)
    n = 20
    shaft = [
        rs.ShaftElement(L=0.24 / n, idl=0.0, odl=0.022 if 5 <= i < 15 else 0.018, material=steel)
        for i in range(n)
    ]
    disks = [
        rs.DiskElement(n=1, m=0.35, Id=2.0e-4, Ip=3.6e-4, tag="compressor"),
        rs.DiskElement(n=19, m=0.45, Id=2.6e-4, Ip=4.8e-4, tag="turbine"),
    ]
    bearings = [
        rs.BearingElement(n=node, kxx=2e6, kyy=1.6e6, kxy=3e5, kyx=-3e5, cxx=150, cyy=120, tag=tag)
        for node, tag in [(5, "C"), (15, "T")]
    ]
    return rs.Rotor(shaft, disks, bearings)


@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    warnings.simplefilter("ignore")
    d = tmp_path_factory.mktemp("ross")
    rotor = build_rotor()
    rotor.save(d / "rotor.toml")
    cmd = [airring_exe(), "modal", "--rotor", str(d / "rotor.toml"), "--out", str(d / "out"),
           "--speed", *map(str, sorted(set(SPEEDS_HZ + UNBALANCE_SPEEDS_HZ))),
           "--unbalance", str(UNBALANCE_G_MM), "--unbalance-node", str(UNBALANCE_NODE)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    ours = json.loads((d / "out" / "modal.json").read_text())
    return rotor, ours


def ross_lateral_modes(rotor, speed_hz):
    """ROSS's modes at a speed, the lateral ones only (x, y, alpha, beta carry most of the
    eigenvector), as (damped frequency [Hz], log dec) by increasing frequency."""
    m = rotor.run_modal(speed=speed_hz * 2 * math.pi, num_modes=2 * rotor.ndof, sparse=False)
    nd, ndof = rotor.number_dof, rotor.ndof
    lateral = [i for i in range(ndof) if i % nd in (0, 1, 3, 4)]
    out = []
    for k in range(len(m.wd)):
        v = m.evectors[:ndof, k]
        if np.sum(np.abs(v[lateral]) ** 2) > 0.5 * np.sum(np.abs(v) ** 2) and m.wd[k] > 0:
            out.append((m.wd[k] / (2 * math.pi), m.log_dec[k]))
    return sorted(out)


def ours_at(ours, speed_hz):
    row = next(r for r in ours["campbell"] if r["speed_hz"] == speed_hz)
    return [(m["freq_hz"], m["log_dec"]) for m in row["modes"]]


@pytest.mark.parametrize("speed_hz", SPEEDS_HZ)
def test_eigenfrequencies_and_log_decrements_agree_with_ross(compared, speed_hz):
    rotor, ours = compared
    theirs = ross_lateral_modes(rotor, speed_hz)
    mine = ours_at(ours, speed_hz)
    # The modes below 10 kHz: the rotor's bending modes and well beyond its speed range.
    theirs = [m for m in theirs if m[0] < 10_000]
    assert len(theirs) >= 12
    assert len(mine) >= len(theirs)
    for (f_r, ld_r), (f_o, ld_o) in zip(theirs, mine):
        assert abs(f_o - f_r) <= 0.005 * f_r, (speed_hz, f_r, f_o)
        # 5 % of the log dec, or 1e-4 absolute for the nearly undamped modes.
        assert abs(ld_o - ld_r) <= max(0.05 * abs(ld_r), 1e-4), (speed_hz, f_r, ld_r, ld_o)


def test_critical_speeds_agree_with_ross(compared):
    rotor, ours = compared
    theirs = rotor.run_critical_speed(num_modes=16)
    theirs_hz = np.asarray(theirs._wd if hasattr(theirs, "_wd") else theirs.wd()) / (2 * math.pi)
    mine = [c["speed_hz"] for c in ours["critical_speeds"]]
    assert len(mine) >= 6
    # ROSS's list mixes in its axial and torsional modes (their frequency does not depend on the
    # speed); every lateral critical speed of ours below 2 kHz must be one of ROSS's.
    for s in mine:
        if s < 2000:
            nearest = min(theirs_hz, key=lambda t: abs(t - s))
            assert abs(nearest - s) <= 0.005 * s, (s, sorted(theirs_hz))


def test_unbalance_response_agrees_with_ross(compared):
    rotor, ours = compared
    w = np.array(UNBALANCE_SPEEDS_HZ) * 2 * math.pi
    resp = rotor.run_unbalance_response(
        node=[UNBALANCE_NODE], unbalance_magnitude=[UNBALANCE_G_MM * 1e-6], unbalance_phase=[0.0],
        frequency=w,
    )
    forced = resp.forced_resp  # ndof x len(w), complex
    nd = rotor.number_dof
    rows = {r["speed_hz"]: r for r in ours["unbalance"]["response"]}
    checked = 0
    for j, f in enumerate(UNBALANCE_SPEEDS_HZ):
        for node in (1, 5, 10, 15, 19):
            theirs_x = abs(forced[nd * node, j]) * 1e6
            theirs_y = abs(forced[nd * node + 1, j]) * 1e6
            mine = rows[f]["nodes"][node]
            assert abs(mine["x_amplitude_um"] - theirs_x) <= 0.02 * theirs_x, (f, node, theirs_x, mine)
            assert abs(mine["y_amplitude_um"] - theirs_y) <= 0.02 * theirs_y, (f, node, theirs_y, mine)
            checked += 1
    assert checked == 25


def test_stability_in_air_ring_bearings_carries_the_weight_ross_gives(tmp_path):
    """`airring stability --rotor` on the same shaft and disks without bearings, carried by two air
    ring bearings: the films' static loads add up to the weight of ROSS's rotor and balance its
    moment about ROSS's centre of gravity (ROSS's own mass and CG, not ours)."""
    warnings.simplefilter("ignore")
    r = build_rotor()
    bare = rs.Rotor(r.shaft_elements, r.disk_elements, [])
    bare.save(tmp_path / "bare.toml")
    cmd = [airring_exe(), "stability", "--rotor", str(tmp_path / "bare.toml"), "--bearing-nodes", "5,15",
           "--speeds", "300:900:600", "--mesh", "10x4", "--out", str(tmp_path / "out")]
    p = subprocess.run(cmd, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    v = json.loads((tmp_path / "out" / "stability.json").read_text())
    assert v["rotor"]["bearing_nodes"] == [5, 15]
    assert (tmp_path / "out" / "rotor.svg").exists()
    weight = bare.m * 9.81
    z = bare.nodes_pos
    for sp in v["report"]["speeds"]:
        (fc, ft) = (sp["bearings"][0]["load_n"], sp["bearings"][1]["load_n"])
        assert abs(fc[1] + ft[1] - weight) <= 1e-9 * weight
        moment = fc[1] * (z[5] - bare.CG) + ft[1] * (z[15] - bare.CG)
        assert abs(moment) <= 1e-9 * weight * 0.24
        assert len(sp["modes"]) >= 8
