//! Linear stability analysis (master::stability) on a coarse film mesh: statics of the journal
//! loads, the equilibrium carries them (checked by an independent steady film solution at the
//! reported journal position), the locus moves towards the centre with speed, 8 modes per speed,
//! and path 1's threshold is bracketed. `airring stability --out` writes its report and figures.

use fmu_airfilm::{steady_state, JournalState};
use master::runup::RunupSettings;
use master::stability::equilibrium::journal_loads_n;
use master::stability::{analyse, params_of, parse_speeds};
use std::f64::consts::TAU;
use std::process::Command;

#[test]
fn path1_equilibrium_modes_and_threshold() {
    let mut s = RunupSettings::preset("path1").unwrap();
    s.n_elem_phi = 10;
    s.n_elem_z = 4;
    let (rotor, films) = params_of(&s).unwrap();
    let film = &films[0];
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
            // An independent steady film solution at the reported journal position carries the
            // load (the Newton tolerance is 1e-7 of |load|; the um rounding of the report adds
            // nothing at this level).
            let j = JournalState::at(b.dx_um * 1e-6, b.dy_um * 1e-6, TAU * sp.speed_hz);
            let f = steady_state(film, j).unwrap().outputs;
            let w = load[0].hypot(load[1]);
            assert!(
                (f.fx_n - load[0]).abs() < 1e-5 * w && (f.fy_n - load[1]).abs() < 1e-5 * w,
                "{} Hz: film force ({}, {}) N vs load {load:?} N",
                sp.speed_hz,
                f.fx_n,
                f.fy_n
            );
            assert!((f.eps - b.eps).abs() < 1e-9, "eps {} vs {}", f.eps, b.eps);
            // The journal sits below the ring centre and off to the side (attitude angle).
            assert!(b.dy_um < 0.0 && b.eps > 0.05 && b.eps < 1.0, "{b:?}");
        }
        // Distinct self-consistent modes (no two ranks on one eigenvalue).
        for w in sp.modes.windows(2) {
            assert!(w[1].freq_hz - w[0].freq_hz > 1e-3 || w[1].damping_ratio != w[0].damping_ratio);
        }
    }
    // A faster film carries the same load at a smaller eccentricity (the bearing number grows).
    for b in 0..2 {
        let (lo, hi) = (&r.speeds[0].bearings[b], &r.speeds[1].bearings[b]);
        assert!(hi.eps < lo.eps, "bearing {b}: eps {} -> {}", lo.eps, hi.eps);
    }
    let t = r
        .threshold
        .expect("path 1 turns unstable between 300 and 700 Hz");
    println!(
        "threshold {:.1} Hz, {} whirl at {:.1} Hz, wall {:.2} s",
        t.speed_hz, t.mode.whirl, t.mode.freq_hz, r.wall_time_s
    );
    // docs/stability.md: 472.9 Hz on the paper mesh, 473.2 / 473.6 Hz on 10x3 / 8x2; a mesh
    // between them must land within a few Hz (the bisection's own tolerance is 0.5 Hz).
    assert!(
        (t.speed_hz - 473.0).abs() < 3.0,
        "threshold {} Hz",
        t.speed_hz
    );
    assert_eq!(t.mode.whirl, "forward");
    assert!(t.whirl_ratio > 0.2 && t.whirl_ratio < 0.6);
}

fn series_points(doc: &roxmltree::Document) -> Vec<(String, usize)> {
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("class") == Some("series"))
        .map(|n| {
            let name = n.attribute("data-name").unwrap_or("").to_string();
            let pts = n
                .attribute("points")
                .unwrap_or("")
                .split_whitespace()
                .count();
            (name, pts)
        })
        .collect()
}

