//! Checkpoints: the FMU states (fmi2SerializeFMUstate) and the master's own state.
//!
//! A checkpoint is a generation: its state files carry the generation's tag in their names
//! (`film_C.<tag>.state`), are written and synced first, and only then does `master.json`, also
//! written to a temporary file, synced and renamed, point to them (with each file's length and
//! checksum). A write cut short at any moment (a kill, a full disk) therefore leaves the previous
//! `master.json` and the files it names intact; the files of older generations are removed only
//! after the new `master.json` is in place. A resume checks every file against `master.json`.

use crate::algorithm::AlgorithmState;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use std::path::Path;

/// (instance name, byte length, FNV-1a 64 checksum) of a state file.
pub type StateCheck = (String, u64, u64);

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
    /// The generation of the state files (`<instance>.<tag>.state`); None in checkpoints written
    /// before generations existed (`<instance>.state`).
    #[serde(default)]
    pub states_tag: Option<String>,
    /// Per instance: its state file's check; empty in older checkpoints (then unchecked).
    #[serde(default)]
    pub state_checks: Vec<StateCheck>,
    /// FNV-1a 64 of timeseries.csv's first `csv_bytes` bytes (None in older checkpoints, or
    /// when no series is written).
    #[serde(default)]
    pub csv_check: Option<u64>,
    /// Which run this checkpoint belongs to (None in older checkpoints: then unchecked).
    #[serde(default)]
    pub identity: Option<RunIdentity>,
    /// End of the long-step window the run closed (`step_plan`): no long steps before it.
    #[serde(default)]
    pub long_steps_closed_until_s: Option<f64>,
    /// Macro steps taken and, of them, long ones (None in older checkpoints, which had no long
    /// steps: then `step_index` steps).
    #[serde(default)]
    pub macro_steps_taken: Option<(u64, u64)>,
}

/// What makes a run itself: a resume continues a checkpoint only into the run that wrote it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunIdentity {
    /// FNV-1a 64 of the run folder's system.toml, as the run started from it.
    pub system_check: u64,
    /// When the run started from t = 0 [ms since the Unix epoch]; kept through resumes.
    pub started_unix_ms: u64,
    /// (instance, GUID of its FMU), in subsystem order.
    pub guids: Vec<(String, String)>,
}

impl RunIdentity {
    /// A run starting now from `system_text` with these (instance, GUID) pairs.
    pub fn new(system_text: &[u8], guids: Vec<(String, String)>) -> Self {
        let started_unix_ms = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_millis() as u64);
        RunIdentity {
            system_check: checksum(system_text),
            started_unix_ms,
            guids,
        }
    }

    /// Why `self` (from the checkpoint) is not the run `now` would continue (None: it is).
    pub fn mismatch(
        &self,
        now_system_text: &[u8],
        now_guids: &[(String, String)],
    ) -> Option<String> {
        if checksum(now_system_text) != self.system_check {
            return Some(
                "system.toml was changed after the checkpoint was written (its checksum differs)"
                    .into(),
            );
        }
        if self.guids != now_guids {
            let show = |g: &[(String, String)]| {
                g.iter()
                    .map(|(i, g)| format!("{i}={g}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Some(format!(
                "the FMUs are not the ones the checkpoint was written with (now {}; then {})",
                show(now_guids),
                show(&self.guids)
            ));
        }
        None
    }
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
            states_tag: None,
            state_checks: vec![],
            csv_check: None,
            identity: None,
            long_steps_closed_until_s: None,
            macro_steps_taken: None,
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

/// FNV-1a 64 of `bytes`: detects a truncated, corrupted or swapped state file (not an attack).
pub fn checksum(bytes: &[u8]) -> u64 {
    checksum_continue(FNV_START, bytes)
}

/// The FNV-1a 64 state before any byte.
pub const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a 64 continued over `bytes` from the state `h` (a checksum kept while a file grows).
pub fn checksum_continue(h: u64, bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(h, |h, b| (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3))
}

fn state_file(name: &str, tag: Option<&str>) -> String {
    match tag {
        Some(t) => format!("{name}.{t}.state"),
        None => format!("{name}.state"),
    }
}

/// A tag no earlier generation of this folder has: the macro-step index and the wall clock.
fn new_tag(step_index: u64) -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!("{step_index}-{nanos}")
}

