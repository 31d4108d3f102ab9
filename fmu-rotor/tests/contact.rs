//! The journal-ring contact evaluated inside the rotor (`RotorParams::contact`): the rotor
//! dropped onto its bearings with no film force comes to rest on the contact, and the rest state
//! obeys the static balance of every body.

use bearing::{min_gap_m, Bore, BoreContact, JournalState};
use fmu_rotor::{BearingForces, FilmCoefficients, Rotor, RotorOutputs, RotorParams};

const MACRO_S: f64 = 1e-4;

fn no_film(_t: f64) -> BearingForces {
    BearingForces::default()
}

/// Paper rotor without spin; `damper` adds a pure viscous link between journal and ring (a
/// stand-in for the squeeze film) so the drop settles in a few tens of milliseconds.
fn dropped(contact: bool, damper_n_s_m: f64, t_end_s: f64) -> (Rotor, RotorOutputs) {
    let p = RotorParams {
        f_max_hz: 0.0,
        contact: contact.then(|| [BoreContact::paper(), BoreContact::paper()]),
        ..RotorParams::paper()
    };
    let film = FilmCoefficients::isotropic(0.0, damper_n_s_m);
    let mut r = Rotor::with_linear_films(p, [film, film]).unwrap();
    let n = (t_end_s / MACRO_S).round() as usize;
    for i in 0..n {
        r.advance(i as f64 * MACRO_S, MACRO_S, &no_film).unwrap();
    }
    let o = r.outputs();
    (r, o)
}

#[test]
fn a_dropped_rotor_rests_on_the_contact_in_static_balance() {
    let (r, o) = dropped(true, 3000.0, 0.3);
    let p = r.params();
    let BoreContact { bore: b, law } = BoreContact::paper();
    let w_rotor_n = p.m_kg * p.g_m_s2;
    let fc = [o.bearing_c.contact_n, o.bearing_t.contact_n];
    // Rotor: the two contact forces carry its weight (no film force, damper at rest).
    let sum_y = fc[0][1] + fc[1][1];
    let sum_x = fc[0][0] + fc[1][0];
    assert!(
        (sum_y - w_rotor_n).abs() < 1e-3 * w_rotor_n,
        "{sum_y} N vs {w_rotor_n} N"
    );
    assert!(sum_x.abs() < 1e-3 * w_rotor_n, "x {sum_x} N");
    // Moment balance about the centre of mass: the bearing loads split as the lever arms.
    let (a_c, a_t) = (p.z_jc_m - p.z_cm_m, p.z_cm_m - p.z_jt_m);
    let expect_c = w_rotor_n * a_t / (a_c + a_t);
    assert!(
        (fc[0][1] - expect_c).abs() < 2e-3 * w_rotor_n,
        "{} N vs {expect_c} N",
        fc[0][1]
    );
    // Rings: mount force balances ring weight plus the journal's push (-F_contact).
    for (bo, c_n_m, m_kg) in [
        (&o.bearing_c, p.c_c_n_m, p.m_r_c_kg),
        (&o.bearing_t, p.c_t_n_m, p.m_r_t_kg),
    ] {
        let y_expect = -(m_kg * p.g_m_s2 + bo.contact_n[1]) / c_n_m;
        assert!(
            (bo.ring_m[1] - y_expect).abs() < 2e-3 * y_expect.abs(),
            "ring y {} vs {y_expect}",
            bo.ring_m[1]
        );
        // The journal sits in the contact band: beyond C - h_con from the centre, yet the
        // penetration needed to carry ~4 N on a penalty of 1e16 N/m^3 is far below 1 um.
        let e = bo.dx_m.hypot(bo.dy_m);
        assert!(e > b.c_m * (1.0 - law.h_con_rel), "eccentricity {e} m");
        let h_min = min_gap_m(&b, &JournalState::at(bo.dx_m, bo.dy_m, 0.0));
        let h_con = law.h_con_rel * b.c_m;
        assert!(
            h_min < h_con && h_min > h_con - 0.1e-6,
            "h_min {h_min} m, h_con {h_con} m"
        );
        // At rest.
        assert!(
            bo.vx_m_s.hypot(bo.vy_m_s) < 1e-5,
            "still moving: {} m/s",
            bo.vx_m_s.hypot(bo.vy_m_s)
        );
    }
}

#[test]
fn without_the_contact_the_rotor_falls_through_the_clearance() {
    // The same drop with the contact off: nothing holds the journal (the contrast that shows
    // the contact force above is the rotor's own, not the damper's).
    let (_, o) = dropped(false, 3000.0, 0.03);
    assert!(
        o.bearing_c.dy_m < -2.0 * Bore::paper().c_m,
        "dy_C = {} m",
        o.bearing_c.dy_m
    );
}

#[test]
fn a_bad_contact_geometry_is_reported_under_the_rotor_parameter_name() {
    let p = RotorParams {
        contact: Some([
            BoreContact::paper(),
            BoreContact {
                bore: Bore {
                    c_m: -1e-6,
                    ..Bore::paper()
                },
                ..BoreContact::paper()
            },
        ]),
        ..RotorParams::paper()
    };
    let e = Rotor::new(p).unwrap_err().to_string();
    assert!(e.contains("bearing_C"), "{e}");
}

