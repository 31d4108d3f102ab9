//! `airring runup --design` with a `[shaft]`: the flexible rotor co-simulated in the rotor FMU
//! that carries it. The rigid limit: the paper's rotor as a stiff shaft with its mass
//! properties (studies/stiff_shaft.toml) runs each Section 3 preset into the rigid rotor's class,
//! with onsets within 1 % and maximum eccentricities within 3 % (measured: 0.04 % and 0.2 %).
//! End to end on the packed FMUs (`cargo xtask fmus` first).

mod common;

use common::airring;
use master::summary::RunSummary;

fn summary(dir: &std::path::Path) -> RunSummary {
    RunSummary::read(dir).unwrap()
}

#[test]
fn a_stiff_shaft_runs_up_as_the_rigid_rotor() {
    let design = concat!(env!("CARGO_MANIFEST_DIR"), "/../studies/stiff_shaft.toml");
    for preset in ["path1", "path2a", "path2b"] {
        let rigid = common::tmp("flexible_runup", &format!("rigid_{preset}"));
        let flexible = common::tmp("flexible_runup", &format!("flexible_{preset}"));
        // The same macro steps for both: the flexible rotor's run takes no calm steps.
        let (ok, err) = airring(&[
            "runup",
            "--preset",
            preset,
            "--calm-macro-step",
            "off",
            "--quiet",
            "--out",
            rigid.to_str().unwrap(),
        ]);
        assert!(ok, "{err}");
        let (ok, err) = airring(&[
            "runup",
            "--preset",
            preset,
            "--design",
            design,
            "--quiet",
            "--out",
            flexible.to_str().unwrap(),
        ]);
        assert!(ok, "{err}");
        assert!(err.contains("flexible rotor: 2 shaft elements"), "{err}");
        assert!(err.contains("reduced from 12 to 4 coordinates"), "{err}");
        let (r, f) = (summary(&rigid), summary(&flexible));
        // The rotor to scale, in the report.
        assert!(f.plots.as_ref().unwrap().iter().any(|p| p == "rotor.svg"));
        let report = std::fs::read_to_string(flexible.join("report.html")).unwrap();
        assert!(report.contains("rotor.svg"));
        assert_eq!(r.classification, f.classification, "{preset}");
        assert_eq!(r.classification.as_deref(), Some(preset));
        let (ro, fo) = (r.onset_speed_hz.unwrap(), f.onset_speed_hz.unwrap());
        println!(
            "{preset}: onset {ro:.2} / {fo:.2} Hz, eps_C {:?} / {:?}, eps_T {:?} / {:?}",
            r.max_eps_c, f.max_eps_c, r.max_eps_t, f.max_eps_t
        );
        assert!((fo - ro).abs() <= 0.01 * ro, "{preset} onset: {ro} {fo}");
        for (a, b) in [(r.max_eps_c, f.max_eps_c), (r.max_eps_t, f.max_eps_t)] {
            let (a, b) = (a.unwrap(), b.unwrap());
            assert!(
                (a - b).abs() <= 0.03 * a,
                "{preset} max eccentricity: {a} {b}"
            );
        }
    }
}