/// Writes the state files of a new generation (step 1 of a checkpoint); returns its tag and
/// the files' checks for `master.json`.
fn write_states(
    cp: &Path,
    names: &[String],
    states: &[Vec<u8>],
    step_index: u64,
) -> std::io::Result<(String, Vec<StateCheck>)> {
    let tag = new_tag(step_index);
    let mut checks: Vec<StateCheck> = Vec::with_capacity(names.len());
    for (n, s) in names.iter().zip(states) {
        if let Err(e) = crate::files::write_whole(&cp.join(state_file(n, Some(&tag))), s) {
            // The generation is incomplete: its files are garbage (the previous one still holds).
            for done in &checks {
                let _ = std::fs::remove_file(cp.join(state_file(&done.0, Some(&tag))));
            }
            return Err(e);
        }
        checks.push((n.clone(), s.len() as u64, checksum(s)));
    }
    Ok((tag, checks))
}

/// Writes `dir/checkpoint/`: a new generation of state files, then `master.json` naming it,
/// then removes the state files of older generations (see the module documentation).
pub fn write(
    dir: &Path,
    names: &[String],
    states: &[Vec<u8>],
    master: &MasterState,
) -> std::io::Result<()> {
    let cp = dir.join("checkpoint");
    // A linked checkpoint folder is refused: the old generations removed below would be another
    // run's files.
    crate::files::real_folder(&cp)?;
    let (tag, checks) = write_states(&cp, names, states, master.step_index)?;
    let master = MasterState {
        states_tag: Some(tag.clone()),
        state_checks: checks,
        ..master.clone()
    };
    let current: Vec<String> = names.iter().map(|n| state_file(n, Some(&tag))).collect();
    if let Err(e) = crate::files::write_whole(
        &cp.join("master.json"),
        serde_json::to_string_pretty(&master)
            .expect("plain data")
            .as_bytes(),
    ) {
        // The new generation is not named by master.json: garbage (the previous one holds).
        for f in &current {
            let _ = std::fs::remove_file(cp.join(f));
        }
        return Err(e);
    }
    // Older generations are garbage now; failing to remove them loses nothing.
    for e in std::fs::read_dir(&cp)?.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.ends_with(".state") && !current.contains(&name) {
            let _ = std::fs::remove_file(e.path());
        }
    }
    Ok(())
}

