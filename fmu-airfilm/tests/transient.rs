//! Transient solver: temporal order on a prescribed whirl orbit, gas mass conservation,
//! bit-identical clone/serialize-restore, and clear errors for bad input.

use fmu_airfilm::Bore;
use fmu_airfilm::{steady_state, AirFilm, BearingParams, FilmError, JournalState};
use std::f64::consts::PI;

fn whirl(
    prm: &BearingParams,
    eps: f64,
    f_whirl_hz: f64,
    f_spin_hz: f64,
) -> impl Fn(f64) -> JournalState {
    let e = eps * prm.bore.c_m;
    let w = 2.0 * PI * f_whirl_hz;
    let om = 2.0 * PI * f_spin_hz;
    move |t: f64| JournalState {
        dx_m: e * (w * t).cos(),
        dy_m: e * (w * t).sin(),
        vx_m_s: -e * w * (w * t).sin(),
        vy_m_s: e * w * (w * t).cos(),
        omega_rad_s: om,
    }
}

/// Film started from the steady state at the orbit's t = 0 position.
fn film_on_orbit(prm: &BearingParams, orbit: &dyn Fn(f64) -> JournalState) -> AirFilm {
    let j0 = orbit(0.0);
    let s = steady_state(prm, j0).unwrap();
    let mut f = AirFilm::new(prm.clone()).unwrap();
    f.set_pressures_rel(0.0, j0, &s.p_rel).unwrap();
    f
}

#[test]
fn temporal_order_on_a_whirl_orbit() {
    let base = BearingParams {
        n_elem_phi: 8,
        n_elem_z: 3,
        ..BearingParams::paper()
    };
    let orbit = whirl(&base, 0.4, 400.0, 1000.0);
    let t_end = 2e-4;
    let run = |h: f64| {
        // Tight Newton convergence (its tolerance scales with rtol) so that only the BDF error remains.
        let prm = BearingParams {
            fixed_step_s: h,
            rtol: 1e-10,
            atol_pa: 1e-6,
            ..base.clone()
        };
        let mut f = film_on_orbit(&prm, &orbit);
        f.advance(0.0, t_end, &orbit).unwrap();
        let o = f.outputs();
        [o.fx_n, o.fy_n]
    };
    let hs = [4e-6, 2e-6, 1e-6, 0.5e-6];
    let fs: Vec<[f64; 2]> = hs.iter().map(|&h| run(h)).collect();
    let mut orders = Vec::new();
    for i in 0..hs.len() - 2 {
        let d1 = (fs[i][0] - fs[i + 1][0]).hypot(fs[i][1] - fs[i + 1][1]);
        let d2 = (fs[i + 1][0] - fs[i + 2][0]).hypot(fs[i + 1][1] - fs[i + 2][1]);
        orders.push((d1 / d2).log2());
        println!(
            "h = {:.1e} s: F = {:?} N, |F_h - F_h/2| = {d1:.3e} N",
            hs[i], fs[i]
        );
    }
    println!("observed temporal orders (BDF2, fixed step): {orders:?}");
    let last = *orders.last().unwrap();
    assert!(last > 1.8 && last < 2.3, "temporal order {last}");

    // Adaptive: the error follows the tolerance.
    let reference = fs[hs.len() - 1];
    for rtol in [1e-3, 1e-4, 1e-5, 1e-6] {
        let prm = BearingParams {
            rtol,
            atol_pa: rtol * 1e5,
            ..base.clone()
        };
        let mut f = film_on_orbit(&prm, &orbit);
        let mut steps = 0;
        steps += f.advance(0.0, t_end, &orbit).unwrap().n_steps;
        let o = f.outputs();
        let err = (o.fx_n - reference[0]).hypot(o.fy_n - reference[1]);
        println!("adaptive rtol {rtol:.0e}: {steps} steps, |F - F_ref| = {err:.3e} N");
    }
}

