//! `airring runup --design` with a `[shaft]`: the flexible rotor co-simulated in the rotor FMU
//! that carries it. The rigid limit: the paper's rotor as a stiff shaft with its mass
//! properties (studies/stiff_shaft.toml) runs each Section 3 preset into the rigid rotor's class,
//! with onsets within 1 % and maximum eccentricities within 3 % (measured: 0.04 % and 0.3 %).
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
