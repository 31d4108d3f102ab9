//! `airring modal --rotor FILE`: a flexible rotor (shaft elements, disks, linear bearings) read
//! from a ROSS rotor file: its modes at each speed (damped, gyroscopic), critical speeds and the
//! response to an imbalance, printed and written to modal.json with the Campbell diagram.

use crate::modal::RingFlags;
use shaft::modal::{critical_speeds, modes, unbalance_response, Whirl};
use shaft::{Ring, ShaftModel};
use std::f64::consts::TAU;
use std::path::Path;

/// An imbalance: node, magnitude [g mm], phase [deg].
#[derive(Clone, Copy, Debug)]
pub struct Unbalance {
    pub node: usize,
    pub g_mm: f64,
    pub phase_deg: f64,
}

/// Reads the rotor file: ROSS's (it has `ross_version`).
pub fn read_rotor(path: &Path) -> Result<(ShaftModel, Vec<String>), String> {
    let r = shaft::ross::read(path).map_err(|e| e.to_string())?;
    Ok((r.model, r.notes))
}

fn whirl_name(w: Whirl) -> &'static str {
    match w {
        Whirl::Forward => "forward",
        Whirl::Backward => "backward",
    }
}

/// Air ring bearings (rings on their mounts, isotropic film springs) at `nodes`, replacing the
/// model's linear bearings at those nodes; returns what was replaced, for the notes.
pub fn add_rings(
    model: &mut ShaftModel,
    nodes: &[usize],
    f: &RingFlags,
) -> Result<Vec<String>, String> {
    f.check()?;
    let mut notes = vec![];
    for (i, &node) in nodes.iter().enumerate() {
        if node >= model.n_nodes() {
            return Err(format!(
                "--bearing-nodes {node} is off the shaft (nodes 0 to {})",
                model.n_nodes() - 1
            ));
        }
        if nodes[..i].contains(&node) {
            return Err(format!(
                "--bearing-nodes names node {node} twice: each bearing needs a node of its own"
            ));
        }
        let before = model.supports.len();
        model.supports.retain(|s| s.node != node);
        if model.supports.len() < before {
            notes.push(format!(
                "the file's bearing at node {node} is replaced by an air ring bearing"
            ));
        }
        let k = f.film_n_per_mm * 1e3;
        model.rings.push(Ring {
            node,
            mass_kg: f.m_r_g * 1e-3,
            mount_k_n_m: f.c_n_per_mm * 1e3,
            mount_c_n_s_m: f.d_n_s_per_m,
            film_k_n_m: [[k, 0.0], [0.0, k]],
            film_c_n_s_m: [[0.0; 2]; 2],
            tag: format!("ring at node {node}"),
        });
    }
    Ok(notes)
}