#[test]
fn gas_mass_is_conserved() {
    // d/dt Int p h dA = -(boundary outflow). The Galerkin scheme conserves mass with its consistent
    // boundary flux; this check uses the independent flux from the FE pressure gradient at the
    // edges, so the imbalance is the O(h^2) error of that gradient and must shrink under refinement.
    // Normalization: the gross Couette inflow at the lobes' leading edges (centred value).
    let mut rels = Vec::new();
    for (ne_phi, ne_z) in [(20, 6), (40, 12)] {
        let prm = BearingParams {
            rtol: 1e-7,
            atol_pa: 1e-3,
            n_elem_phi: ne_phi,
            n_elem_z: ne_z,
            ..BearingParams::paper()
        };
        let orbit = whirl(&prm, 0.5, 400.0, 1000.0);
        let mut f = film_on_orbit(&prm, &orbit);
        let dt = 2e-6;
        let n = 250; // 0.5 ms = 1/5 whirl period
        let m0 = f.mass_times_rt_j();
        let mut q_prev = f.mass_outflow_times_rt_w();
        let mut outflow = 0.0;
        for k in 0..n {
            f.advance(k as f64 * dt, dt, &orbit).unwrap();
            let q = f.mass_outflow_times_rt_w();
            outflow += 0.5 * dt * (q + q_prev);
            q_prev = q;
        }
        // The vacuum floor adds gas where it acts; in a resolved film it must not act at all.
        assert_eq!(f.total_stats().n_pressure_floored, 0);
        let m1 = f.mass_times_rt_j();
        let lam = prm.bearing_number(orbit(0.0).omega_rad_s);
        let h_lead = (prm.bore.c_m + prm.bore.dh_m) / prm.bore.c_m;
        let gross_w = prm.p_a_pa.powi(2) * prm.bore.c_m.powi(3) / (12.0 * prm.eta_pa_s)
            * 2.0
            * 3.0
            * lam
            * h_lead
            * 0.5
            * prm.bore.b_m
            / prm.bore.r_m;
        let imbalance = m1 - m0 + outflow;
        let rel = imbalance.abs() / (gross_w * n as f64 * dt);
        println!(
            "mesh {ne_phi}x{ne_z}: mass*RT {m0:.6e} -> {m1:.6e} J, integrated net outflow {outflow:.4e} J, \
             gross inflow {:.4e} J, imbalance {imbalance:.3e} J = {rel:.2e} of the gross inflow",
            gross_w * n as f64 * dt
        );
        rels.push(rel);
    }
    println!(
        "imbalance reduction under mesh refinement: {:.2} (order {:.2})",
        rels[0] / rels[1],
        (rels[0] / rels[1]).log2()
    );
    assert!(rels[0] < 0.05);
    // Observed reduction is ~2.4 per halving (edge-gradient flux converges at ~O(h^1.3) here).
    assert!(rels[0] / rels[1] > 2.0);
}

#[test]
fn clone_and_serialized_state_continue_bit_identically() {
    let prm = BearingParams::paper();
    let orbit = whirl(&prm, 0.3, 400.0, 1000.0);
    let mut a = AirFilm::new(prm).unwrap();
    for k in 0..30 {
        a.advance(k as f64 * 1e-5, 1e-5, &orbit).unwrap();
    }
    let mut b = a.clone();
    let bytes = bincode::serialize(&a).unwrap();
    let mut c: AirFilm = bincode::deserialize(&bytes).unwrap();
    println!("serialized film state: {} bytes", bytes.len());
    for k in 30..60 {
        for f in [&mut a, &mut b, &mut c] {
            f.advance(k as f64 * 1e-5, 1e-5, &orbit).unwrap();
        }
    }
    let (oa, ob, oc) = (a.outputs(), b.outputs(), c.outputs());
    assert_eq!(oa.fx_n.to_bits(), ob.fx_n.to_bits());
    assert_eq!(oa.fy_n.to_bits(), oc.fy_n.to_bits());
    assert!(a
        .pressures_rel()
        .iter()
        .zip(c.pressures_rel())
        .all(|(x, y)| x.to_bits() == y.to_bits()));
}

