//! `airring stability`: flags (as the run-up's), the printed Campbell table, stability.json and
//! the figures (Campbell, damping, journal locus, eccentricity).

use super::{analyse_with_equilibria, parse_speeds, StabilityReport};
use crate::error::{Classify, Error};
use crate::plot::Figure;
use crate::runup::RunupSettings;
use std::path::PathBuf;

#[derive(clap::Args, Clone, Debug)]
pub struct StabilityArgs {
    /// The rotor and its bearings, as for `airring runup`.
    #[command(flatten)]
    pub bearing: crate::runup::DesignArgs,
    /// Speed grid from:to:step [Hz] (at most 1000 speeds), or one speed.
    #[arg(long, default_value = "100:2000:50")]
    pub speeds: String,
    /// Output folder for stability.json and the diagrams.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Compressor-wheel imbalance "mass_g,radius_mm,phase_deg": adds the unbalance response
    /// (amplitude and phase of journals and rings, critical speeds) to the report. Also
    /// --imbalance-c, the run-up's name.
    #[arg(long, visible_alias = "imbalance-c", allow_hyphen_values = true)]
    pub unbalance_c: Option<String>,
    /// Turbine-wheel imbalance "mass_g,radius_mm,phase_deg" (see --unbalance-c). Also
    /// --imbalance-t.
    #[arg(long, visible_alias = "imbalance-t", allow_hyphen_values = true)]
    pub unbalance_t: Option<String>,
    /// A flexible rotor: a rotor file saved by ROSS 2.3.0 (shaft elements, disks, point masses;
    /// a linear bearing of the file at a bearing node is replaced, others are refused) in place of
    /// the paper's rigid rotor, carried by the two air ring bearings at --bearing-nodes. The
    /// bearing flags and the design file give the bearings; the rigid rotor's mass properties do
    /// not apply. A design file's [shaft] table does the same without --rotor.
    #[arg(long, requires = "bearing_nodes")]
    pub rotor: Option<PathBuf>,
    /// A flexible rotor's imbalance [g mm] (mass times radius) at --unbalance-node: adds the
    /// unbalance response in the films (their coefficients at each speed's own frequency).
    #[arg(long, requires = "unbalance_node")]
    pub unbalance: Option<f64>,
    /// The node of --unbalance.
    #[arg(long, requires = "unbalance")]
    pub unbalance_node: Option<usize>,
    /// The phase of --unbalance [deg].
    #[arg(long, default_value_t = 0.0, requires = "unbalance")]
    pub unbalance_phase: f64,
    /// With --rotor: the nodes of bearings C and T, "C,T".
    #[arg(long, value_delimiter = ',', num_args = 1.., requires = "rotor")]
    pub bearing_nodes: Vec<usize>,
}

/// The run-up settings these flags describe (preset, design file, then overrides; the
/// imbalance of --unbalance-c / --unbalance-t).
pub fn settings(a: &StabilityArgs) -> Result<RunupSettings, String> {
    let mut s = a.bearing.settings()?;
    if let Some(t) = &a.unbalance_c {
        s.imbalance_c = super::unbalance::parse_imbalance(t, "unbalance-c")?;
    }
    if let Some(t) = &a.unbalance_t {
        s.imbalance_t = super::unbalance::parse_imbalance(t, "unbalance-t")?;
    }
    s.validate()?;
    s.validate_fmu_parameters()?;
    Ok(s)
}

