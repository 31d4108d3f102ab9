//! Static equilibrium of the rotor under gravity at a constant speed.
//!
//! The rotor is one rigid body on two bearings, so its journal loads follow from statics alone:
//! with the journal offsets a_C = z_JC - z_cm, a_T = z_JT - z_cm, force and moment balance
//! F_C + F_T + m g = 0, a_C F_C + a_T F_T = 0 give the film forces on the journals
//! F_C = -a_T m g_up / (a_C - a_T), F_T = a_C m g_up / (a_C - a_T) (g_up = (0, 9.81) m/s^2).
//! Each film must carry its load: Newton on the journal displacement d (relative to the ring),
//! F_film(d, Omega) = F_req, with the analytic film stiffness K(nu = 0) = -dF/dd as Jacobian
//! (it equals `static_stiffness` to ~5e-6, see fmu-airfilm/tests/dynamic.rs) and steady states
//! warm-started from the previous iterate. Each ring rests where its mount carries the film's
//! reaction and its own weight: c r_R = -F_film + m_R g (g = (0, -9.81)). Gyroscopic and
//! ring-mount damping terms vanish at rest.

use fmu_airfilm::dynamic::FilmLinearization;
use fmu_airfilm::geometry::min_gap_m;
use fmu_airfilm::steady::steady_from;
use fmu_airfilm::{steady_state, BearingParams, FilmError, JournalState, SteadySolution};
use fmu_rotor::RotorParams;
use serde::Serialize;

/// Film forces on the journals [N] that hold the rotor's weight, [C, T], each (x, y).
pub fn journal_loads_n(rotor: &RotorParams) -> [[f64; 2]; 2] {
    let a_c = rotor.z_jc_m - rotor.z_cm_m;
    let a_t = rotor.z_jt_m - rotor.z_cm_m;
    let w = rotor.m_kg * rotor.g_m_s2;
    [[0.0, -a_t * w / (a_c - a_t)], [0.0, a_c * w / (a_c - a_t)]]
}

/// Equilibrium of one bearing, in the units engineers read (named in the fields).
#[derive(Clone, Debug, Serialize)]
pub struct BearingEquilibrium {
    /// Journal relative to the ring [um].
    pub dx_um: f64,
    pub dy_um: f64,
    /// |d| / C.
    pub eps: f64,
    /// Angle of d from the -y (load) direction, positive in the spin sense [deg].
    pub attitude_deg: f64,
    /// Film force on the journal [N] (= the required load).
    pub load_n: [f64; 2],
    pub h_min_um: f64,
    pub p_max_kpa: f64,
    /// Friction torque of the film on the journal [N mm] and the power it dissipates [W]
    /// (wall shear, `fmu_airfilm::friction`).
    pub friction_torque_nmm: f64,
    pub power_loss_w: f64,
    /// Absolute ring and journal centres [um].
    pub ring_um: [f64; 2],
    pub journal_um: [f64; 2],
    /// Static film stiffness K(0) [N/mm] (row = force, column = displacement).
    pub k_static_n_per_mm: [[f64; 2]; 2],
    pub newton_iterations: usize,
}

/// Equilibrium of one bearing with its linearization (kept for the frequency-dependent
/// coefficients of the stability analysis).
pub struct SolvedBearing {
    pub summary: BearingEquilibrium,
    pub lin: FilmLinearization,
    pub journal: JournalState,
}

const MAX_NEWTON: usize = 40;