/// `airring stability --out DIR`: stability.json with the equilibria per speed, and the four
/// figures (SVG + PNG): Campbell and damping with one line per mode, the journal locus of both
/// bearings in the bore (with its three lobe contours) and the eccentricity vs speed.
#[test]
fn stability_command_writes_report_and_figures() {
    let dir = std::env::temp_dir().join(format!("airring-stability-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args([
            "stability",
            "--mesh",
            "8x2",
            "--speeds",
            "300:1500:600",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("stability.json")).unwrap())
            .unwrap();
    let speeds = json["report"]["speeds"].as_array().unwrap();
    assert_eq!(speeds.len(), 3);
    for sp in speeds {
        for b in sp["bearings"].as_array().unwrap() {
            let (dx, dy) = (b["dx_um"].as_f64().unwrap(), b["dy_um"].as_f64().unwrap());
            let eps = b["eps"].as_f64().unwrap();
            // Clearance 20 um (path-1 preset): |d| / C is the reported eccentricity.
            assert!((dx.hypot(dy) / 20.0 - eps).abs() < 1e-9, "{b}");
        }
    }
    // The films' friction at the equilibria: power = torque * omega, growing with speed (at
    // least linearly: Petroff's torque alone grows with speed).
    let loss = |k: usize| speeds[k]["bearings"][0]["power_loss_w"].as_f64().unwrap();
    for (k, sp) in speeds.iter().enumerate() {
        let b = &sp["bearings"][0];
        let omega = std::f64::consts::TAU * sp["speed_hz"].as_f64().unwrap();
        let torque_nm = b["friction_torque_nmm"].as_f64().unwrap() * 1e-3;
        assert!((loss(k) - torque_nm * omega).abs() <= 1e-9 * loss(k), "{b}");
    }
    assert!(loss(0) > 0.0 && loss(1) > 3.0 * loss(0) && loss(2) > 1.6 * loss(1));
    // Oscillating modes per speed: a Campbell line per mode rank, broken where a speed has
    // fewer modes (overdamped there), so the lines hold exactly the modes of stability.json.
    let per_speed: Vec<usize> = speeds
        .iter()
        .map(|s| s["modes"].as_array().unwrap().len())
        .collect();
    let ranks = *per_speed.iter().max().unwrap();
    let total: usize = per_speed.iter().sum();
    for stem in ["campbell", "damping", "locus", "eccentricity"] {
        let text = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
        let bad = master::plot::layout::problems(&text);
        assert!(bad.is_empty(), "{stem}: {bad:#?}");
        let doc = roxmltree::Document::parse(&text).unwrap();
        let s = series_points(&doc);
        let mut names: Vec<&str> = s.iter().map(|(n, _)| n.as_str()).collect();
        names.dedup();
        let points: usize = s.iter().map(|(_, n)| n).sum();
        if stem == "campbell" || stem == "damping" {
            assert_eq!(names.len(), ranks, "{stem}: {s:?}");
            assert_eq!(points, total, "{stem}: {s:?} vs {per_speed:?}");
        } else {
            assert_eq!(names, ["bearing C", "bearing T"], "{stem}");
            assert!(
                s.iter().all(|(_, n)| *n == 3),
                "{stem}: a point per speed: {s:?}"
            );
        }
        if stem == "locus" {
            let lobes = doc
                .descendants()
                .filter(|n| n.attribute("class") == Some("lobe"))
                .count();
            assert_eq!(lobes, 3);
        }
        let png = std::fs::read(dir.join(format!("{stem}.png"))).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{stem}.png");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs()
}

/// The linear model takes its parameters through the FMUs' own variable tables and mapping, from
/// the parameters the run-up's system file would give each instance: the preset's values, and
/// any `--set` FMU parameter on top, per film where asked.
#[test]
fn linear_model_reads_parameters_as_the_fmus_do() {
    let mut s = RunupSettings::preset("path2b").unwrap();
    let (rotor, films) = params_of(&s).unwrap();
    assert!(close(rotor.c_c_n_m, 1e5) && close(rotor.c_t_n_m, 1e5));
    assert!(close(rotor.m_r_c_kg, 0.15) && close(rotor.d_c_n_s_m, 50.0));
    for f in &films {
        assert!(
            close(f.bore.c_m, 20e-6) && close(f.bore.dh_m, 40e-6),
            "{f:?}"
        );
        assert_eq!((f.n_elem_phi, f.n_elem_z), (20, 6));
        // The contact is part of the linearized film wherever a run-up evaluates it.
        assert!(f.contact_in_force);
    }
    s.fmu_parameters = vec![
        ("film_T.C".into(), "25 um".into()),
        ("film.eta".into(), "2e-5".into()),
        ("rotor.c_C".into(), "1500 N/mm".into()),
    ];
    let (rotor, films) = params_of(&s).unwrap();
    assert!(close(rotor.c_c_n_m, 1.5e6) && close(rotor.c_t_n_m, 1e5));
    assert!(close(films[0].bore.c_m, 20e-6) && close(films[1].bore.c_m, 25e-6));
    assert!(close(films[0].eta_pa_s, 2e-5) && close(films[1].eta_pa_s, 2e-5));
    s.fmu_parameters = vec![("film.viscosity".into(), "1".into())];
    assert!(params_of(&s).unwrap_err().contains("viscosity"));
    // A ring without mount stiffness has no static position: a clear error, not NaN positions.
    s.fmu_parameters.clear();
    s.c_n_per_mm = 0.0;
    let e = analyse(&s, &[500.0]).unwrap_err();
    assert!(e.contains("c > 0"), "{e}");
}

/// Least-squares fit of v(t) = a + b (t - tc) + Re(X e^{i psi(t)}) over the samples: X.
fn synchronous_amplitude(t: &[f64], psi: &[f64], v: &[f64], tc: f64) -> (f64, f64) {
    // Columns 1, t - tc, cos psi, -sin psi (X = c2 + i c3); 4x4 normal equations, Gauss elimination.
    let rows: Vec<[f64; 4]> = t
        .iter()
        .zip(psi)
        .map(|(t, p)| [1.0, t - tc, p.cos(), -p.sin()])
        .collect();
    let mut a = [[0.0; 5]; 4];
    for (r, y) in rows.iter().zip(v) {
        for i in 0..4 {
            for j in 0..4 {
                a[i][j] += r[i] * r[j];
            }
            a[i][4] += r[i] * y;
        }
    }
    for k in 0..4 {
        let p = (k..4)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap();
        a.swap(k, p);
        for i in k + 1..4 {
            let f = a[i][k] / a[k][k];
            for j in k..5 {
                a[i][j] -= f * a[k][j];
            }
        }
    }
    let mut x = [0.0; 4];
    for k in (0..4).rev() {
        let s: f64 = (k + 1..4).map(|j| a[k][j] * x[j]).sum();
        x[k] = (a[k][4] - s) / a[k][k];
    }
    (x[2], x[3])
}

/// The unbalance response of the linear model against a nonlinear run-up with the same small
/// imbalance (0.01 g at 20 mm on the compressor wheel, no disturbance, 8x2 mesh) at three speeds
/// below the threshold: the run-up's synchronous orbit (least-squares fit over 10 ms where it passes
/// each speed) matches the linear prediction within 2 % in amplitude and 2 degrees in phase
/// (measured: 0.1-0.4 %, 0.0 degrees).
#[test]
fn unbalance_response_matches_a_nonlinear_runup_in_the_linear_regime() {
    let dir = std::env::temp_dir().join(format!("airring-unbalance-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_airring"))
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let lin = dir.join("linear");
    let nonlin = dir.join("runup");
    let (l, n) = (lin.to_str().unwrap(), nonlin.to_str().unwrap());
    let imbalance = "0.01,20,0";
    run(&[
        "stability",
        "--mesh",
        "8x2",
        "--speeds",
        "250:450:100",
        "--unbalance-c",
        imbalance,
        "--out",
        l,
    ]);
    run(&[
        "runup",
        "--mesh",
        "8x2",
        "--disturbance",
        "0",
        "--imbalance-c",
        imbalance,
        "--stop",
        "0.7",
        "--output-interval",
        "50",
        "--quiet",
        "--out",
        n,
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(lin.join("stability.json")).unwrap())
            .unwrap();
    let points = json["unbalance"]["points"].as_array().unwrap();
    assert_eq!(points.len(), 3);
    for stem in ["unbalance_amplitude", "unbalance_phase"] {
        assert!(
            lin.join(format!("{stem}.svg")).exists() && lin.join(format!("{stem}.png")).exists()
        );
        let svg = std::fs::read_to_string(lin.join(format!("{stem}.svg"))).unwrap();
        let bad = master::plot::layout::problems(&svg);
        assert!(bad.is_empty(), "{stem}: {bad:#?}");
    }
    // The run-up's series and its spin angle (trapezoid of omega).
    let csv = std::fs::read_to_string(nonlin.join("timeseries.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let col = |name: &str| {
        let k = header
            .iter()
            .position(|h| h.starts_with(&format!("{name} [")))
            .unwrap();
        rows.iter().map(|r| r[k]).collect::<Vec<f64>>()
    };
    let t = col("time");
    let omega = col("rotor.omega");
    let mut psi = vec![0.0; t.len()];
    for i in 1..t.len() {
        psi[i] = psi[i - 1] + 0.5 * (omega[i] + omega[i - 1]) * (t[i] - t[i - 1]);
    }
    for p in points {
        let f = p["speed_hz"].as_f64().unwrap();
        let tc = f / 2000.0 * 3.0; // the preset's ramp: 2000 Hz in 3 s
        let idx: Vec<usize> = (0..t.len())
            .filter(|&i| (t[i] - tc).abs() < 0.005)
            .collect();
        let pick = |v: &[f64]| idx.iter().map(|&i| v[i]).collect::<Vec<f64>>();
        let (tw, pw) = (pick(&t), pick(&psi));
        for (point, xs, ys) in [
            ("journal_c", "rotor.x_JC", "rotor.y_JC"),
            ("journal_t", "rotor.x_JT", "rotor.y_JT"),
            ("ring_c", "rotor.x_RC", "rotor.y_RC"),
        ] {
            let (xr, xi) = synchronous_amplitude(&tw, &pw, &pick(&col(xs)), tc);
            let (yr, yi) = synchronous_amplitude(&tw, &pw, &pick(&col(ys)), tc);
            // Semi-major axis of the orbit, as the linear report gives it.
            let a = 0.5 * (xr * xr + xi * xi + yr * yr + yi * yi);
            let (zr, zi) = (
                xr * xr - xi * xi + yr * yr - yi * yi,
                2.0 * (xr * xi + yr * yi),
            );
            let semi_major_um = (a + 0.5 * zr.hypot(zi)).sqrt() * 1e6;
            let phase_deg = xi.atan2(xr).to_degrees();
            let lin_um = p[point]["semi_major_um"].as_f64().unwrap();
            let lin_deg = p[point]["x_phase_deg"].as_f64().unwrap();
            assert!(
                (semi_major_um - lin_um).abs() <= 0.02 * lin_um,
                "{f} Hz {point}: run-up {semi_major_um:.4} um, linear {lin_um:.4} um"
            );
            let dphase = (phase_deg - lin_deg + 540.0).rem_euclid(360.0) - 180.0;
            assert!(
                dphase.abs() <= 2.0,
                "{f} Hz {point}: {phase_deg:.1} vs {lin_deg:.1} deg"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each way a `--speeds` grid can be wrong is named (it was always "expected from:to:step"), a
/// grid of more than `MAX_SPEEDS` analyses is refused, and one speed is a grid too.
#[test]
fn speed_grids_parse_or_say_what_is_wrong() {
    assert_eq!(
        parse_speeds("100:200:50").unwrap(),
        vec![100.0, 150.0, 200.0]
    );
    assert_eq!(parse_speeds("500").unwrap(), vec![500.0]);
    for (spec, why) in [
        ("0:100:50", "the speeds must be > 0 Hz (from = 0)"),
        ("100:50:10", "to = 50 Hz lies below from = 100 Hz"),
        ("100:200:0", "the step must be > 0 Hz (step = 0)"),
        (
            "1:1e9:1e8",
            "the speeds must be at most 20000 Hz (to = 1000000000)",
        ),
        ("nan:200:50", "from must be a finite number of Hz"),
        ("100:abc:50", "to 'abc' is not a number (Hz)"),
        (
            "100:200",
            "expected from:to:step in Hz (e.g. 100:2000:50) or one speed",
        ),
        ("10:20:0.001", "10001 speeds, at most 1000"),
    ] {
        let e = parse_speeds(spec).unwrap_err();
        assert!(
            e.contains(why) && e.starts_with(&format!("--speeds '{spec}'")),
            "{spec}: {e}"
        );
    }
}
