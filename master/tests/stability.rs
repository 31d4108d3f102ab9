//! Linear stability analysis (master::stability) on a coarse film mesh: statics of the journal
//! loads, the equilibrium carries them, 8 modes per speed, and path 1's threshold is bracketed.

use master::runup::RunupSettings;
use master::stability::equilibrium::journal_loads_n;
use master::stability::{analyse, params_of, parse_speeds};

#[test]
fn path1_equilibrium_modes_and_threshold() {
    let mut s = RunupSettings::preset("path1").unwrap();
    s.n_elem_phi = 10;
    s.n_elem_z = 4;
    let (rotor, _) = params_of(&s);
    let loads = journal_loads_n(&rotor);
    // Force and moment balance of the rigid rotor.
    let w = rotor.m_kg * rotor.g_m_s2;
    assert!((loads[0][1] + loads[1][1] - w).abs() < 1e-12);
    let m =
        loads[0][1] * (rotor.z_jc_m - rotor.z_cm_m) + loads[1][1] * (rotor.z_jt_m - rotor.z_cm_m);
    assert!(m.abs() < 1e-12);

    let speeds = parse_speeds("300:700:400").unwrap();
    assert_eq!(speeds, vec![300.0, 700.0]);
    let r = analyse(&s, &speeds).unwrap();
    for sp in &r.speeds {
        assert_eq!(sp.modes.len(), 8);
        for (b, load) in sp.bearings.iter().zip(loads) {
            assert!((b.load_n[1] - load[1]).abs() < 1e-9);
            // The journal sits below the ring centre and off to the side (attitude angle).
            assert!(b.dy_um < 0.0 && b.eps > 0.05 && b.eps < 1.0, "{b:?}");
        }
        // Distinct self-consistent modes (no two ranks on one eigenvalue).
        for w in sp.modes.windows(2) {
            assert!(w[1].freq_hz - w[0].freq_hz > 1e-3 || w[1].damping_ratio != w[0].damping_ratio);
        }
    }
    let t = r
        .threshold
        .expect("path 1 turns unstable between 300 and 700 Hz");
    println!(
        "threshold {:.1} Hz, {} whirl at {:.1} Hz, wall {:.2} s",
        t.speed_hz, t.mode.whirl, t.mode.freq_hz, r.wall_time_s
    );
    assert!(t.speed_hz > 300.0 && t.speed_hz < 700.0);
    assert_eq!(t.mode.whirl, "forward");
    assert!(t.whirl_ratio > 0.2 && t.whirl_ratio < 0.6);
}
