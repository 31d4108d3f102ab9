//! `airring modal --rotor FILE`: a flexible rotor (shaft elements, disks, linear bearings) read
//! from a ROSS rotor file: its modes at each speed (damped, gyroscopic), critical speeds and the
//! response to an imbalance, printed and written to modal.json with the Campbell diagram.

use crate::error::{Classify, Error};
use crate::modal::RingFlags;
use crate::plot::{Anchor, Chart, Figure, Rgb, Role};
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

/// Reads a rotor file: saved by ROSS (it has `ross_version`), or a design file's `[shaft]` (its
/// bearing nodes are the design's business: `airring stability --design`).
pub fn read_rotor(path: &Path) -> Result<(ShaftModel, Vec<String>), String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot be read: {e}", path.display()))?;
    let is_design = text
        .parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("shaft") && !t.contains_key("ross_version"));
    if is_design {
        let d = crate::design::Design::load(path)?;
        let spec = d.shaft.expect("a [shaft] table");
        return Ok((spec.model, spec.notes));
    }
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

/// The highest frequency the Campbell diagram and the automatic critical speeds look at: twice
/// the highest speed, at least 1 kHz.
pub fn campbell_cap_hz(speeds_hz: &[f64]) -> f64 {
    (2.0 * speeds_hz.iter().copied().fold(0.0, f64::max)).max(1000.0)
}

