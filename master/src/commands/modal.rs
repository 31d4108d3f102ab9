//! `airring modal`: modal analysis of the rotor with linear film springs, or of a flexible rotor
//! read from a ROSS rotor file (`--rotor`) on that file's linear bearings.

use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Rotor speed [Hz] (several: Campbell data).
    #[arg(long, num_args = 1.., default_values_t = vec![1000.0])]
    pub speed: Vec<f64>,
    /// Ring mount stiffness [N/mm].
    #[arg(long, default_value_t = 500.0)]
    pub c: f64,
    /// Ring mount damping [N s/m].
    #[arg(long, default_value_t = 0.0)]
    pub d: f64,
    /// Isotropic air-film stiffness [N/mm].
    #[arg(long, default_value_t = 2000.0)]
    pub film_stiffness: f64,
    /// Ring mass [g].
    #[arg(long, default_value_t = 50.0)]
    pub m_r: f64,
    /// A flexible rotor: a rotor file saved by ROSS 2.3.0 (`Rotor.save("rotor.toml")`), its
    /// shaft elements, disks and linear bearings as they are. Replaces the paper's rigid rotor and
    /// its ring flags.
    #[arg(long, conflicts_with_all = ["c", "d", "film_stiffness", "m_r"])]
    pub rotor: Option<PathBuf>,
    /// With --rotor: critical speeds of the first N modes (damped frequency = speed).
    #[arg(long, default_value_t = 8, requires = "rotor")]
    pub critical_speeds: usize,
    /// With --rotor: the response to an imbalance of this size [g mm] at every --speed.
    #[arg(long, requires_all = ["rotor", "unbalance_node"])]
    pub unbalance: Option<f64>,
    /// The node of the imbalance (0 at the shaft's first end).
    #[arg(long, requires = "unbalance")]
    pub unbalance_node: Option<usize>,
    /// The imbalance's phase [deg].
    #[arg(long, default_value_t = 0.0, requires = "unbalance")]
    pub unbalance_phase: f64,
    /// Output folder for modal.json and the Campbell diagram (campbell.svg/.png).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn execute(a: Args) -> Result<ExitCode, String> {
    let Args {
        speed,
        c,
        d,
        film_stiffness,
        m_r,
        rotor,
        critical_speeds,
        unbalance,
        unbalance_node,
        unbalance_phase,
        out,
    } = a;
    if let Some(rotor) = rotor {
        let u = unbalance.map(|g_mm| master::flexible::Unbalance {
            node: unbalance_node.unwrap_or(0),
            g_mm,
            phase_deg: unbalance_phase,
        });
        return master::flexible::modal(&rotor, &speed, critical_speeds, u, out.as_deref())
            .map(|_| ExitCode::SUCCESS);
    }
    master::modal::modal(&speed, c, d, film_stiffness, m_r, out.as_deref())
        .map(|_| ExitCode::SUCCESS)
}
