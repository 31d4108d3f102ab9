//! Modal analysis of paper Section 2.3: c = 500 N/mm, d = 0, isotropic film springs 2000 N/mm,
//! undamped. Campbell data, the speed at which the paper's table is matched, mode shapes.
use fmu_rotor::linear::*;
use fmu_rotor::*;
use std::f64::consts::PI;

/// Paper values, ascending: Mode1 b/f, Mode2 b/f, Mode3 b/f, Mode4 b/f [Hz].
const PAPER_HZ: [f64; 8] = [125.0, 145.0, 156.0, 181.0, 1161.0, 1162.0, 1176.0, 1179.0];
const PAPER_WHIRL: [Whirl; 8] = [
    Whirl::Backward,
    Whirl::Forward,
    Whirl::Backward,
    Whirl::Forward,
    Whirl::Backward,
    Whirl::Forward,
    Whirl::Backward,
    Whirl::Forward,
];

fn section_2_3() -> (RotorParams, [FilmCoefficients; 2]) {
    let mut p = RotorParams::paper();
    p.c_c_n_m = 5e5;
    p.c_t_n_m = 5e5;
    p.d_c_n_s_m = 0.0;
    p.d_t_n_s_m = 0.0;
    (p, [FilmCoefficients::isotropic(2e6, 0.0); 2])
}

fn modes_at(f_hz: f64) -> Vec<Mode> {
    let (p, films) = section_2_3();
    modes(&lateral_matrices(&p, 2.0 * PI * f_hz, &films)).unwrap()
}

fn wl(w: Whirl) -> &'static str {
    match w {
        Whirl::Forward => "f",
        Whirl::Backward => "b",
    }
}

#[test]
fn campbell_and_paper_match() {
    println!("Campbell data (Hz; b = backward, f = forward whirl):");
    for f in (0..=2000).step_by(250) {
        let ms = modes_at(f as f64);
        assert_eq!(ms.len(), 8);
        let s: Vec<String> = ms
            .iter()
            .map(|m| format!("{:7.1}{}", m.freq_hz, wl(m.whirl)))
            .collect();
        println!("Omega = {f:4} Hz: {}", s.join(" "));
        for m in &ms {
            assert!(
                m.damping_ratio.abs() < 1e-6,
                "undamped system must have zero damping"
            );
        }
    }
    // Speed scan: RMS relative deviation from the paper's eight values.
    let dev = |f: f64| {
        let ms = modes_at(f);
        (ms.iter()
            .zip(PAPER_HZ)
            .map(|(m, p)| ((m.freq_hz - p) / p).powi(2))
            .sum::<f64>()
            / 8.0)
            .sqrt()
    };
    let (mut best_f, mut best) = (0.0, f64::INFINITY);
    for f in (0..=2000).step_by(5) {
        let d = dev(f as f64);
        if d < best {
            best = d;
            best_f = f as f64;
        }
    }
    println!(
        "best match at Omega = {best_f} Hz: RMS relative deviation {:.3} %",
        100.0 * best
    );
    let ms = modes_at(best_f);
    for (i, m) in ms.iter().enumerate() {
        println!(
            "  {:7.1} Hz {} (paper {:6.0} {}): {}",
            m.freq_hz,
            wl(m.whirl),
            PAPER_HZ[i],
            wl(PAPER_WHIRL[i]),
            m.shape.describe()
        );
        assert_eq!(m.whirl, PAPER_WHIRL[i], "whirl label of mode {i}");
        assert!(
            (m.freq_hz - PAPER_HZ[i]).abs() / PAPER_HZ[i] < 0.01,
            "mode {i}: {} vs {}",
            m.freq_hz,
            PAPER_HZ[i]
        );
    }
    assert!((best_f - 1000.0).abs() <= 50.0, "best speed {best_f}");
    // Shapes at 1000 Hz from our eigenvectors (see MODAL.md): the lower rotor pair has its node
    // near the turbine-side journal, the upper pair near the compressor-side journal; the 1161 Hz
    // pair is the compressor-side ring, the 1177 Hz pair the turbine-side ring.
    let nodes: String = ms.iter().map(|m| m.shape.node()).collect();
    assert_eq!(nodes, "TTCCTTCC");
    let z_cm = 0.125;
    assert!(
        ms[0].shape.rotor_node_z_m < z_cm && ms[1].shape.rotor_node_z_m < z_cm,
        "mode 1: node on the turbine side"
    );
    assert!(
        ms[2].shape.rotor_node_z_m > z_cm && ms[3].shape.rotor_node_z_m > z_cm,
        "mode 2: node on the compressor side"
    );
    for m in &ms[4..6] {
        assert!(
            (m.shape.rotor_node_z_m - 0.060).abs() < 0.015,
            "mode 3: rotor pivots about the T journal"
        );
    }
    for m in &ms[6..8] {
        assert!(
            (m.shape.rotor_node_z_m - 0.170).abs() < 0.015,
            "mode 4: rotor pivots about the C journal"
        );
    }
    for m in &ms[4..6] {
        let a = m.shape.amplitudes();
        assert!(a[2] > 0.99 && a[3] < 0.2, "mode 3 is the C ring");
    }
    for m in &ms[6..8] {
        let a = m.shape.amplitudes();
        assert!(a[3] > 0.99 && a[2] < 0.2, "mode 4 is the T ring");
    }
}