/// Modes at each speed, the first `n_critical` critical speeds (None: those of the modes below
/// `campbell_cap_hz` at rest), the unbalance response at each
/// speed; returns modal.json's value. `rings`: air ring bearings at these nodes.
pub fn modal(
    rotor: &Path,
    speeds_hz: &[f64],
    rings: Option<(&[usize], RingFlags)>,
    n_critical: Option<usize>,
    unbalance: Option<Unbalance>,
    out: Option<&Path>,
) -> Result<serde_json::Value, Error> {
    crate::modal::check_speeds(speeds_hz).flag()?;
    let (mut model, mut notes) = read_rotor(rotor).input()?;
    if let Some((nodes, flags)) = rings {
        notes.extend(add_rings(&mut model, nodes, &flags).flag()?);
    }
    if let Some(u) = unbalance {
        if u.node >= model.n_nodes() {
            return Err(Error::Flag(format!(
                "--unbalance-node {} is off the shaft (nodes 0 to {})",
                u.node,
                model.n_nodes() - 1
            )));
        }
        if !(u.g_mm.is_finite() && u.g_mm > 0.0) {
            return Err(Error::Flag(format!(
                "--unbalance {} g mm must be a finite number > 0",
                crate::runup::fmt_number(u.g_mm)
            )));
        }
        if !u.phase_deg.is_finite() {
            return Err(Error::Flag(
                "--unbalance-phase must be a finite number [deg]".into(),
            ));
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
        let ms = modes(&model, f * TAU).run()?;
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
    let n_critical = match n_critical {
        Some(n) => n,
        None => {
            let cap = campbell_cap_hz(speeds_hz);
            modes(&model, 0.0)
                .run()?
                .iter()
                .filter(|m| m.wd_rad_s / TAU <= cap)
                .count()
        }
    };
    let crit = critical_speeds(&model, n_critical).run()?;
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
            .run()?;
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
            "Campbell diagram (flexible rotor, damped frequencies)",
            Some(campbell_cap_hz(speeds_hz)),
        )
        .output()?;
        let files =
            write_figures(dir, &model, speeds_hz.first().copied().unwrap_or(0.0)).output()?;
        println!(
            "wrote {}",
            files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(v)
}

/// The rigid rotor `p` as a flexible one, for checks of the rigid limit (the rotor FMU's
/// [`fmu_rotor::flexible::stiff_shaft_of`]: a light, very stiff shaft through the journals and
/// the centre of mass, the rotor's mass and inertias as a disk there). Lighter or stiffer, the
/// state matrix would span too many decades for the eigenvalues of the slow modes (1e-9 kg
/// nodes on 300 N s/m films gave spurious modes at 0.001 Hz).
pub fn stiff_shaft_of(p: &fmu_rotor::RotorParams) -> ShaftModel {
    fmu_rotor::flexible::stiff_shaft_of(p).shaft
}

/// [`rotor_drawing`] of a rotor whose air ring bearings sit at `bearing_nodes` [C, T] (a
/// design's `[shaft]`, run up in the rotor FMU): the rings drawn at their nodes.
pub fn drawing_with_bearings(model: &ShaftModel, bearing_nodes: [usize; 2]) -> Chart {
    let mut m = model.clone();
    for (node, tag) in bearing_nodes.into_iter().zip(["C", "T"]) {
        m.rings.push(Ring {
            node,
            mass_kg: 0.0,
            mount_k_n_m: 0.0,
            mount_c_n_s_m: 0.0,
            film_k_n_m: [[0.0; 2]; 2],
            film_c_n_s_m: [[0.0; 2]; 2],
            tag: tag.into(),
        });
    }
    rotor_drawing(&m)
}

/// The rotor to scale [mm]: the shaft's outline (outer and, dashed, inner diameters), disks as
/// solid disks of their mass and inertias, bearings at their nodes (linear: grey; air ring: the
/// ring in blue), and the node numbers.
pub fn rotor_drawing(model: &ShaftModel) -> Chart {
    let z = model.node_z_m();
    let mm = |v: f64| 1e3 * v;
    // A disk drawn as a solid cylinder: Ip = m r^2 / 2, Id = m (3 r^2 + w^2) / 12.
    let disk_shape = |d: &shaft::Disk| -> (f64, f64) {
        if d.mass_kg <= 0.0 {
            return (0.0, 0.0);
        }
        let r = (2.0 * d.ip_kg_m2 / d.mass_kg).sqrt();
        let w2 = 12.0 * d.id_kg_m2 / d.mass_kg - 3.0 * r * r;
        (r, w2.max(0.0).sqrt())
    };
    let r_max = model
        .elements
        .iter()
        .map(|e| 0.5 * e.od_left_m.max(e.od_right_m))
        .chain(model.disks.iter().map(|d| disk_shape(d).0))
        .fold(0.0, f64::max);
    let length = *z.last().unwrap_or(&0.0);
    // To scale: equal millimetres per pixel on both axes. The frame's size follows from the
    // chart's margins (figures::chart: 78 px left label area + 8, 22 px right + the legend; 38 px
    // top, 52 px x-label area + 8 bottom) and the spans from it.
    let legend = ["shaft", "disk", "linear bearing", "air ring bearing"];
    let legend_px = legend
        .iter()
        .map(|n| crate::plot::font::text_width_px(n, 13.0))
        .fold(0.0, f64::max)
        .ceil()
        + 44.0;
    let (width, height) = (900.0, 420.0);
    let frame_w = width - 78.0 - 8.0 - 22.0 - legend_px;
    let frame_h = height - 38.0 - 52.0 - 8.0;
    let x_span = 1.04 * mm(length);
    let y_half = (0.5 * x_span * frame_h / frame_w).max(1.4 * mm(r_max));
    // Chart::new widens each range by 5 %; undo it so that the spans are the ones computed.
    let shrink = |lo: f64, hi: f64| {
        let pad = (hi - lo) * 0.05 / 1.1;
        (lo + pad, hi - pad)
    };
    let mut c = Chart::new(
        width as u32,
        height as u32,
        "Rotor (to scale)",
        "axial position z [mm]",
        "radius [mm]",
        shrink(-0.02 * mm(length), 1.02 * mm(length)),
        shrink(-y_half, y_half),
    );
    for sign in [1.0, -1.0] {
        let outer: Vec<(f64, f64)> = model
            .elements
            .iter()
            .zip(z.windows(2))
            .flat_map(|(e, w)| {
                [
                    (mm(w[0]), sign * mm(e.od_left_m / 2.0)),
                    (mm(w[1]), sign * mm(e.od_right_m / 2.0)),
                ]
            })
            .collect();
        c.line(outer, Rgb::BLACK, 1.4, false, Role::Series, "shaft");
        for (e, w) in model.elements.iter().zip(z.windows(2)) {
            if e.id_left_m > 0.0 || e.id_right_m > 0.0 {
                c.line(
                    [
                        (mm(w[0]), sign * mm(e.id_left_m / 2.0)),
                        (mm(w[1]), sign * mm(e.id_right_m / 2.0)),
                    ],
                    Rgb::BLACK,
                    0.8,
                    true,
                    Role::Series,
                    "bore",
                );
            }
        }
    }
    // The shaft's end faces.
    for (k, e) in [
        (0, model.elements.first()),
        (z.len() - 1, model.elements.last()),
    ] {
        if let Some(e) = e {
            let r = if k == 0 { e.od_left_m } else { e.od_right_m } / 2.0;
            c.line(
                [(mm(z[k]), mm(r)), (mm(z[k]), -mm(r))],
                Rgb::BLACK,
                1.4,
                false,
                Role::Series,
                "shaft",
            );
        }
    }
    for d in &model.disks {
        let (r, w) = disk_shape(d);
        let (z0, z1) = (mm(z[d.node] - w / 2.0), mm(z[d.node] + w / 2.0));
        let r = mm(r);
        c.line(
            [(z0, -r), (z0, r), (z1, r), (z1, -r), (z0, -r)],
            Rgb::RED,
            1.4,
            false,
            Role::Series,
            &format!("disk {}", d.tag),
        );
    }
    let below = -1.25 * mm(r_max);
    let bearings = model
        .supports
        .iter()
        .map(|s| (s.node, Rgb::GREY, format!("bearing {}", s.tag)))
        .chain(
            model
                .rings
                .iter()
                .map(|r| (r.node, Rgb::BLUE, format!("air ring bearing {}", r.tag))),
        );
    for (node, colour, name) in bearings {
        let zs = mm(z[node]);
        c.line(
            [(zs, below), (zs, below * 0.8)],
            colour,
            3.0,
            false,
            Role::Marker,
            &name,
        );
    }
    // Node numbers, thinned to at least 40 px apart (the plot spans about 700 px).
    let px_per_mm = 700.0 / mm(length).max(1e-9);
    let mut last = f64::NEG_INFINITY;
    for (k, zk) in z.iter().enumerate() {
        let x = mm(*zk);
        if (x - last) * px_per_mm >= 40.0 || k + 1 == z.len() && (x - last) * px_per_mm >= 25.0 {
            c.label(
                (x, 1.25 * mm(r_max)),
                (0, 0),
                &k.to_string(),
                Anchor::Middle,
            );
            last = x;
        }
    }
    c.legend(&[
        (legend[0], Rgb::BLACK),
        (legend[1], Rgb::RED),
        (legend[2], Rgb::GREY),
        (legend[3], Rgb::BLUE),
    ]);
    c
}

/// Mode shapes along the shaft at one speed: each node's orbit size (semi-major axis), scaled so
/// that the largest on the shaft is 1. Rings and tilts are left out: a ring mode shows as a
/// shaft moving little at its bearing.
pub fn mode_shapes(model: &ShaftModel, ms: &[shaft::Mode], speed_hz: f64, count: usize) -> Chart {
    let z: Vec<f64> = model.node_z_m().iter().map(|v| 1e3 * v).collect();
    let colours = [
        Rgb::RED,
        Rgb::BLUE,
        Rgb::GREEN,
        Rgb(255, 127, 14),
        Rgb(148, 103, 189),
        Rgb(140, 86, 75),
    ];
    let mut c = Chart::new(
        900,
        480,
        &format!(
            "Mode shapes at {} Hz (orbit size along the shaft)",
            crate::runup::fmt_number(speed_hz)
        ),
        "axial position z [mm]",
        "orbit semi-major axis [-]",
        (z[0], *z.last().unwrap_or(&1.0)),
        (0.0, 1.0),
    );
    let mut legend = vec![];
    for (k, m) in ms.iter().take(count.min(colours.len())).enumerate() {
        let size: Vec<f64> = (0..z.len())
            .map(|n| {
                let at = shaft::DOF_PER_NODE * n;
                fmu_rotor::forced::semi_major_axis(&[m.shape[at], m.shape[at + 1]])
            })
            .collect();
        let big = size.iter().copied().fold(0.0, f64::max).max(1e-300);
        let pts: Vec<(f64, f64)> = z.iter().zip(&size).map(|(z, s)| (*z, s / big)).collect();
        let name = format!(
            "mode {}: {} Hz {}",
            k + 1,
            crate::runup::fmt_number((m.wd_rad_s / TAU * 10.0).round() / 10.0),
            whirl_name(m.whirl)
        );
        c.line(pts, colours[k], 1.6, false, Role::Series, &name);
        legend.push((name, colours[k]));
    }
    let entries: Vec<(&str, Rgb)> = legend.iter().map(|(n, c)| (n.as_str(), *c)).collect();
    c.legend(&entries);
    c
}

/// rotor.svg/png and modes.svg/png (at the first speed) in `dir`.
fn write_figures(
    dir: &Path,
    model: &ShaftModel,
    speed_hz: f64,
) -> Result<Vec<std::path::PathBuf>, String> {
    let ms = modes(model, speed_hz * TAU).map_err(|e| e.to_string())?;
    let mut files = rotor_drawing(model)
        .save(dir, "rotor")
        .map_err(|e| format!("figures not written: {e}"))?;
    files.extend(
        mode_shapes(model, &ms, speed_hz, 6)
            .save(dir, "modes")
            .map_err(|e| format!("figures not written: {e}"))?,
    );
    Ok(files)
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
        let v = modal(
            &f,
            &[0.0, 500.0],
            None,
            Some(2),
            Some(u),
            Some(&d.join("out")),
        )
        .unwrap();
        assert_eq!(v["campbell"].as_array().unwrap().len(), 2);
        assert_eq!(v["critical_speeds"].as_array().unwrap().len(), 2);
        let at500 = &v["unbalance"]["response"][1]["nodes"][1];
        assert!(at500["major_um"].as_f64().unwrap() > 0.0, "{at500}");
        for f in [
            "modal.json",
            "campbell.svg",
            "rotor.svg",
            "rotor.png",
            "modes.svg",
        ] {
            assert!(d.join("out").join(f).exists(), "{f}");
        }
        for f in ["rotor.svg", "modes.svg"] {
            let svg = std::fs::read_to_string(d.join("out").join(f)).unwrap();
            let bad = crate::plot::layout::problems(&svg);
            assert!(bad.is_empty(), "{f}: {bad:#?}");
        }
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
        let e = modal(&f, &[100.0], None, Some(2), Some(off), None).unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.contains("--unbalance-node 3") && m.contains("0 to 2")),
            "{e:?}"
        );
        let zero = Unbalance { g_mm: 0.0, ..off };
        let e = modal(
            &f,
            &[100.0],
            None,
            Some(2),
            Some(Unbalance { node: 1, ..zero }),
            None,
        )
        .unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.contains("--unbalance 0 g mm")),
            "{e:?}"
        );
        let e = modal(&d.join("missing.toml"), &[100.0], None, Some(2), None, None).unwrap_err();
        assert!(
            matches!(&e, Error::Input(m) if m.contains("missing.toml") && m.contains("cannot be read")),
            "{e:?}"
        );
        let e = modal(&f, &[-5.0], None, Some(2), None, None).unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.starts_with("--speed -5 Hz")),
            "{e:?}"
        );
        let _ = std::fs::remove_dir_all(&d);
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
        let mut stiff = stiff_shaft_of(&p);
        add_rings(&mut stiff, &[2, 0], &f).unwrap();
        let flexible = modes(&stiff, omega).unwrap();
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
