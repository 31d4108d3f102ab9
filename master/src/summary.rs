//! `summary.json`, the one record of how a run ended and what it showed, written and read through
//! one typed struct. Every field has a default, so folders of earlier versions (and the failure
//! summaries a sweep writes for run-ups that wrote none) read back.

use cosim::{ControlStats, RunReport};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// How a run ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    Completed,
    Interrupted,
    #[default]
    Failed,
    /// Written when a run starts: a folder left with it was killed (SIGKILL, power loss) before
    /// it could write how it ended; its checkpoint, if any, can be resumed.
    Running,
}

impl RunStatus {
    pub fn as_str(self) -> &'static str {
        match self {
            RunStatus::Completed => "completed",
            RunStatus::Interrupted => "interrupted",
            RunStatus::Failed => "failed",
            RunStatus::Running => "running",
        }
    }
}

/// Each bearing's nominal clearance [um], as the analysis used it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClearancesUm {
    #[serde(rename = "C")]
    pub c: f64,
    #[serde(rename = "T")]
    pub t: f64,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RunSummary {
    pub status: RunStatus,
    pub interrupted: bool,
    /// Why a run that was to halt on a limit (`runup --halt-film`) ended before its stop time:
    /// the limit crossed, where and when. The run is completed; its series ends there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub halted: Option<String>,
    pub error: Option<String>,
    pub t_end_s: Option<f64>,
    pub macro_steps: Option<u64>,
    /// Of those, the long steps taken where the run was planned calm (`calm_steps` in the
    /// settings; None: no plan, or a folder of an earlier version).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub long_macro_steps: Option<u64>,
    /// Where a rejected or discarded step ended the calm window early [s] (the run was not as
    /// calm as the linear analysis said; since the start or the resumed checkpoint).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub calm_window_closed_at_s: Vec<f64>,
    pub retried_macro_steps: Option<u64>,
    pub macro_step_control: Option<ControlStats>,
    pub wall_time_s: Option<f64>,
    /// Wall time in each FMU instance's fmi2DoStep [s].
    pub wall_in_fmus_s: BTreeMap<String, f64>,
    /// The master's own wall time [s] and its parts.
    pub master_overhead_s: Option<f64>,
    pub master_overhead_parts_s: BTreeMap<String, f64>,
    pub master_overhead_percent: Option<f64>,
    /// Whether the films stepped in two threads or one after the other (chosen by measurement as the
    /// run went; None: serial by request, or a folder of an earlier version).
    #[serde(default)]
    pub group_stepping: Option<cosim::parallel_choice::SteppingStats>,
    /// Integer outputs (solver counters) of each FMU instance at the end.
    pub fmu_counters: BTreeMap<String, BTreeMap<String, i32>>,
    /// The run-up settings (or the system file of `airring run`), as the command got them.
    pub settings: serde_json::Value,
    /// Each bearing's clearance the analysis normalised with (run-ups only).
    pub clearance_um: Option<ClearancesUm>,
    pub classification: Option<String>,
    /// Set when the classification covers only the part of the run that was simulated.
    pub classification_note: Option<String>,
    pub onset_time_s: Option<f64>,
    pub onset_speed_hz: Option<f64>,
    #[serde(rename = "max_eps_C")]
    pub max_eps_c: Option<f64>,
    #[serde(rename = "max_eps_T")]
    pub max_eps_t: Option<f64>,
    pub first_bearing: Option<String>,
    pub criteria: Option<String>,
    /// Each criterion's value, bound and relative margin (analysis::classify::Criterion).
    pub margins: Option<Vec<crate::analysis::classify::Criterion>>,
    /// A deciding criterion lies within 10 % of its bound (None in folders of earlier versions).
    pub borderline: Option<bool>,
    pub whirl: Option<serde_json::Value>,
    /// Friction power loss of the films [W]: at the quoted speeds and at most (run-ups whose
    /// films report `power_loss`).
    pub power_loss_w: Option<crate::analysis::PowerLossSummary>,
    /// Where the whirl started going up and stopped coming down (runs whose speed profile has a
    /// run-down).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis: Option<crate::analysis::Hysteresis>,
    /// File names of the figures written into the run folder.
    pub plots: Option<Vec<String>>,
    pub plot_error: Option<String>,
}

