//! The linear stability analysis of a flexible rotor in air ring bearings, in the rigid limit:
//! the paper's rotor as a massless, very stiff shaft with its mass and inertias as a disk
//! (`master::flexible::stiff_shaft_of`) in the path-1 bearings gives the rigid rotor's
//! equilibria, modes and threshold speed. Coarse film mesh (10 x 4): the comparison is between
//! two rotor models on one film.

use master::runup::RunupSettings;
use master::stability::{analyse, analyse_flexible, params_of};

#[test]
fn a_stiff_shaft_in_the_path1_bearings_has_the_rigid_rotors_threshold_and_modes() {
    let mut s = RunupSettings::preset("path1").unwrap();
    s.n_elem_phi = 10;
    s.n_elem_z = 4;
    let speeds = [300.0, 700.0];
    let rigid = analyse(&s, &speeds).unwrap();
    let (p, _) = params_of(&s).unwrap();
    let model = master::flexible::stiff_shaft_of(&p);
    // Bearing C (compressor journal) is node 2, T node 0.
    let (flexible, solved, rotor) = analyse_flexible(&s, model, [2, 0], &speeds).unwrap();
    for (r, f) in rigid.speeds.iter().zip(&flexible.speeds) {
        for b in 0..2 {
            let (er, ef) = (r.bearings[b].eps, f.bearings[b].eps);
            // The stiff shaft adds 4e-5 of the rotor's mass (and moves its centre of mass by as
            // little): eps moves by about 2e-5.
            assert!(
                (er - ef).abs() < 1e-4,
                "{} Hz bearing {b}: eps {er} vs {ef}",
                r.speed_hz
            );
        }
        // The flexible analysis follows the modes below twice the highest speed (1400 Hz).
        let n = f.modes.len().min(r.modes.len());
        assert!(n >= 6, "{} Hz: {} modes", r.speed_hz, f.modes.len());
        for (mr, mf) in r.modes.iter().zip(&f.modes).take(n) {
            assert!(
                (mr.freq_hz - mf.freq_hz).abs() < 0.1,
                "{} Hz: {} vs {} Hz",
                r.speed_hz,
                mr.freq_hz,
                mf.freq_hz
            );
            assert!(
                (mr.growth_per_s - mf.growth_per_s).abs() < 0.1 + 1e-3 * mr.growth_per_s.abs(),
                "{} Hz, mode at {} Hz: growth {} vs {} 1/s",
                r.speed_hz,
                mr.freq_hz,
                mr.growth_per_s,
                mf.growth_per_s
            );
            assert_eq!(
                mr.whirl, mf.whirl,
                "{} Hz, mode at {} Hz",
                r.speed_hz, mr.freq_hz
            );
        }
    }
    let (tr, tf) = (
        rigid
            .threshold
            .as_ref()
            .expect("path 1 turns unstable between 300 and 700 Hz"),
        flexible
            .threshold
            .as_ref()
            .expect("so does the stiff shaft"),
    );
    assert!(
        (tr.speed_hz - tf.speed_hz).abs() <= 0.01 * tr.speed_hz,
        "threshold {} vs {} Hz",
        tr.speed_hz,
        tf.speed_hz
    );
    assert_eq!(tr.mode.whirl, tf.mode.whirl);

    // The unbalance response in the films: an imbalance at the centre of mass (the rigid rotor's
    // compressor imbalance moved there; the flexible rotor's at the disk node), 0.1 g at 10 mm.
    let mut s_imb = s.clone();
    s_imb
        .fmu_parameters
        .push(("rotor.z_imb_C".into(), format!("{}", p.z_cm_m)));
    s_imb.imbalance_c = (0.1, 10.0, 0.0);
    let (p_imb, _) = params_of(&s_imb).unwrap();
    let (rigid_r, rigid_solved) =
        master::stability::analyse_with_equilibria(&s_imb, &speeds).unwrap();
    let rigid_u = master::stability::unbalance::unbalance_report(
        &p_imb,
        [s_imb.imbalance_c, (0.0, 0.0, 0.0)],
        &rigid_r.speeds,
        &rigid_solved,
    )
    .unwrap();
    let flex_u = master::stability::unbalance::flexible_unbalance_report(
        &rotor,
        (1, 0.1 * 10.0, 0.0),
        &flexible.speeds,
        &solved,
    )
    .unwrap();
    assert_eq!(flex_u.points.len(), speeds.len());
    for (a, b) in rigid_u.points.iter().zip(&flex_u.points) {
        for (x, y, what) in [
            (&a.journal_c, &b.journal_c, "J_C"),
            (&a.journal_t, &b.journal_t, "J_T"),
            (&a.ring_c, &b.ring_c, "R_C"),
        ] {
            assert!(
                (x.semi_major_um - y.semi_major_um).abs() <= 1e-3 * x.semi_major_um,
                "{} Hz {what}: {} vs {} um",
                a.speed_hz,
                x.semi_major_um,
                y.semi_major_um
            );
        }
    }
}

