//! `airring orbits`: flags, the printed progress and orbits.json.

use super::driver::{find_orbits, OrbitsRequest};
use std::path::PathBuf;

#[derive(clap::Args, Clone, Debug)]
pub struct OrbitsArgs {
    /// The rotor and its bearings, as for `airring runup`.
    #[command(flatten)]
    pub bearing: crate::design::DesignArgs,
    /// Constant speeds from:to:step [Hz]; each is simulated until its whirl settles and the
    /// orbit is shot from there.
    #[arg(long)]
    pub speeds: String,
    /// Constant-speed simulation before a whirl counts as settled [s].
    #[arg(long, default_value_t = 1.0)]
    pub settle: f64,
    /// Only the orbits at the given speeds: no continuation of the branch.
    #[arg(long)]
    pub no_continuation: bool,
    /// Shoot on the full state (the rotor and both films' pressure fields) by Newton-Krylov,
    /// at the given speeds only (no continuation), instead of the reduced shooting in the
    /// rotor's coordinates with the films relaxed onto the orbit.
    #[arg(long)]
    pub full_state: bool,
    /// A run-up folder whose eccentricity envelope the bifurcation diagram shows beside the
    /// orbits.
    #[arg(long)]
    pub runup: Option<PathBuf>,
    /// Output folder (orbits.json, bifurcation.svg/.png, the system file of each speed).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run_cli(args: &OrbitsArgs, fmu_dir: PathBuf) -> Result<(), String> {
    let settings = args.bearing.settings()?;
    // Read before hours of shooting, so that a wrong folder is refused at once.
    let runup = match &args.runup {
        Some(dir) => {
            let bores = crate::run_folder::bores_of_run(dir)?.ok_or_else(|| {
                format!("--runup {}: no run-up's system.toml there", dir.display())
            })?;
            Some(crate::analysis::load_run(
                dir,
                [bores[0].c_m, bores[1].c_m],
            )?)
        }
        None => None,
    };
    let speeds_hz = crate::stability::parse_speeds(&args.speeds)?;
    let req = OrbitsRequest {
        settings,
        speeds_hz,
        settle_s: args.settle,
        continuation: !args.no_continuation && !args.full_state,
        full_state: args.full_state,
        fmu_dir,
        out_dir: args.out.clone(),
    };
    let report = find_orbits(&req, &mut |line| eprintln!("{line}"))?;
    super::figure::write_bifurcation_diagram(&report, runup.as_ref(), &args.out)
        .map_err(|e| format!("{}: {e}", args.out.display()))?;
    if let Some(t) = report.linear_threshold_hz {
        println!("linear threshold: {t:.1} Hz");
    }
    if let Some(h) = report.hopf_estimate_hz {
        println!(
            "branch meets the equilibrium at {h:.1} Hz ({})",
            report
                .criticality
                .as_deref()
                .unwrap_or("criticality not decided")
        );
    }
    println!(
        "{} orbits, {} flows, {} macro steps, {:.1} s; written to {}",
        report.orbits.len(),
        report.flows,
        report.macro_steps,
        report.wall_time_s,
        args.out.join("orbits.json").display()
    );
    Ok(())
}
