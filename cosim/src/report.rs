//! How a run ended and where its time went: what the run loop hands back and observers see last.

use crate::step_control::ControlStats;

/// How a run ended and where its time went.
#[derive(Debug, Default, serde::Serialize)]
pub struct RunReport {
    pub completed: bool,
    /// Set when an observer ended the run before its stop time ([`crate::Observer::halt`]):
    /// its reason. Such a run is completed: it ran until it had shown what it was run for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub halted: Option<String>,
    pub interrupted: bool,
    pub error: Option<String>,
    pub t_end_s: f64,
    /// Macro steps taken (a long step counts once).
    pub macro_steps: u64,
    /// Of those, the long ones (`step_plan`; None without a plan).
    pub long_macro_steps: Option<u64>,
    /// Times [s] at which a rejected or discarded step closed the rest of a long-step window
    /// (since the start or the resumed checkpoint).
    pub long_steps_closed_at_s: Vec<f64>,
    pub retries: u64,
    pub wall_time_s: f64,
    /// Wall time in each subsystem's fmi2DoStep, and everything else (the master's own work).
    pub wall_per_subsystem_s: Vec<(String, f64)>,
    pub master_overhead_s: f64,
    /// Parts of the master's own time: state saving, coupling (polynomials, get/set), thread hand-over.
    pub master_parts_s: Vec<(String, f64)>,
    /// How the parallel groups were stepped: threads or one after the other, chosen by measurement
    /// (None: no parallel group, or parallel off).
    pub group_stepping: Option<crate::parallel_choice::SteppingStats>,
    /// What the macro-step control did (None: fixed macro step).
    pub control: Option<ControlStats>,
    /// Integer outputs of each FMU at the end (solver counters such as the air film's
    /// `n_pressure_floored`; counted since the start or the resumed checkpoint).
    pub counters: Vec<(String, Vec<(String, i32)>)>,
}