/// The master's roll-back: one saved copy reused (`clone_from` both ways) across windows in which
/// the Jacobians are refactorized. A restored film must repeat the window bit for bit and, at the
/// end, match a film that was never rolled back (a skipped copy of a changed factor would not).
#[test]
fn reused_saved_state_rolls_back_bit_identically() {
    let prm = BearingParams::paper();
    let orbit = whirl(&prm, 0.3, 400.0, 1000.0);
    let h = 1e-5;
    let mut a = AirFilm::new(prm).unwrap();
    for k in 0..30 {
        a.advance(k as f64 * h, h, &orbit).unwrap();
    }
    let mut reference = a.clone();
    let mut saved = a.clone();
    let mut k = 30;
    let window = 40;
    for _round in 0..4 {
        saved.clone_from(&a);
        let jac_before = a.total_stats().n_jacobians;
        let mut first = vec![];
        for i in 0..window {
            a.advance((k + i) as f64 * h, h, &orbit).unwrap();
            first.push(a.outputs().fx_n.to_bits());
        }
        assert!(
            a.total_stats().n_jacobians > jac_before,
            "the window must refactorize for the test to mean anything"
        );
        a.clone_from(&saved);
        for (i, bits) in first.iter().enumerate() {
            a.advance((k + i) as f64 * h, h, &orbit).unwrap();
            assert_eq!(a.outputs().fx_n.to_bits(), *bits, "replayed step {i}");
        }
        for i in 0..window {
            reference.advance((k + i) as f64 * h, h, &orbit).unwrap();
        }
        k += window;
    }
    assert!(a
        .pressures_rel()
        .iter()
        .zip(reference.pressures_rel())
        .all(|(x, y)| x.to_bits() == y.to_bits()));
}

/// Under a master's macro step the film's step control alternates between one sub-step and two
/// of half its size, and the BDF coefficient c0 jumps by ~2x at every switch. Each lobe keeps a
/// factorized matrix for each size, so the switches do not refactorize; the answer stays within
/// the tolerance of a run at a quarter of the tolerance. A save and restore across the switches
/// (both matrices per lobe in play) repeats the steps bit for bit.
#[test]
fn alternating_sub_step_sizes_reuse_a_matrix_for_each() {
    let prm = BearingParams {
        rtol: 1e-3,
        atol_pa: 100.0,
        h_max_s: 50e-6,
        ..BearingParams::paper()
    };
    let orbit = whirl(&prm, 0.3, 200.0, 1000.0);
    // 50 us, 25 us, 25 us, ...: 30 cycles, 90 calls, 4.5 ms (0.9 whirl periods).
    let calls: Vec<(f64, f64)> = (0..30)
        .flat_map(|c| {
            let t = c as f64 * 100e-6;
            [(t, 50e-6), (t + 50e-6, 25e-6), (t + 75e-6, 25e-6)]
        })
        .collect();
    let run = |prm: &BearingParams, calls: &[(f64, f64)]| {
        let mut f = film_on_orbit(prm, &orbit);
        for &(t, h) in calls {
            f.advance(t, h, &orbit).unwrap();
        }
        f
    };
    // The first call climbs from the initial sub-step; every later one takes a single sub-step.
    let start = run(&prm, &calls[..1]).total_stats();
    let f = run(&prm, &calls);
    let st = f.total_stats();
    assert_eq!(st.n_steps - start.n_steps, calls.len() - 1, "{st:?}");
    // A single matrix per lobe would refactorize at each of the 59 switches (177 Jacobians).
    // Two per lobe: each refactorized when 40 steps old (89 steps: at most 3 times each), or
    // when Newton converges slowly.
    let n_lobes = 3;
    let jacobians = st.n_jacobians - start.n_jacobians;
    // Every one of them factorized without row interchanges (linsolve::GROWTH_LIMIT).
    assert_eq!(st.n_pivoted_factorizations, 0, "{st:?}");
    assert!(
        jacobians <= 8 * n_lobes,
        "{jacobians} Jacobians over 59 switches of the sub-step size: {st:?}"
    );
    let tight = BearingParams {
        rtol: 2.5e-4,
        atol_pa: 25.0,
        ..prm.clone()
    };
    let reference = run(&tight, &calls).outputs();
    let o = f.outputs();
    let scale = reference.fx_n.hypot(reference.fy_n);
    let diff = (o.fx_n - reference.fx_n).hypot(o.fy_n - reference.fy_n);
    assert!(
        diff < 1e-2 * scale,
        "force {:?} vs reference {:?}",
        (o.fx_n, o.fy_n),
        (reference.fx_n, reference.fy_n)
    );

    // Save after a third of the calls, run on, restore into the same copy, repeat.
    // Into a reused copy, as a master saves its FMU state (only changed factors are copied).
    let mut a = run(&prm, &calls[..30]);
    let mut saved = run(&prm, &calls[..3]);
    saved.clone_from(&a);
    let mut first = vec![];
    for &(t, h) in &calls[30..] {
        a.advance(t, h, &orbit).unwrap();
        first.push(a.outputs().fx_n.to_bits());
    }
    a.clone_from(&saved);
    for (i, &(t, h)) in calls[30..].iter().enumerate() {
        a.advance(t, h, &orbit).unwrap();
        assert_eq!(a.outputs().fx_n.to_bits(), first[i], "replayed call {i}");
    }
    assert_eq!(a.outputs().fx_n.to_bits(), o.fx_n.to_bits());
}