fn print_unbalance(u: &super::unbalance::UnbalanceReport) {
    let (c, t) = (u.imbalance_c, u.imbalance_t);
    match u.imbalance_at_node {
        Some((node, g_mm, deg)) => println!(
            "unbalance response: {g_mm} g mm at node {node}, {deg} deg (J_C, J_T: the journals \
             at bearings C and T)"
        ),
        None => println!(
            "unbalance response: compressor {} g at {} mm, {} deg; turbine {} g at {} mm, {} deg",
            c.0, c.1, c.2, t.0, t.1, t.2
        ),
    }
    println!(
        "orbit semi-major axes [um] (journals, rings, journal relative to ring); x phase [deg]"
    );
    println!(
        "{:>7} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>7} {:>7}",
        "speed", "J_C", "J_T", "R_C", "R_T", "film_C", "film_T", "ph J_C", "ph J_T"
    );
    for p in &u.points {
        println!(
            "{:7.1} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:7.1} {:7.1}{}",
            p.speed_hz,
            p.journal_c.semi_major_um,
            p.journal_t.semi_major_um,
            p.ring_c.semi_major_um,
            p.ring_t.semi_major_um,
            p.film_c_um,
            p.film_t_um,
            p.journal_c.x_phase_deg,
            p.journal_t.x_phase_deg,
            if p.unstable {
                "  (linearly unstable here)"
            } else {
                ""
            }
        );
    }
    if u.critical_speeds.is_empty() {
        println!("no critical speed (response peak) inside the speed range");
    }
    for cs in &u.critical_speeds {
        println!(
            "critical speed {:.1} Hz (journal {}): {:.4} um, amplification factor {}",
            cs.speed_hz,
            cs.journal,
            cs.peak_um,
            cs.amplification_factor.map_or(
                "n/a (half-power points outside the range)".to_string(),
                |q| { format!("{q:.2}") }
            )
        );
    }
}

fn print_table(s: &RunupSettings, r: &StabilityReport) {
    println!(
        "linear stability: c = {} N/mm, d = {} N s/m, m_R = {} g, C = {} um, dH = {} um, mesh {}x{}",
        s.c_n_per_mm, s.d_n_s_per_m, s.m_r_g, s.clearance_um, s.dh_um, s.n_elem_phi, s.n_elem_z
    );
    if !s.fmu_parameters.is_empty() {
        let kv: Vec<String> = s
            .fmu_parameters
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        println!("FMU parameters: {}", kv.join(", "));
    }
    println!("Campbell table: whirl frequency [Hz], F/B = forward/backward, damping ratio [%]; N = growth");
    println!(
        "exponent Int Re(lambda) dt accumulated along a run-up at {:.1} Hz/s",
        r.ramp_hz_per_s
    );
    println!("P_C, P_T: friction power loss of each film at its static equilibrium [W]");
    print!(
        "{:>7} {:>6} {:>6} {:>7} {:>7} {:>6} |",
        "speed", "eps_C", "eps_T", "P_C", "P_T", "N"
    );
    // At most 12 columns (a flexible rotor has more modes; stability.json has them all).
    let all_ranks = r.speeds.iter().map(|s| s.modes.len()).max().unwrap_or(0);
    let n_ranks = all_ranks.min(12);
    for k in 0..n_ranks {
        print!(" {:>15}", format!("mode {}", k + 1));
    }
    println!();
    for (sp, n) in r.speeds.iter().zip(&r.growth_exponent) {
        let [c, t] = &sp.bearings;
        print!(
            "{:7.1} {:6.3} {:6.3} {:7.2} {:7.2} {:6.1} |",
            sp.speed_hz, c.eps, t.eps, c.power_loss_w, t.power_loss_w, n
        );
        for m in sp.modes.iter().take(n_ranks) {
            let w = if m.whirl == "forward" { 'F' } else { 'B' };
            let flag = if m.converged { ' ' } else { '*' };
            print!(
                " {:6.0}{w} {:6.2}{flag}",
                m.freq_hz,
                100.0 * m.damping_ratio
            );
        }
        // Ranks this speed lacks (overdamped there) stay blank, so the columns line up.
        for _ in sp.modes.len().min(n_ranks)..n_ranks {
            print!(" {:>15}", "-");
        }
        if let Some(re) = sp.real_eigenvalues_per_s.iter().copied().reduce(f64::max) {
            if re > 0.0 {
                print!("  divergence: real eigenvalue {re:.3e} 1/s");
            }
        }
        println!();
    }
    if all_ranks == n_ranks + 1 {
        println!("mode {all_ranks} is in stability.json (--out)");
    } else if all_ranks > n_ranks {
        println!(
            "modes {} to {all_ranks} are in stability.json (--out)",
            n_ranks + 1
        );
    }
    let unconverged: usize = r
        .speeds
        .iter()
        .map(|s| s.modes.iter().filter(|m| !m.converged).count())
        .sum();
    if unconverged > 0 {
        println!(
            "* {unconverged} mode(s) did not meet nu = Im(lambda) to 1e-6 in the iteration limit: \
             their film coefficients are taken at a nearby frequency"
        );
    }
    match (&r.threshold, r.unstable_at_first_speed) {
        (_, true) => println!(
            "unstable already at the first speed of the range ({} Hz): the threshold lies below it",
            r.speeds.first().map_or(f64::NAN, |s| s.speed_hz)
        ),
        (Some(t), _) if t.mode.whirl == "none" => println!(
            "threshold speed of instability: {:.1} Hz (+-{} Hz): static divergence (a real eigenvalue crosses 0)",
            t.speed_hz, t.tolerance_hz
        ),
        (Some(t), _) => println!(
            "threshold speed of instability: {:.1} Hz (+-{} Hz): {} whirl at {:.1} Hz (whirl ratio {:.3}), log decrement {:.4}; {}",
            t.speed_hz,
            t.tolerance_hz,
            t.mode.whirl,
            t.mode.freq_hz,
            t.whirl_ratio,
            t.mode.log_decrement,
            t.mode.description
        ),
        (None, false) => println!("stable over the whole speed range"),
    }
    println!("wall time {:.2} s", r.wall_time_s);
}