/// Removes a run folder's checkpoint (a fresh run into a reused folder must not leave one that a
/// later `resume` would continue from).
pub fn remove(dir: &Path) -> std::io::Result<()> {
    let cp = dir.join("checkpoint");
    if crate::files::is_symlink(&cp) {
        // The link goes, what it points to stays.
        return std::fs::remove_file(&cp);
    }
    match std::fs::remove_dir_all(&cp) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

pub fn read(dir: &Path, names: &[String]) -> Result<(MasterState, Vec<Vec<u8>>), String> {
    let cp = dir.join("checkpoint");
    if crate::files::is_symlink(&cp) {
        // A resume writes new generations into it and removes the old ones: not through a link.
        return Err(format!(
            "{} is a symbolic link: a run is resumed only from a checkpoint folder of its own \
             (AirRing does not write or delete through links in a run folder)",
            cp.display()
        ));
    }
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
            let file = state_file(n, m.states_tag.as_deref());
            let bytes = std::fs::read(cp.join(&file))
                .map_err(|e| format!("{}/{file}: {e}", cp.display()))?;
            if let Some((_, len, sum)) = m.state_checks.iter().find(|c| &c.0 == n) {
                if bytes.len() as u64 != *len || checksum(&bytes) != *sum {
                    let what = if bytes.len() as u64 != *len {
                        format!("{} bytes, expected {len}", bytes.len())
                    } else {
                        format!("{len} bytes as expected, but their checksum differs")
                    };
                    return Err(format!(
                        "{}/{file}: does not match master.json ({what}): the checkpoint is \
                         damaged",
                        cp.display(),
                    ));
                }
            } else if !m.state_checks.is_empty() {
                return Err(format!(
                    "{}/master.json: no check for instance '{n}'",
                    cp.display()
                ));
            }
            Ok(bytes)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((m, states))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("cosim-cp-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn master(step: u64) -> MasterState {
        let state = AlgorithmState {
            t_s: step as f64 * 1e-3,
            histories: vec![VecDeque::new(), VecDeque::new()],
            refine_level: 0,
        };
        MasterState::new(&state, step, step, 1.0)
    }

    #[test]
    fn a_write_cut_short_leaves_the_previous_checkpoint_whole() {
        let dir = tmp("cut");
        let names = vec!["a".to_string(), "b".to_string()];
        write(&dir, &names, &[vec![1; 100], vec![2; 50]], &master(10)).unwrap();
        // The next checkpoint's state files are written, then the process dies before its
        // master.json: the first checkpoint still reads back, whole.
        let cp = dir.join("checkpoint");
        write_states(&cp, &names, &[vec![3; 7], vec![4; 7]], 20).unwrap();
        // ... also with a half-written master.json.tmp left behind.
        std::fs::write(cp.join("master.json.tmp"), "{ \"format\": 1, \"t_b").unwrap();
        let (m, states) = read(&dir, &names).unwrap();
        assert_eq!(m.step_index, 10);
        assert_eq!(states, [vec![1; 100], vec![2; 50]]);
        // A complete write replaces it and removes every older state file.
        write(&dir, &names, &[vec![5; 9], vec![6; 9]], &master(30)).unwrap();
        let (m, states) = read(&dir, &names).unwrap();
        assert_eq!(m.step_index, 30);
        assert_eq!(states, [vec![5; 9], vec![6; 9]]);
        let n_state_files = std::fs::read_dir(&cp)
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().ends_with(".state"))
            .count();
        assert_eq!(n_state_files, 2);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn truncated_or_swapped_state_files_are_refused() {
        let dir = tmp("damaged");
        let names = vec!["film_C".to_string(), "film_T".to_string()];
        write(
            &dir,
            &names,
            &[vec![1, 2, 3, 4], vec![5, 6, 7, 8]],
            &master(3),
        )
        .unwrap();
        let (m, _) = read(&dir, &names).unwrap();
        let cp = dir.join("checkpoint");
        let file = |n: &str| cp.join(state_file(n, m.states_tag.as_deref()));
        // Swapped: same lengths, other content.
        let (c, t) = (
            std::fs::read(file("film_C")).unwrap(),
            std::fs::read(file("film_T")).unwrap(),
        );
        std::fs::write(file("film_C"), &t).unwrap();
        std::fs::write(file("film_T"), &c).unwrap();
        let e = read(&dir, &names).unwrap_err();
        assert!(e.contains("film_C") && e.contains("damaged"), "{e}");
        // Same length, other bytes: said so (not "4 bytes, expected 4").
        assert!(
            e.contains("4 bytes as expected, but their checksum differs"),
            "{e}"
        );
        // Truncated.
        std::fs::write(file("film_C"), &c[..2]).unwrap();
        let e = read(&dir, &names).unwrap_err();
        assert!(e.contains("2 bytes, expected 4"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn checkpoints_of_earlier_versions_still_read() {
        // The oldest layout: <instance>.state, no tag, no checks.
        let dir = tmp("old");
        let cp = dir.join("checkpoint");
        std::fs::create_dir_all(&cp).unwrap();
        std::fs::write(cp.join("rotor.state"), [9u8; 5]).unwrap();
        let mut m = master(7);
        m.refine_level = 2;
        let mut v = serde_json::to_value(&m).unwrap();
        let o = v.as_object_mut().unwrap();
        o.remove("states_tag");
        o.remove("state_checks");
        std::fs::write(cp.join("master.json"), v.to_string()).unwrap();
        let (back, states) = read(&dir, &["rotor".to_string()]).unwrap();
        assert_eq!(back.step_index, 7);
        assert_eq!(back.refine_level, 2);
        assert_eq!(states, [vec![9u8; 5]]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