/// A Newton failure names the lobe and the cause (here a fixed step far too long for a violent
/// orbit), and the film stays at its last accepted state.
#[test]
fn newton_failure_names_lobe_and_cause() {
    let prm = BearingParams {
        fixed_step_s: 2e-4,
        ..BearingParams::paper()
    };
    let orbit = whirl(&prm, 0.97, 3000.0, 2000.0);
    let mut film = AirFilm::new(prm).unwrap();
    let mut failure = None;
    for k in 0..50 {
        if let Err(e) = film.advance(k as f64 * 2e-4, 2e-4, &orbit) {
            failure = Some((k, e));
            break;
        }
    }
    let (k, e) = failure.expect("a 200 us step on a 3 kHz whirl at eps 0.97 must fail");
    match &e {
        FilmError::NewtonFailure {
            t_reached_s,
            lobe,
            cause,
            ..
        } => {
            assert_eq!(*t_reached_s, k as f64 * 2e-4);
            assert!(*lobe < 3 && !cause.is_empty());
            assert_eq!(film.time_s(), *t_reached_s);
        }
        other => panic!("expected a Newton failure, got {other}"),
    }
    let text = e.to_string();
    assert!(
        text.contains("lobe") && text.contains("last failure"),
        "{text}"
    );
    println!("{text}");
}

#[test]
fn bad_input_gives_clear_errors() {
    let prm = BearingParams::paper();
    for (bad, name) in [
        (
            BearingParams {
                bore: Bore {
                    c_m: 0.0,
                    ..prm.bore.clone()
                },
                ..prm.clone()
            },
            "C",
        ),
        (
            BearingParams {
                bore: Bore {
                    phi_t_rad: 2.5,
                    ..prm.bore.clone()
                },
                ..prm.clone()
            },
            "phi_t",
        ),
        (
            BearingParams {
                n_elem_phi: 2,
                ..prm.clone()
            },
            "n_elem_phi",
        ),
        (
            BearingParams {
                eta_pa_s: f64::NAN,
                ..prm.clone()
            },
            "eta",
        ),
        (
            BearingParams {
                bore: Bore {
                    dh_m: 1e-6,
                    ..BearingParams::plain_bore().bore
                },
                ..BearingParams::plain_bore()
            },
            "dH",
        ),
        // Below the tolerance the Newton iteration reaches in double precision (MIN_RTOL).
        (
            BearingParams {
                rtol: 1e-11,
                ..prm.clone()
            },
            "rtol",
        ),
    ] {
        let e = AirFilm::new(bad).unwrap_err();
        println!("{e}");
        assert!(matches!(e, FilmError::InvalidParameter { name: n, .. } if n == name));
    }
    let mut f = AirFilm::new(prm.clone()).unwrap();
    let e = f
        .advance(0.0, 1e-5, &|_| JournalState::at(f64::NAN, 0.0, 100.0))
        .unwrap_err();
    println!("{e}");
    assert!(matches!(e, FilmError::InvalidInput { what: "dx", .. }));
    // Plain bore: the journal touches the ring at eps = 1.
    let mut f = AirFilm::new(BearingParams::plain_bore()).unwrap();
    let e = f
        .advance(0.0, 1e-5, &|_| {
            JournalState::at(0.0, -1.01 * prm.bore.c_m, 100.0)
        })
        .unwrap_err();
    println!("{e}");
    assert!(matches!(e, FilmError::BeyondContactLimit { .. }));
}