/// Modes at each speed, the first `n_critical` critical speeds, the unbalance response at each
/// speed; returns modal.json's value. `rings`: air ring bearings at these nodes.
pub fn modal(
    rotor: &Path,
    speeds_hz: &[f64],
    rings: Option<(&[usize], RingFlags)>,
    n_critical: usize,
    unbalance: Option<Unbalance>,
    out: Option<&Path>,
) -> Result<serde_json::Value, String> {
    let top = crate::runup::MAX_SPEED_HZ;
    if let Some(f) = speeds_hz
        .iter()
        .find(|f| !(f.is_finite() && **f >= 0.0 && **f <= top))
    {
        return Err(format!(
            "--speed {} Hz must lie between 0 and {top} Hz",
            crate::runup::fmt_number(*f)
        ));
    }
    let (mut model, mut notes) = read_rotor(rotor)?;
    if let Some((nodes, flags)) = rings {
        notes.extend(add_rings(&mut model, nodes, &flags)?);
    }
    if let Some(u) = unbalance {
        if u.node >= model.n_nodes() {
            return Err(format!(
                "--unbalance-node {} is off the shaft (nodes 0 to {})",
                u.node,
                model.n_nodes() - 1
            ));
        }
        if !(u.g_mm.is_finite() && u.g_mm > 0.0) {
            return Err(format!(
                "--unbalance {} g mm must be a finite number > 0",
                crate::runup::fmt_number(u.g_mm)
            ));
        }
        if !u.phase_deg.is_finite() {
            return Err("--unbalance-phase must be a finite number [deg]".into());
        }
    }
    let z = model.node_z_m();
    println!(
        "flexible rotor {}: {} shaft elements, {} nodes, {:.1} mm long, {:.4} kg; {} disks, {} \
         linear bearings, {} air ring bearings (linear film springs)",
        rotor.display(),
        model.elements.len(),
        model.n_nodes(),
        1e3 * z.last().copied().unwrap_or(0.0),
        model.mass_kg(),
        model.disks.len(),
        model.supports.len(),
        model.rings.len()
    );
    for n in &notes {
        println!("note: {n}");
    }
    let mut table = vec![];
    for &f in speeds_hz {
        let ms = modes(&model, f * TAU).map_err(|e| e.to_string())?;
        println!("speed {f} Hz:");
        let mut rows = vec![];
        for (k, m) in ms.iter().enumerate() {
            let freq_hz = m.wd_rad_s / TAU;
            if k < 12 {
                println!(
                    "  {:2}. {:10.2} Hz  log dec {:8.4}  {}",
                    k + 1,
                    freq_hz,
                    m.log_dec,
                    whirl_name(m.whirl)
                );
            }
            rows.push(serde_json::json!({
                "freq_hz": freq_hz, "wn_hz": m.wn_rad_s / TAU,
                "damping_ratio": m.damping_ratio, "log_dec": m.log_dec,
                "whirl": whirl_name(m.whirl),
            }));
        }
        if ms.len() > 12 {
            println!("  ... {} more in modal.json", ms.len() - 12);
        }
        table.push(serde_json::json!({ "speed_hz": f, "modes": rows }));
    }
    let crit = critical_speeds(&model, n_critical).map_err(|e| e.to_string())?;
    if !crit.is_empty() {
        println!("critical speeds (damped frequency = speed):");
        for c in &crit {
            println!(
                "  mode {:2}: {:10.2} Hz ({:8.0} rpm)  log dec {:8.4}  {}",
                c.mode + 1,
                c.speed_rad_s / TAU,
                c.speed_rad_s / TAU * 60.0,
                c.log_dec,
                whirl_name(c.whirl)
            );
        }
    }
    let crit_json: Vec<_> = crit
        .iter()
        .map(|c| {
            serde_json::json!({"mode": c.mode + 1, "speed_hz": c.speed_rad_s / TAU,
                "log_dec": c.log_dec, "whirl": whirl_name(c.whirl)})
        })
        .collect();
    let mut unb_json = vec![];
    if let Some(u) = unbalance {
        println!(
            "unbalance response to {} g mm at node {} ({} deg): largest semi-major axis",
            u.g_mm, u.node, u.phase_deg
        );
        for &f in speeds_hz {
            let q = unbalance_response(
                &model,
                u.node,
                u.g_mm * 1e-6,
                u.phase_deg.to_radians(),
                f * TAU,
            )
            .map_err(|e| e.to_string())?;
            let nodes: Vec<_> = (0..model.n_nodes())
                .map(|k| {
                    let (x, y) = (q[4 * k], q[4 * k + 1]);
                    serde_json::json!({
                        "node": k, "z_mm": 1e3 * z[k],
                        "x_amplitude_um": 1e6 * x.norm(), "x_phase_deg": x.arg().to_degrees(),
                        "y_amplitude_um": 1e6 * y.norm(), "y_phase_deg": y.arg().to_degrees(),
                        "major_um": 1e6 * fmu_rotor::forced::semi_major_axis(&[x, y]),
                    })
                })
                .collect();
            let (k, big) = nodes
                .iter()
                .map(|n| n["major_um"].as_f64().unwrap_or(0.0))
                .enumerate()
                .fold((0, 0.0), |acc, (k, v)| if v > acc.1 { (k, v) } else { acc });
            println!("  {f:8} Hz: {big:10.4} um at node {k}");
            unb_json.push(serde_json::json!({"speed_hz": f, "nodes": nodes}));
        }
    }
    let v = serde_json::json!({
        "rotor": {
            "file": rotor.display().to_string(), "elements": model.elements.len(),
            "nodes_z_mm": z.iter().map(|v| 1e3 * v).collect::<Vec<_>>(),
            "mass_kg": model.mass_kg(), "notes": notes,
        },
        "campbell": table,
        "critical_speeds": crit_json,
        "unbalance": unbalance.map(|u| serde_json::json!({
            "node": u.node, "g_mm": u.g_mm, "phase_deg": u.phase_deg, "response": unb_json,
        })),
    });
    if let Some(dir) = out {
        crate::modal::write_outputs(
            dir,
            &v,
            "Campbell diagram (flexible rotor on linear bearings, damped frequencies)",
        )?;
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-element shaft on two bearings, in ROSS's file format.
    fn rotor_file(dir: &Path) -> std::path::PathBuf {
        let mut text = String::from("ross_version = \"2.3.0\"\n[parameters]\n");
        for n in 0..2 {
            text += &format!(
                "[\"ShaftElement_S{n}\"]\nL = 0.1\nidl = 0.0\nodl = 0.02\nn = {n}\n\
                 [\"ShaftElement_S{n}\".material]\nname = \"Steel\"\nrho = 7810.0\n\
                 E = 211e9\nG_s = 81.2e9\n"
            );
        }
        for (n, tag) in [(0, "C"), (2, "T")] {
            text += &format!(
                "[\"BearingElement_{tag}\"]\nn = {n}\ntag = \"{tag}\"\nkxx = [1e6]\nkyy = [1e6]\n\
                 cxx = [100]\ncyy = [100]\n"
            );
        }
        let p = dir.join("rotor.toml");
        std::fs::write(&p, text).unwrap();
        p
    }

    fn scratch(name: &str) -> std::path::PathBuf {
        let d =
            std::env::temp_dir().join(format!("airring-flexible-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn modes_critical_speeds_and_unbalance_are_written() {
        let d = scratch("ok");
        let f = rotor_file(&d);
        let u = Unbalance {
            node: 1,
            g_mm: 5.0,
            phase_deg: 0.0,
        };
        let v = modal(&f, &[0.0, 500.0], None, 2, Some(u), Some(&d.join("out"))).unwrap();
        assert_eq!(v["campbell"].as_array().unwrap().len(), 2);
        assert_eq!(v["critical_speeds"].as_array().unwrap().len(), 2);
        let at500 = &v["unbalance"]["response"][1]["nodes"][1];
        assert!(at500["major_um"].as_f64().unwrap() > 0.0, "{at500}");
        assert!(d.join("out/modal.json").exists() && d.join("out/campbell.svg").exists());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn bad_input_is_named() {
        let d = scratch("bad");
        let f = rotor_file(&d);
        let off = Unbalance {
            node: 3,
            g_mm: 5.0,
            phase_deg: 0.0,
        };
        let e = modal(&f, &[100.0], None, 2, Some(off), None).unwrap_err();
        assert!(
            e.contains("--unbalance-node 3") && e.contains("0 to 2"),
            "{e}"
        );
        let zero = Unbalance { g_mm: 0.0, ..off };
        let e = modal(
            &f,
            &[100.0],
            None,
            2,
            Some(Unbalance { node: 1, ..zero }),
            None,
        )
        .unwrap_err();
        assert!(e.contains("--unbalance 0 g mm"), "{e}");
        let e = modal(&d.join("missing.toml"), &[100.0], None, 2, None, None).unwrap_err();
        assert!(
            e.contains("missing.toml") && e.contains("cannot be read"),
            "{e}"
        );
        let e = modal(&f, &[-5.0], None, 2, None, None).unwrap_err();
        assert!(e.starts_with("--speed -5 Hz"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    /// The paper's rigid rotor as a flexible one: a massless, very stiff two-element shaft
    /// through the turbine journal, the centre of mass and the compressor journal, the rotor's
    /// mass and inertias as a disk at the centre of mass, air ring bearings at the journals.
    fn paper_as_a_stiff_shaft(p: &fmu_rotor::RotorParams, f: &RingFlags) -> ShaftModel {
        let mut steel = shaft::Material::steel();
        steel.rho_kg_m3 = 1e-6;
        steel.e_pa *= 1e5;
        steel.g_pa *= 1e5;
        let mut model = ShaftModel {
            elements: vec![
                shaft::ShaftElement::cylinder(p.z_cm_m - p.z_jt_m, 0.0, 0.02, steel.clone()),
                shaft::ShaftElement::cylinder(p.z_jc_m - p.z_cm_m, 0.0, 0.02, steel),
            ],
            disks: vec![shaft::Disk {
                node: 1,
                mass_kg: p.m_kg,
                id_kg_m2: p.j_t_kg_m2,
                ip_kg_m2: p.j_p_kg_m2,
                tag: "rotor".into(),
            }],
            ..Default::default()
        };
        add_rings(&mut model, &[2, 0], f).unwrap();
        model
    }

    /// The rigid limit: `airring modal`'s rigid rotor and the stiff flexible one give the same
    /// eight modes at 1000 Hz within 0.1 Hz, whirl directions alike.
    #[test]
    fn a_stiff_shaft_with_the_papers_mass_properties_is_the_rigid_rotor() {
        let f = RingFlags {
            c_n_per_mm: 500.0,
            d_n_s_per_m: 50.0,
            film_n_per_mm: 2000.0,
            m_r_g: 50.0,
        };
        let mut p = fmu_rotor::RotorParams::paper();
        (p.c_c_n_m, p.c_t_n_m) = (f.c_n_per_mm * 1e3, f.c_n_per_mm * 1e3);
        (p.d_c_n_s_m, p.d_t_n_s_m) = (f.d_n_s_per_m, f.d_n_s_per_m);
        (p.m_r_c_kg, p.m_r_t_kg) = (f.m_r_g * 1e-3, f.m_r_g * 1e-3);
        let film = fmu_rotor::FilmCoefficients::isotropic(f.film_n_per_mm * 1e3, 0.0);
        let omega = 1000.0 * TAU;
        let rigid = fmu_rotor::linear::modes(&fmu_rotor::linear::lateral_matrices(
            &p,
            omega,
            &[film, film],
        ))
        .unwrap();
        let flexible = modes(&paper_as_a_stiff_shaft(&p, &f), omega).unwrap();
        assert_eq!(rigid.len(), 8);
        for (r, x) in rigid.iter().zip(&flexible) {
            let fx = x.wd_rad_s / TAU;
            assert!((r.freq_hz - fx).abs() < 0.1, "{} Hz vs {fx} Hz", r.freq_hz);
            let rigid_forward = r.whirl == fmu_rotor::linear::Whirl::Forward;
            assert_eq!(rigid_forward, x.whirl == Whirl::Forward, "{} Hz", r.freq_hz);
        }
        // The shaft's own bending modes lie far above.
        assert!(
            flexible[8].wd_rad_s / TAU > 20_000.0,
            "{}",
            flexible[8].wd_rad_s / TAU
        );
    }

    #[test]
    fn air_ring_bearings_replace_the_files_bearings_and_need_nodes_of_their_own() {
        let d = scratch("rings");
        let (mut model, _) = read_rotor(&rotor_file(&d)).unwrap();
        let f = RingFlags {
            c_n_per_mm: 500.0,
            d_n_s_per_m: 50.0,
            film_n_per_mm: 2000.0,
            m_r_g: 50.0,
        };
        let notes = add_rings(&mut model.clone(), &[0], &f).unwrap();
        assert!(
            notes[0].contains("node 0") && notes[0].contains("replaced"),
            "{notes:?}"
        );
        let e = add_rings(&mut model.clone(), &[1, 1], &f).unwrap_err();
        assert!(e.contains("node 1 twice"), "{e}");
        let e = add_rings(&mut model, &[4], &f).unwrap_err();
        assert!(
            e.contains("--bearing-nodes 4") && e.contains("0 to 2"),
            "{e}"
        );
        let e = add_rings(&mut model, &[1], &RingFlags { m_r_g: 0.0, ..f }).unwrap_err();
        assert!(e.starts_with("--m-r = 0 g"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