/// Runs the command; returns the report as JSON.
pub fn run_cli(a: &StabilityArgs) -> Result<serde_json::Value, Error> {
    let s = settings(a).flag()?;
    let speeds = parse_speeds(&a.speeds).flag()?;
    let mut rotor_json = serde_json::Value::Null;
    let from_file = match (&a.rotor, &s.shaft) {
        (Some(_), Some(_)) => {
            return Err(Error::Flag(
                "--rotor and the design's [shaft] both give a flexible rotor: keep one".into(),
            ))
        }
        (Some(file), None) => {
            let &[c, t] = a.bearing_nodes.as_slice() else {
                return Err(Error::Flag(format!(
                    "--bearing-nodes takes two nodes, bearing C's and T's (\"C,T\"); {} given",
                    a.bearing_nodes.len()
                )));
            };
            let (model, notes) = crate::flexible::read_rotor(file).input()?;
            Some((file.display().to_string(), model, [c, t], notes))
        }
        (None, Some(spec)) => Some((
            format!(
                "{} [shaft]",
                s.design
                    .as_ref()
                    .map_or(String::new(), |p| p.display().to_string())
            ),
            spec.model.clone(),
            spec.bearing_nodes,
            spec.notes.clone(),
        )),
        (None, None) => None,
    };
    let mut drawing: Option<crate::plot::Chart> = None;
    let mut flexible: Option<super::structure::FlexibleRotor> = None;
    let (r, solved) = match from_file {
        Some((file, mut model, nodes, mut notes)) => {
            // A linear bearing of the file at a bearing node is the bearing the air ring
            // bearing replaces (as `airring modal --bearing-nodes` does).
            for node in nodes {
                let before = model.supports.len();
                model.supports.retain(|b| b.node != node);
                if model.supports.len() < before {
                    notes.push(format!(
                        "the file's bearing at node {node} is replaced by an air ring bearing"
                    ));
                }
            }
            if a.unbalance_c.is_some() || a.unbalance_t.is_some() {
                return Err(Error::Flag(
                    "--unbalance-c and --unbalance-t are the paper rotor's wheels; a flexible \
                     rotor's imbalance is --unbalance G_MM --unbalance-node N"
                        .into(),
                ));
            }
            println!(
                "flexible rotor {}: {} shaft elements, {:.4} kg, bearings C at node {}, T at node {}",
                file,
                model.elements.len(),
                model.mass_kg(),
                nodes[0],
                nodes[1]
            );
            for n in &notes {
                println!("note: {n}");
            }
            rotor_json = serde_json::json!({
                "file": file, "elements": model.elements.len(),
                "mass_kg": model.mass_kg(), "bearing_nodes": nodes, "notes": notes,
            });
            // The rotor as drawn (rotor.svg): its air ring bearings at their nodes.
            drawing = Some(crate::flexible::drawing_with_bearings(&model, nodes));
            let (r, solved, rotor) = super::analyse_flexible(&s, model, nodes, &speeds).run()?;
            flexible = Some(rotor);
            (r, solved)
        }
        None => analyse_with_equilibria(&s, &speeds).run()?,
    };
    print_table(&s, &r);
    let unbalance = if let Some(g_mm) = a.unbalance {
        let Some(rotor) = &flexible else {
            return Err(Error::Flag(
                "--unbalance and --unbalance-node are a flexible rotor's (--rotor or a \
                        design's [shaft]); the paper rotor's wheels take --unbalance-c and \
                        --unbalance-t"
                    .into(),
            ));
        };
        let node = a.unbalance_node.unwrap_or(0);
        if node >= rotor.model.n_nodes() {
            return Err(Error::Flag(format!(
                "--unbalance-node {node} is off the shaft (nodes 0 to {})",
                rotor.model.n_nodes() - 1
            )));
        }
        if !(g_mm.is_finite() && g_mm > 0.0 && a.unbalance_phase.is_finite()) {
            return Err(Error::Flag(format!(
                "--unbalance {} g mm must be a finite number > 0 (and --unbalance-phase finite)",
                crate::runup::fmt_number(g_mm)
            )));
        }
        let u = super::unbalance::flexible_unbalance_report(
            rotor,
            (node, g_mm, a.unbalance_phase),
            &r.speeds,
            &solved,
        )
        .run()?;
        print_unbalance(&u);
        Some(u)
    } else if a.unbalance_c.is_some() || a.unbalance_t.is_some() {
        let (rotor, _) = super::params_of(&s).flag()?;
        let u = super::unbalance::unbalance_report(
            &rotor,
            [s.imbalance_c, s.imbalance_t],
            &r.speeds,
            &solved,
        )
        .run()?;
        print_unbalance(&u);
        Some(u)
    } else {
        None
    };
    let v = serde_json::json!({
        "settings": {
            "preset": s.preset, "c_n_per_mm": s.c_n_per_mm, "d_n_s_per_m": s.d_n_s_per_m,
            "m_r_g": s.m_r_g, "clearance_um": s.clearance_um, "dh_um": s.dh_um,
            "n_elem_phi": s.n_elem_phi, "n_elem_z": s.n_elem_z,
            "fmu_parameters": s.fmu_parameters,
            "nu_grid_hz": super::campbell::GRID_HZ,
        },
        "rotor": rotor_json,
        "report": r,
        "unbalance": unbalance,
    });
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::Output(format!("{}: {e}", dir.display())))?;
        let path = dir.join("stability.json");
        crate::output::write_whole(&path, serde_json::to_string_pretty(&v).unwrap().as_bytes())
            .output()?;
        // Both films share the bore unless --set gives film_T another one: draw bearing C's.
        let lobes = super::params_of(&s).flag()?.1[0].bore.clone();
        let mut figs = super::figures::save(&r, &lobes, dir).output()?;
        if let Some(u) = &unbalance {
            figs.extend(super::figures::save_unbalance(u, dir).output()?);
        }
        if let Some(chart) = &drawing {
            figs.extend(
                chart
                    .save(dir, "rotor")
                    .map_err(|e| Error::Output(format!("figures not written: {e}")))?,
            );
        }
        println!("wrote {} and {} figure files", path.display(), figs.len());
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Flags {
        #[command(flatten)]
        args: StabilityArgs,
    }

    /// The run-up's names of the imbalance flags work here too.
    #[test]
    fn imbalance_flags_take_the_run_ups_names_too() {
        for (c, t) in [
            ("--unbalance-c", "--unbalance-t"),
            ("--imbalance-c", "--imbalance-t"),
        ] {
            let f = Flags::try_parse_from(["stability", c, "0.01,20,0", t, "0.02,20,90"]).unwrap();
            let s = settings(&f.args).unwrap();
            assert_eq!(
                (s.imbalance_c, s.imbalance_t),
                ((0.01, 20.0, 0.0), (0.02, 20.0, 90.0)),
                "{c}"
            );
        }
    }
}