/// A shaft the rotor FMU cannot take is refused before the run, naming the design file, the
/// entry and what to do.
#[test]
fn a_bad_shaft_is_refused_before_the_run() {
    let dir = common::tmp("flexible_runup", "bad");
    std::fs::create_dir_all(&dir).unwrap();
    let design = dir.join("shaft.toml");
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../studies/stiff_shaft.toml"
    ))
    .unwrap();
    // An imbalance must sit at a node of the shaft.
    std::fs::write(&design, &text).unwrap();
    let out = dir.join("run");
    let (ok, err) = airring(&[
        "runup",
        "--design",
        design.to_str().unwrap(),
        "--imbalance-c",
        "0.1,10,0",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("shaft.toml") && err.contains("z_imb_C") && err.contains("node"),
        "{err}"
    );
    assert!(!out.join("summary.json").exists());
    // Both bearings on one node.
    std::fs::write(&design, text.replace("compressor = 2", "compressor = 0")).unwrap();
    let (ok, err) = airring(&[
        "runup",
        "--design",
        design.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("node 0"), "{err}");
}

/// Orbits of a flexible rotor: the stiff shaft's whirl orbit of path 2a at 520 Hz (its state the
/// reduced shaft's and the rings' coordinates and rates) is the rigid rotor's: both stable, the
/// whirl frequency within 1 %, the largest eccentricities within 3 %.
#[test]
fn a_stiff_shafts_orbit_is_the_rigid_rotors() {
    use master::orbits::driver::{find_orbits, OrbitsRequest};
    use master::runup::RunupSettings;
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../studies/stiff_shaft.toml"
    ))
    .unwrap();
    let table: toml::Table = text.parse().unwrap();
    let shaft = master::design::shaft::parse(table["shaft"].as_table().unwrap(), None).unwrap();
    let mut orbits = vec![];
    for flexible in [false, true] {
        let mut settings = RunupSettings::preset("path2a").unwrap();
        if flexible {
            settings.shaft = Some(shaft.clone());
        }
        let dir = common::tmp("flexible_runup", &format!("orbit_{flexible}"));
        let req = OrbitsRequest {
            settings,
            speeds_hz: vec![520.0],
            settle_s: 1.0,
            continuation: false,
            full_state: false,
            fmu_dir: common::root().join("target/fmu"),
            out_dir: dir.clone(),
        };
        let report = find_orbits(&req, &mut |line| eprintln!("{line}")).unwrap();
        assert_eq!(report.orbits.len(), 1, "flexible {flexible}: {report:?}");
        orbits.push(report.orbits[0].clone());
        let _ = std::fs::remove_dir_all(&dir);
    }
    let (r, f) = (&orbits[0], &orbits[1]);
    println!("rigid {r:?}\nflexible {f:?}");
    assert!(r.stable && f.stable);
    assert!((r.whirl_frequency_hz - f.whirl_frequency_hz).abs() <= 0.01 * r.whirl_frequency_hz);
    for (a, b) in [(r.max_eps_c, f.max_eps_c), (r.max_eps_t, f.max_eps_t)] {
        assert!(
            (a - b).abs() <= 0.03 * a,
            "max eccentricity {a} against {b}"
        );
    }
}

/// A study's linear map of a flexible rotor: the stiff shaft's predicted threshold speeds are the
/// rigid rotor's (within 1 %), cell by cell.
#[test]
fn a_stiff_shafts_linear_map_is_the_rigid_rotors() {
    let dir = common::tmp("flexible_runup", "linear_map");
    std::fs::create_dir_all(&dir).unwrap();
    let design = concat!(env!("CARGO_MANIFEST_DIR"), "/../studies/stiff_shaft.toml");
    let mut thresholds = vec![];
    for (name, fixed) in [
        ("rigid", String::new()),
        ("flexible", format!("design = \"{design}\"\n")),
    ] {
        let study = dir.join(format!("{name}.toml"));
        std::fs::write(
            &study,
            format!(
                "name = \"{name}\"\n[fixed]\npreset = \"path1\"\n{fixed}\n[[grid]]\n\
                 cases = [{{ clearance = 20, dh = 40 }}]\nc = [500, 1500]\n"
            ),
        )
        .unwrap();
        let out = dir.join(name);
        let (ok, err) = airring(&[
            "sweep",
            study.to_str().unwrap(),
            "--linear",
            "--speeds",
            "200:2000:100",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{name}: {err}");
        let csv = std::fs::read_to_string(out.join("study_linear.csv")).unwrap();
        let t: Vec<f64> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().parse::<f64>().unwrap())
            .collect();
        assert_eq!(t.len(), 2, "{csv}");
        thresholds.push(t);
    }
    println!(
        "thresholds: rigid {:?}, stiff shaft {:?}",
        thresholds[0], thresholds[1]
    );
    for (r, f) in thresholds[0].iter().zip(&thresholds[1]) {
        assert!((r - f).abs() <= 0.01 * r, "{r} {f}");
    }
}