/// Journal position where the film carries `load_n` at `omega_rad_s`, from the guess `start`
/// (displacement [m] and optionally a pressure field at it). Ring mount data for the absolute
/// positions: stiffness `c_n_m`, ring mass `m_r_kg`, gravity `g_m_s2`.
pub fn solve_bearing(
    prm: &BearingParams,
    omega_rad_s: f64,
    load_n: [f64; 2],
    start: ([f64; 2], Option<&SteadySolution>),
    c_n_m: f64,
    m_r_kg: f64,
    g_m_s2: f64,
) -> Result<SolvedBearing, String> {
    let err = |e: FilmError| e.to_string();
    let mut d = start.0;
    let mut steady = match start.1 {
        Some(s) => s.clone(),
        None => steady_state(prm, JournalState::at(d[0], d[1], omega_rad_s)).map_err(err)?,
    };
    let tol_n = 1e-7 * (load_n[0].hypot(load_n[1])) + 1e-9;
    for it in 1..=MAX_NEWTON {
        let j = JournalState::at(d[0], d[1], omega_rad_s);
        if it > 1 || start.1.is_some() {
            // A warm start that is already converged to round-off can stall the pseudo-time
            // schedule of steady_from (its residual no longer falls): restart from ambient then.
            steady = match steady_from(prm, steady.mesh.clone(), j, steady.p_rel.clone(), None) {
                Ok(s) => s,
                Err(FilmError::SteadyNotConverged { .. }) => steady_state(prm, j).map_err(err)?,
                Err(e) => return Err(err(e)),
            };
        }
        let r = [
            steady.outputs.fx_n - load_n[0],
            steady.outputs.fy_n - load_n[1],
        ];
        let lin = FilmLinearization::from_steady(prm, j, steady.clone()).map_err(err)?;
        if r[0].hypot(r[1]) < tol_n {
            return Ok(finish(lin, j, load_n, c_n_m, m_r_kg, g_m_s2, it));
        }
        let (k, _) = lin.impedance(0.0).map_err(err)?;
        // F(d + delta) ~ F(d) - K delta = load  =>  K delta = F(d) - load.
        let det = k[0][0] * k[1][1] - k[0][1] * k[1][0];
        if !(det.is_finite() && det != 0.0) {
            return Err(format!("singular film stiffness at d = {d:?} m"));
        }
        let mut delta = [
            (k[1][1] * r[0] - k[0][1] * r[1]) / det,
            (k[0][0] * r[1] - k[1][0] * r[0]) / det,
        ];
        // Damping: at most 0.2 C per step, and keep the journal off the ring surface.
        let big = delta[0].hypot(delta[1]) / (0.2 * prm.bore.c_m);
        if big > 1.0 {
            delta = [delta[0] / big, delta[1] / big];
        }
        for _ in 0..30 {
            let trial = JournalState::at(d[0] + delta[0], d[1] + delta[1], omega_rad_s);
            if min_gap_m(&prm.bore, &trial) > 0.5 * prm.contact.h_con_rel * prm.bore.c_m {
                break;
            }
            delta = [0.5 * delta[0], 0.5 * delta[1]];
        }
        d = [d[0] + delta[0], d[1] + delta[1]];
    }
    Err(format!(
        "static equilibrium not found in {MAX_NEWTON} Newton steps at {:.1} Hz (load {:?} N)",
        omega_rad_s / std::f64::consts::TAU,
        load_n
    ))
}

fn finish(
    lin: FilmLinearization,
    j: JournalState,
    load_n: [f64; 2],
    c_n_m: f64,
    m_r_kg: f64,
    g_m_s2: f64,
    iterations: usize,
) -> SolvedBearing {
    let o = lin.steady().outputs;
    let k = lin
        .impedance(0.0)
        .map(|(k, _)| k)
        .unwrap_or([[f64::NAN; 2]; 2]);
    let ring = [-o.fx_n / c_n_m, (-o.fy_n - m_r_kg * g_m_s2) / c_n_m];
    // Attitude: angle from -y to d, counter-clockwise (spin sense) positive.
    let attitude = (j.dx_m).atan2(-j.dy_m).to_degrees();
    let summary = BearingEquilibrium {
        dx_um: j.dx_m * 1e6,
        dy_um: j.dy_m * 1e6,
        eps: o.eps,
        attitude_deg: attitude,
        load_n,
        h_min_um: o.h_min_m * 1e6,
        p_max_kpa: o.p_max_pa * 1e-3,
        friction_torque_nmm: o.friction_torque_nm * 1e3,
        power_loss_w: o.power_loss_w,
        ring_um: [ring[0] * 1e6, ring[1] * 1e6],
        journal_um: [(ring[0] + j.dx_m) * 1e6, (ring[1] + j.dy_m) * 1e6],
        k_static_n_per_mm: [
            [k[0][0] * 1e-3, k[0][1] * 1e-3],
            [k[1][0] * 1e-3, k[1][1] * 1e-3],
        ],
        newton_iterations: iterations,
    };
    SolvedBearing {
        summary,
        lin,
        journal: j,
    }
}
