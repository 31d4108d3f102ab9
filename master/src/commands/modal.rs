//! `airring modal`: modal analysis of the rotor with linear film springs.

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
        out,
    } = a;
    master::modal::modal(&speed, c, d, film_stiffness, m_r, out.as_deref())
        .map(|_| ExitCode::SUCCESS)
}