#[test]
fn contact_pressure_acts_below_h_con() {
    let prm = BearingParams::plain_bore();
    let om = 2.0 * PI * 1000.0;
    let s = steady_state(&prm, JournalState::at(0.0, -0.98 * prm.bore.c_m, om)).unwrap();
    let o = s.outputs;
    // Contact on the band where h < h_con: analytic penalty force for h = C (1 + 0.98 sin theta).
    let (hc, e) = (prm.contact.h_con_rel, 0.98);
    let n = 200_000;
    let mut fy = 0.0;
    for i in 0..n {
        let th = 2.0 * PI * (i as f64 + 0.5) / n as f64;
        let h = 1.0 + e * th.sin();
        if h < hc {
            fy -= prm.contact.c_con_n_per_m3 * prm.bore.c_m * (hc - h) * th.sin() * 2.0 * PI
                / n as f64;
        }
    }
    fy *= prm.bore.b_m * prm.bore.r_m;
    println!("eps 0.98 plain bore: F = ({:.3}, {:.3}) N, contact {:.3} N (reference {fy:.3} N), h_min {:.3e} m", o.fx_n, o.fy_n, o.fy_contact_n, o.h_min_m);
    assert!(o.fy_contact_n > 0.0 && ((o.fy_contact_n - fy) / fy).abs() < 1e-6);
    assert!(o.fx_n.is_finite() && o.fy_n > o.fy_contact_n);
}

#[test]
fn contact_in_force_false_leaves_exactly_the_contact_out_of_the_force() {
    // Same film, journal in the contact band: with contact_in_force = false the force output is
    // the pressure force alone; the contact force is still reported (the rotor applies it).
    let with = BearingParams::plain_bore();
    let without = BearingParams {
        contact_in_force: false,
        ..with.clone()
    };
    let j = JournalState::at(0.0, -0.98 * with.bore.c_m, 2.0 * PI * 1000.0);
    let a = steady_state(&with, j).unwrap().outputs;
    let b = steady_state(&without, j).unwrap().outputs;
    assert!(a.fy_contact_n > 1.0, "not in contact: {a:?}");
    assert_eq!(
        (b.fx_contact_n, b.fy_contact_n),
        (a.fx_contact_n, a.fy_contact_n)
    );
    // Same pressure field (the contact is not in the Reynolds equation): equal up to the
    // rounding of (F_p + F_c) - F_c.
    let tol = 1e-12 * a.fy_n.abs();
    assert!(
        (b.fx_n - (a.fx_n - a.fx_contact_n)).abs() <= tol,
        "{b:?} vs {a:?}"
    );
    assert!(
        (b.fy_n - (a.fy_n - a.fy_contact_n)).abs() <= tol,
        "{b:?} vs {a:?}"
    );
    // And the force the rotor evaluates for that displacement is the film's contact force.
    let rotor_side = fmu_airfilm::contact::contact_force_at_n(&without.bore, &without.contact, &j);
    assert_eq!(rotor_side, [a.fx_contact_n, a.fy_contact_n]);
}