/// The same stiff shaft written out as a design file's `[shaft]` table (units as an engineer
/// writes them) through `airring stability --design`: the rigid rotor's threshold again; a run-up
/// takes the design as its flexible rotor (the rotor FMU reduces it to the journals' four
/// coordinates: its bending modes lie far above any cut-off).
#[test]
fn a_design_files_shaft_table_is_the_flexible_rotor_of_stability_and_runups() {
    use clap::Parser;
    #[derive(Parser)]
    struct Flags {
        #[command(flatten)]
        args: master::stability::cli::StabilityArgs,
    }
    let p = fmu_rotor::RotorParams::paper();
    let dir = std::env::temp_dir().join(format!("airring-shaft-design-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let design = dir.join("design.toml");
    std::fs::write(
        &design,
        format!(
            "[shaft]\nmaterial = {{ rho = \"1 kg/m3\", E = \"211000 GPa\", G = \"81200 GPa\" }}\n\
             elements = [{{ L = \"{} mm\", od = \"20 mm\" }}, {{ L = \"{} mm\", od = \"20 mm\" }}]\n\
             disks = [{{ node = 1, m = \"{} g\", Id = \"{} kg.m2\", Ip = \"{} kg.m2\" }}]\n\
             bearing_nodes = {{ compressor = 2, turbine = 0 }}\n",
            1e3 * (p.z_cm_m - p.z_jt_m),
            1e3 * (p.z_jc_m - p.z_cm_m),
            1e3 * p.m_kg,
            p.j_t_kg_m2,
            p.j_p_kg_m2
        ),
    )
    .unwrap();
    let flags = Flags::try_parse_from([
        "stability",
        "--design",
        design.to_str().unwrap(),
        "--speeds",
        "300:700:400",
        "--mesh",
        "10x4",
    ])
    .unwrap();
    let v = master::stability::cli::run_cli(&flags.args).unwrap();
    assert_eq!(v["rotor"]["bearing_nodes"], serde_json::json!([2, 0]));
    let mut s = RunupSettings::preset("path1").unwrap();
    s.n_elem_phi = 10;
    s.n_elem_z = 4;
    let rigid = analyse(&s, &[300.0, 700.0]).unwrap();
    let threshold = v["report"]["threshold"]["speed_hz"].as_f64().unwrap();
    let tr = rigid.threshold.unwrap().speed_hz;
    assert!((threshold - tr).abs() <= 0.01 * tr, "{threshold} vs {tr}");

    #[derive(Parser)]
    struct Runup {
        #[command(flatten)]
        args: master::runup::DesignArgs,
    }
    let runup = Runup::parse_from(["x", "--design", design.to_str().unwrap()])
        .args
        .settings()
        .unwrap();
    runup.validate_runup().unwrap();
    let reduction = runup.shaft_reduction().unwrap().unwrap();
    assert_eq!((reduction.full_dof, reduction.reduced_dof), (12, 4));
    let _ = std::fs::remove_dir_all(&dir);
}