#[test]
fn linearization_matches_analytic_matrices() {
    // Hand-built 8-DOF matrices (the same physics as the minimal-coordinate test).
    let (p, films) = section_2_3();
    let om = 2.0 * PI * 1000.0;
    let lm = lateral_matrices(&p, om, &films);
    let (ac, at) = (lm.a_c_m, lm.a_t_m);
    assert!((lm.m[0][0] - p.m_kg).abs() < 1e-12 && (lm.m[2][2] - p.j_t_kg_m2).abs() < 1e-12);
    assert!(
        (lm.g[2][3] - p.j_p_kg_m2 * om).abs() < 1e-9
            && (lm.g[3][2] + p.j_p_kg_m2 * om).abs() < 1e-9
    );
    let kf = 2e6;
    // rotor y row: 2 kf y - kf (ac + at) alpha - kf (y_RC + y_RT)
    assert!((lm.k[1][1] - 2.0 * kf).abs() < 1e-3 * kf);
    assert!((lm.k[1][2] + kf * (ac + at)).abs() < 1e-3 * kf);
    assert!((lm.k[2][2] - kf * (ac * ac + at * at)).abs() < 1e-6 * kf);
    assert!((lm.k[5][5] - (kf + 5e5)).abs() < 1e-3 * kf);
    let dmax = lm.d.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(dmax < 1e-6, "no damping in this case: {dmax}");
}

/// `real_eigenvalues` completes `modes`: every eigenvalue is either an oscillating mode (with its
/// conjugate) or real, and a negative film stiffness (a statically unstable bearing) shows as a
/// positive real eigenvalue, which `modes` alone would never reveal.
#[test]
fn real_eigenvalues_complete_the_modes_and_reveal_a_divergence() {
    let (p, films) = section_2_3();
    let lm = lateral_matrices(&p, 2.0 * PI * 1000.0, &films);
    assert_eq!(modes(&lm).unwrap().len(), 8);
    assert!(
        real_eigenvalues(&lm).unwrap().is_empty(),
        "undamped: all oscillate"
    );

    // Films pushing the journal away from the centre, no damping, no spin: a conservative system
    // with negative-stiffness directions, so its real eigenvalues come in pairs +-sqrt(mu)
    // (x and y stiffnesses differ, so no eigenvalue is double).
    let neg = [FilmCoefficients {
        k_n_m: [[-1e5, 0.0], [0.0, -2e5]],
        d_n_s_m: [[0.0; 2]; 2],
    }; 2];
    let lm = lateral_matrices(&p, 0.0, &neg);
    let osc = modes(&lm).unwrap().len();
    let mut real = real_eigenvalues(&lm).unwrap();
    assert_eq!(2 * osc + real.len(), 16, "{osc} modes, real {real:?}");
    real.sort_by(f64::total_cmp);
    assert!(real.last().copied().unwrap() > 1.0, "divergence: {real:?}");
    for (a, b) in real.iter().zip(real.iter().rev()) {
        assert!(
            (a + b).abs() < 1e-6 * a.abs().max(1.0),
            "pairs +-: {real:?}"
        );
    }
}
