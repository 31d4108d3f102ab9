//! Checkpoints: the FMU states (fmi2SerializeFMUstate) and the master's own state, written
//! atomically (temporary file, then rename) so a crash during a write leaves the previous one intact.

use crate::algorithm::AlgorithmState;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use std::path::Path;

/// The master's own state in `checkpoint/master.json` (the FMU states are files beside it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MasterState {
    pub format: u32,
    /// Time and macro-step index, as f64 bits (exact).
    pub t_bits: u64,
    pub step_index: u64,
    pub next_output_index: u64,
    /// Bytes of timeseries.csv at the checkpoint (a resume cuts the file there).
    pub csv_bytes: u64,
    /// Per subsystem: coupling history points (time bits, value bits).
    pub histories: Vec<Vec<(u64, Vec<u64>)>>,
    /// Wall time already spent before this checkpoint.
    pub wall_before_s: f64,
    /// Refinement level of the macro-step control (0 in checkpoints written before it existed).
    #[serde(default)]
    pub refine_level: u32,
}

pub const FORMAT: u32 = 1;

impl MasterState {
    /// The master's state at a macro point; `csv_bytes` is left 0 for the time-series writer to
    /// fill in (`Observer::checkpoint`).
    pub fn new(
        state: &AlgorithmState,
        step_index: u64,
        next_output_index: u64,
        wall_before_s: f64,
    ) -> Self {
        MasterState {
            format: FORMAT,
            t_bits: state.t_s.to_bits(),
            step_index,
            next_output_index,
            csv_bytes: 0,
            histories: state.histories.iter().map(encode_history).collect(),
            wall_before_s,
            refine_level: state.refine_level,
        }
    }

    /// The algorithm's state this checkpoint holds.
    pub fn algorithm_state(&self) -> AlgorithmState {
        AlgorithmState {
            t_s: f64::from_bits(self.t_bits),
            histories: self.histories.iter().map(|h| decode_history(h)).collect(),
            refine_level: self.refine_level,
        }
    }
}

pub fn encode_history(h: &VecDeque<(f64, Vec<f64>)>) -> Vec<(u64, Vec<u64>)> {
    h.iter()
        .map(|(t, v)| (t.to_bits(), v.iter().map(|x| x.to_bits()).collect()))
        .collect()
}

pub fn decode_history(h: &[(u64, Vec<u64>)]) -> VecDeque<(f64, Vec<f64>)> {
    h.iter()
        .map(|(t, v)| {
            (
                f64::from_bits(*t),
                v.iter().map(|x| f64::from_bits(*x)).collect(),
            )
        })
        .collect()
}

fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}

/// Writes `dir/checkpoint/` (one `.state` file per instance, then `master.json` last, so a
/// `master.json` always refers to complete state files).
pub fn write(
    dir: &Path,
    names: &[String],
    states: &[Vec<u8>],
    master: &MasterState,
) -> std::io::Result<()> {
    let cp = dir.join("checkpoint");
    std::fs::create_dir_all(&cp)?;
    for (n, s) in names.iter().zip(states) {
        write_atomic(&cp.join(format!("{n}.state")), s)?;
    }
    write_atomic(
        &cp.join("master.json"),
        serde_json::to_string_pretty(master)
            .expect("plain data")
            .as_bytes(),
    )
}

pub fn read(dir: &Path, names: &[String]) -> Result<(MasterState, Vec<Vec<u8>>), String> {
    let cp = dir.join("checkpoint");
    let text = std::fs::read_to_string(cp.join("master.json"))
        .map_err(|e| format!("{}: no checkpoint ({e})", cp.display()))?;
    let m: MasterState =
        serde_json::from_str(&text).map_err(|e| format!("{}/master.json: {e}", cp.display()))?;
    if m.format != FORMAT {
        return Err(format!(
            "checkpoint format {} is not supported (expected {FORMAT})",
            m.format
        ));
    }
    let states = names
        .iter()
        .map(|n| {
            std::fs::read(cp.join(format!("{n}.state")))
                .map_err(|e| format!("{}/{n}.state: {e}", cp.display()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((m, states))
}