/// The paper rotor with its ring contacts, moved `dy_m` in y and tilted `tilt_rad` about x from
/// its initial state, every coordinate moving (its system, positions and velocities).
fn rotor_against_its_rings(
    dy_m: f64,
    tilt_rad: f64,
) -> (fmu_rotor::system::MultibodySystem, Vec<f64>, Vec<f64>) {
    use fmu_rotor::rotor::{build_system, initial_state};
    let p = RotorParams {
        contact: Some([BoreContact::paper(), BoreContact::paper()]),
        ..RotorParams::paper()
    };
    let (mut x, mut v) = initial_state(&p);
    x[1] += dy_m;
    x[3] += tilt_rad;
    for (i, vi) in v.iter_mut().enumerate() {
        *vi += 1e-3 * (i as f64 + 1.0).sin();
    }
    (build_system(&p, None), x, v)
}

/// The force Jacobians' velocity columns leave the ring contact out (it depends on positions
/// alone, so it cancels in their difference quotients): with both journals pressed into their
/// rings they equal difference quotients of the whole force vector, to the quotients' own
/// rounding.
#[test]
fn velocity_columns_without_the_contact_equal_those_of_the_whole_force() {
    use fmu_rotor::ggl::{force_jacobians, Work};
    use fmu_rotor::rotor::N_INPUTS;
    use fmu_rotor::system::RingContacts;
    // The rotor 3 C below its rings (beyond the lobes' steps of 2 C), moving and spinning.
    let (sys, x, v) = rotor_against_its_rings(-3.0 * Bore::paper().c_m, 0.0);
    let nq = sys.n_coords();
    let u = [0.0; N_INPUTS];
    let mut work = Work::new(sys.bodies.len());
    let (mut with, mut without) = (vec![0.0; nq], vec![0.0; nq]);
    sys.eval_with(
        &x,
        &v,
        &u,
        &mut work.m_blocks,
        &mut with,
        RingContacts::Evaluate,
    );
    sys.eval_with(
        &x,
        &v,
        &u,
        &mut work.m_blocks,
        &mut without,
        RingContacts::Omit,
    );
    let contact = (with[1] - without[1]).abs();
    assert!(
        contact > 10.0,
        "the journals must press on their rings: {contact} N"
    );
    let (_, fv, _) = force_jacobians(&sys, &x, &v, &u, &mut work);
    let mut vp = v.clone();
    let mut f = vec![0.0; nq];
    let scale = fv.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    for j in 0..nq {
        let dv = 1.5e-8 * v[j].abs().max(1.0);
        vp[j] = v[j] + dv;
        sys.eval(&x, &vp, &u, &mut work.m_blocks, &mut f);
        vp[j] = v[j];
        for i in 0..nq {
            let whole = (f[i] - with[i]) / dv;
            // Rounding of a force of ~|with| over dv.
            let tol = 1e-6 * scale + 4.0 * f64::EPSILON * with[i].abs() / dv;
            assert!(
                (fv[i * nq + j] - whole).abs() <= tol,
                "({i}, {j}): {} vs {whole}",
                fv[i * nq + j]
            );
        }
    }
}

/// The force Jacobians' position columns reuse a ring contact's force where the column's
/// coordinate leaves that journal's displacement against its ring bitwise unchanged: the
/// columns equal difference quotients of full evaluations bit for bit, with one journal pressed
/// into its ring or both, and most of the contact evaluations are saved.
#[test]
fn position_columns_reusing_unmoved_contacts_equal_full_evaluations_bit_for_bit() {
    use fmu_rotor::ggl::{force_jacobians, Work};
    use fmu_rotor::rotor::N_INPUTS;
    let c = Bore::paper().c_m;
    // Pressed: the rotor 3 C below its rings; tilted: one journal in, the other one free.
    for (label, dy, tilt) in [
        ("both pressed", -3.0 * c, 0.0),
        ("one pressed", -1.5 * c, 1e-4),
    ] {
        let (sys, x, v) = rotor_against_its_rings(dy, tilt);
        let nq = sys.n_coords();
        let u = [0.0; N_INPUTS];
        let mut work = Work::new(sys.bodies.len());
        let (fx, _, _) = force_jacobians(&sys, &x, &v, &u, &mut work);
        let reused = work.contacts.reused();
        let (mut f0, mut f) = (vec![0.0; nq], vec![0.0; nq]);
        sys.eval(&x, &v, &u, &mut work.m_blocks, &mut f0);
        let mut xp = x.clone();
        for j in 0..nq {
            let dx = 1.5e-8 * x[j].abs().max(1e-3);
            xp[j] = x[j] + dx;
            sys.eval(&xp, &v, &u, &mut work.m_blocks, &mut f);
            xp[j] = x[j];
            for i in 0..nq {
                let full = (f[i] - f0[i]) / dx;
                assert_eq!(
                    fx[i * nq + j].to_bits(),
                    full.to_bits(),
                    "{label}: ({i}, {j}) {} vs {full}",
                    fx[i * nq + j]
                );
            }
        }
        // Each journal moves against its ring with the rotor's 4 lateral coordinates and its
        // ring's 2: the other 12 of the 18 columns reuse its force.
        assert!(reused >= 2 * 12, "{label}: {reused} contact forces reused");
    }
}