impl RunSummary {
    /// The generic part from the run's report (no run-up analysis yet).
    pub fn of_report(report: &RunReport, settings: serde_json::Value) -> Self {
        RunSummary {
            status: if report.completed {
                RunStatus::Completed
            } else if report.interrupted {
                RunStatus::Interrupted
            } else {
                RunStatus::Failed
            },
            interrupted: report.interrupted,
            halted: report.halted.clone(),
            error: report.error.clone(),
            t_end_s: Some(report.t_end_s),
            macro_steps: Some(report.macro_steps),
            long_macro_steps: report.long_macro_steps,
            calm_window_closed_at_s: report.long_steps_closed_at_s.clone(),
            retried_macro_steps: Some(report.retries),
            macro_step_control: report.control,
            group_stepping: report.group_stepping,
            wall_time_s: Some(report.wall_time_s),
            wall_in_fmus_s: report.wall_per_subsystem_s.iter().cloned().collect(),
            master_overhead_s: Some(report.master_overhead_s),
            master_overhead_parts_s: report.master_parts_s.iter().cloned().collect(),
            master_overhead_percent: Some(
                100.0 * report.master_overhead_s / report.wall_time_s.max(1e-12),
            ),
            fmu_counters: report
                .counters
                .iter()
                .map(|(sub, c)| (sub.clone(), c.iter().cloned().collect()))
                .collect(),
            settings,
            ..RunSummary::default()
        }
    }

    /// The summary of a run that has started and not ended yet (what a killed run leaves).
    pub fn running(settings: serde_json::Value) -> Self {
        RunSummary {
            status: RunStatus::Running,
            settings,
            ..RunSummary::default()
        }
    }

    /// A failure summary for a run that wrote none (a crash, bad flags, a kill).
    pub fn failure(error: String) -> Self {
        RunSummary {
            status: RunStatus::Failed,
            error: Some(error),
            ..RunSummary::default()
        }
    }

    /// Reads `dir/summary.json`; None if it is missing or not a summary.
    pub fn read(dir: &Path) -> Option<Self> {
        let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// Writes `dir/summary.json` whole or not at all (a temporary file renamed over it), so a
    /// full disk never leaves a truncated or empty summary.
    pub fn write(&self, dir: &Path) -> Result<(), String> {
        let path = dir.join("summary.json");
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        crate::output::write_whole(&path, text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_summary_round_trips() {
        let report = RunReport {
            completed: true,
            t_end_s: 3.0,
            macro_steps: 150_000,
            wall_time_s: 70.0,
            master_overhead_s: 1.0,
            wall_per_subsystem_s: vec![("film_C".into(), 30.0)],
            counters: vec![("film_C".into(), vec![("n_newton".into(), 7)])],
            ..RunReport::default()
        };
        let mut s = RunSummary::of_report(&report, serde_json::json!({ "preset": "path1" }));
        s.classification = Some("path1".into());
        s.max_eps_c = Some(1.2);
        s.clearance_um = Some(ClearancesUm { c: 20.0, t: 25.0 });
        let text = serde_json::to_string_pretty(&s).unwrap();
        // The names earlier versions wrote (and scripts read).
        for key in [
            "\"status\": \"completed\"",
            "\"max_eps_C\": 1.2",
            "\"T\": 25.0",
        ] {
            assert!(text.contains(key), "{key} in {text}");
        }
        let back: RunSummary = serde_json::from_str(&text).unwrap();
        assert_eq!(back, s);
    }

    #[test]
    fn summaries_of_earlier_versions_and_failures_read_back() {
        // Written by an older run-up (no clearances, no counters) ...
        let old = r#"{ "status": "interrupted", "interrupted": true, "error": null,
            "classification": null, "onset_time_s": null, "max_eps_C": null, "max_eps_T": null,
            "settings": { "clearance_um": 20.0 }, "wall_time_s": 12.5 }"#;
        let s: RunSummary = serde_json::from_str(old).unwrap();
        assert_eq!(s.status, RunStatus::Interrupted);
        assert_eq!(s.wall_time_s, Some(12.5));
        assert_eq!(s.clearance_um, None);
        // ... and by a sweep for a run-up that wrote none.
        let failed = r#"{ "status": "failed", "error": "exit code 101", "wall_time_s": null }"#;
        let s: RunSummary = serde_json::from_str(failed).unwrap();
        assert_eq!(s.status, RunStatus::Failed);
        assert_eq!(s.error.as_deref(), Some("exit code 101"));
        assert!(serde_json::from_str::<RunSummary>(r#"{ "status": "bogus" }"#).is_err());
    }
}
