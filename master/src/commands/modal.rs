//! `airring modal`: modal analysis of the rotor with linear film springs, or of a flexible rotor
//! read from a ROSS rotor file (`--rotor`) on that file's linear bearings.

use master::error::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Rotor speed [Hz] (several: Campbell data).
    #[arg(long, num_args = 1.., default_values_t = vec![1000.0])]
    pub speed: Vec<f64>,
    /// Ring mount stiffness [N/mm] [default: 500].
    #[arg(long)]
    pub c: Option<f64>,
    /// Ring mount damping [N s/m] [default: 0].
    #[arg(long)]
    pub d: Option<f64>,
    /// Isotropic air-film stiffness [N/mm] [default: 2000].
    #[arg(long)]
    pub film_stiffness: Option<f64>,
    /// Ring mass [g] [default: 50].
    #[arg(long)]
    pub m_r: Option<f64>,
    /// A flexible rotor: a rotor file saved by ROSS 2.3.0 (`Rotor.save("rotor.toml")`), its
    /// shaft elements, disks and linear bearings as they are, or a design file's [shaft] table,
    /// instead of the paper's rigid rotor.
    #[arg(long)]
    pub rotor: Option<PathBuf>,
    /// With --rotor: air ring bearings (ring, mount and film springs as the flags above) at these
    /// nodes, in place of the file's bearings there.
    #[arg(long, num_args = 1.., value_delimiter = ',', requires = "rotor")]
    pub bearing_nodes: Vec<usize>,
    /// With --rotor: critical speeds (damped frequency = speed) of the first N modes [default:
    /// every mode below twice the highest --speed at rest, at least below 1 kHz].
    #[arg(long, requires = "rotor")]
    pub critical_speeds: Option<usize>,
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

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args {
        speed,
        c,
        d,
        film_stiffness,
        m_r,
        rotor,
        bearing_nodes,
        critical_speeds,
        unbalance,
        unbalance_node,
        unbalance_phase,
        out,
    } = a;
    let ring_flags = [
        c.is_some(),
        d.is_some(),
        film_stiffness.is_some(),
        m_r.is_some(),
    ];
    let rings = master::modal::RingFlags {
        c_n_per_mm: c.unwrap_or(500.0),
        d_n_s_per_m: d.unwrap_or(0.0),
        film_n_per_mm: film_stiffness.unwrap_or(2000.0),
        m_r_g: m_r.unwrap_or(50.0),
    };
    if let Some(rotor) = rotor {
        if bearing_nodes.is_empty() && ring_flags.iter().any(|&given| given) {
            return Err(Error::Flag(
                "--c, --d, --film-stiffness and --m-r describe air ring bearings: with \
                        --rotor they need --bearing-nodes"
                    .into(),
            ));
        }
        let u = unbalance.map(|g_mm| master::flexible::Unbalance {
            node: unbalance_node.unwrap_or(0),
            g_mm,
            phase_deg: unbalance_phase,
        });
        let rings = (!bearing_nodes.is_empty()).then_some((bearing_nodes.as_slice(), rings));
        return master::flexible::modal(&rotor, &speed, rings, critical_speeds, u, out.as_deref())
            .map(|_| ExitCode::SUCCESS);
    }
    master::modal::modal(&speed, &rings, out.as_deref()).map(|_| ExitCode::SUCCESS)
}
