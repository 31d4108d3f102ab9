//! Everything that watches a run attaches through [`Observer`] (after libcosim's `observer` and
//! rapier's `EventHandler`): the time-series file, progress displays, in-memory series, an
//! application's own analysis. Every method has a no-op default, so an observer implements only
//! what it watches; the run loop knows none of them.

use crate::algorithm::{CoSim, Event};
use crate::checkpoint::MasterState;
pub use crate::error::ObserverError;
use crate::report::RunReport;
use crate::setup::Recorded;

/// The run as an observer first sees it.
pub struct RunStart<'a> {
    /// The recorded variables, in column order (time comes first in every row and is not listed).
    pub columns: &'a [Recorded],
    /// The checkpoint the run resumes from (None: a fresh run from t = 0).
    pub resumed_from: Option<&'a MasterState>,
    pub stop_time_s: f64,
    /// Simulated time between output samples [s].
    pub output_interval_s: f64,
    /// Threads that wait on the parallel groups' pool and may do an observer's per-sample work
    /// in small pieces ([`crate::parallel::IdleWork`]); None when the run has no such pool.
    pub idle_workers: Option<crate::parallel::IdleWorkers>,
}

/// A watcher of a run. An error ([`ObserverError`]) ends the run as failed, its text in the
/// report.
pub trait Observer {
    /// Before the first macro step (also of a resumed run). Any observer may still refuse the
    /// run here: change nothing a refused run must leave as it was (do that in [`Self::begun`]).
    fn started(&mut self, _run: &RunStart<'_>) -> Result<(), ObserverError> {
        Ok(())
    }

    /// Every observer has accepted the start: the run goes ahead. Called in order after all
    /// [`Self::started`] calls succeeded; the place to replace a folder's old outputs.
    fn begun(&mut self, _run: &RunStart<'_>) -> Result<(), ObserverError> {
        Ok(())
    }

    /// An output sample: the recorded variables at time `t_s`, in column order.
    fn sample(&mut self, _t_s: f64, _values: &[f64]) -> Result<(), ObserverError> {
        Ok(())
    }

    /// At every macro point, after its samples: the co-simulation as it stands.
    fn macro_point(&mut self, _cosim: &CoSim, _stop_time_s: f64) {}

    /// Whether the run has shown what it was run for (a limit it was to watch is crossed):
    /// `Some(reason)` ends it at this macro point, before its stop time, as completed and
    /// halted (`RunReport::halted`). Asked at every macro point after its samples. A halted run
    /// writes no checkpoint: it is finished, not interrupted.
    fn halt(&self) -> Option<String> {
        None
    }

    /// Something the algorithm did (a roll-back, ...).
    fn event(&mut self, _event: &Event) {}

    /// A checkpoint is being written: make everything observed so far durable, and record in
    /// `state` what a resume needs (the time-series writer records its byte count).
    fn checkpoint(&mut self, _state: &mut MasterState) -> Result<(), ObserverError> {
        Ok(())
    }

    /// The run has ended (completed, interrupted or failed); `report` says which.
    fn finished(&mut self, _cosim: &CoSim, _report: &RunReport) -> Result<(), ObserverError> {
        Ok(())
    }
}
