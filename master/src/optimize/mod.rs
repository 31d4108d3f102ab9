//! `airring optimize`: which bearing to build. A search over design variables (clearance, step
//! height, mount stiffness and damping, ring mass, any film or rotor parameter) for the design
//! that best meets an objective while the requirement (film thickness, whirl amplitude, run-up
//! class over a speed range) holds at every corner of its tolerance box; the recommended design
//! verified by slow run-ups and run-downs on a finer film mesh, with the discretization error of
//! its deciding quantities.
//!
//! Modules: `problem` (the optimisation file), `evaluate` (a candidate at its corners, linear
//! stage first, run-ups where it leaves the answer open), `verify` (the recommendation re-run),
//! `outputs` (tables, the recommended design file, figures, the report). This file runs the
//! rounds: the search (`design_search`) asks for a batch of candidates, their corners' linear
//! analyses run in-process on all cores, their run-ups as one study through the sweep machinery
//! (`--jobs` at a time), and every finished candidate is appended to `evaluations.jsonl`, from
//! which an interrupted optimisation resumes.

pub mod evaluate;
pub mod outputs;
pub mod problem;
pub mod verify;

pub use evaluate::{Candidate, Corner, Stage};
pub use problem::Problem;

use crate::sweep::{self, RunSpec, Study, SweepOptions};
use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

pub struct OptimizeOptions {
    pub out: PathBuf,
    pub jobs: usize,
    /// The `airring` executable the run-ups are started with.
    pub exe: PathBuf,
    pub quiet: bool,
    pub stop: Arc<AtomicBool>,
    /// Skip the verification of the recommended design.
    pub no_verify: bool,
    /// Leave the run-ups to another runner (Dask, Slurm, `airring sweep`): write the study of
    /// the run-ups a round needs and stop ([`Outcome::pending`]) instead of running them.
    pub external_runs: bool,
}

/// What an optimisation produced.
pub struct Outcome {
    pub candidates: Vec<Candidate>,
    /// Index (into `candidates`) of the recommended design.
    pub best: Option<usize>,
    pub verification: Option<verify::Verification>,
    pub files: Vec<PathBuf>,
    pub wall_time_s: f64,
    /// The search stopped early (interrupt): run the command again to continue.
    pub interrupted: bool,
    /// With `external_runs`: the study file whose run-ups are to be run before the command
    /// runs again, and how many of them are not completed.
    pub pending: Option<(PathBuf, usize)>,
}

/// The file evaluations are appended to, one JSON candidate per line.
const EVALUATIONS: &str = "evaluations.jsonl";

/// The batch a round asked for, until its candidates are in `EVALUATIONS`: an interrupted
/// round (or one waiting for external run-ups) continues with the same candidates.
const PENDING: &str = "pending_batch.json";

/// Runs (or resumes) the optimisation `p` (its file's text `text`) into `opts.out`.
pub fn optimize(p: &Problem, text: &str, opts: &OptimizeOptions) -> Result<Outcome, String> {
    let start = Instant::now();
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    refuse_other_problem(&opts.out, text)?;
    crate::output::write_whole(&opts.out.join("optimization.toml"), text.as_bytes())?;
    let base = crate::sweep::linear::settings_for(&p.base).map_err(|e| format!("[base]: {e}"))?;
    let base_values = base_values(p, &base);
    let mut candidates = read_evaluations(&opts.out.join(EVALUATIONS), p)?;
    if !opts.quiet {
        eprintln!(
            "optimize '{}': {} variables, {} corners per candidate (nominal and tolerance box), \
             budget {}, {} evaluated before -> {}",
            p.name,
            p.dim(),
            p.corner_count(),
            p.budget,
            candidates.len(),
            opts.out.display()
        );
    }
    let method = match p.method {
        problem::SearchMethod::Ego => design_search::Method::Ego {
            initial: p.initial,
            batch: p.batch,
            seed: p.seed,
            // Candidates are rounded to 4 significant digits (they name the run folders): in
            // the unit cube of a variable spanning a decade or more, points closer than about
            // 1e-3 are one design.
            repeat_distance: 1e-3,
        },
        problem::SearchMethod::Random => design_search::Method::Random { seed: p.seed },
        problem::SearchMethod::Grid => design_search::Method::Grid,
    };
    let variables: Vec<design_search::Variable> =
        p.variables.iter().map(|v| v.bounds.clone()).collect();
    let n_constraints = constraint_count(p);
    let mut round = 0usize;
    let mut runner = RunUps {
        p,
        f_max_hz: base.f_max_hz,
        opts,
        all: vec![],
        pending: None,
    };
    // Runs the search already asked for go into the cumulative study again (names stay).
    for c in &candidates {
        runner.note(c);
    }
    // A round left unfinished (interrupted, or waiting for external run-ups) continues with its
    // own candidates before the search asks anew.
    let mut searched: Result<(), String> = Ok(());
    if let Some((first, xs)) = read_pending(&opts.out.join(PENDING), p) {
        // Candidates of the round already recorded (a process killed after recording its
        // round and before removing this file, or in between): the rest of it is what is left.
        let recorded = first.map_or(0, |f| candidates.len().saturating_sub(f));
        let xs = &xs[recorded.min(xs.len())..];
        if xs.is_empty() {
            let _ = std::fs::remove_file(opts.out.join(PENDING));
        } else if candidates.len() + xs.len() <= p.budget {
            searched = run_round(
                p,
                &base_values,
                xs,
                &mut candidates,
                &mut runner,
                &mut round,
            )
            .map(|_| ());
        } else {
            let _ = std::fs::remove_file(opts.out.join(PENDING));
        }
    }
    if searched.is_ok() {
        let done: Vec<design_search::Evaluation> =
            candidates.iter().map(|c| as_search(p, c)).collect();
        searched = design_search::search(
            &variables,
            p.objectives.len(),
            n_constraints,
            method,
            p.budget,
            done,
            |xs| {
                run_round(
                    p,
                    &base_values,
                    xs,
                    &mut candidates,
                    &mut runner,
                    &mut round,
                )
            },
        )
        .map(|_| ());
    }
    let pending = runner.pending.take();
    let interrupted = match searched {
        Ok(_) => false,
        Err(_) if pending.is_some() => true,
        Err(e) if opts.stop.load(Ordering::Relaxed) => {
            eprintln!("optimize interrupted ({e}): run the same command again to continue");
            true
        }
        Err(e) => return Err(e),
    };
    if let Some(pending) = pending {
        let best = best_of(p, &candidates);
        outputs::write_all(p, &candidates, best, None, &opts.out)?;
        return Ok(Outcome {
            best,
            candidates,
            verification: None,
            files: vec![],
            wall_time_s: start.elapsed().as_secs_f64(),
            interrupted,
            pending: Some(pending),
        });
    }
    let best = best_of(p, &candidates);
    let verification = match best {
        Some(b) if !opts.no_verify && !interrupted => {
            if !opts.quiet {
                eprintln!(
                    "verifying the recommended design at its {} corners: run-up and run-down in \
                     {} s each way, search mesh and {}x{}",
                    candidates[b].corners.len(),
                    p.verify_t_ramp_s,
                    p.verify_mesh.0,
                    p.verify_mesh.1
                );
            }
            match verify::verify(p, &candidates[b], base.f_max_hz, opts)? {
                verify::Verified::Done(v) => Some(v),
                verify::Verified::Pending(study, n) => {
                    outputs::write_all(p, &candidates, best, None, &opts.out)?;
                    return Ok(Outcome {
                        candidates,
                        best,
                        verification: None,
                        files: vec![],
                        wall_time_s: start.elapsed().as_secs_f64(),
                        interrupted: false,
                        pending: Some((study, n)),
                    });
                }
            }
        }
        _ => None,
    };
    let files = outputs::write_all(p, &candidates, best, verification.as_ref(), &opts.out)?;
    Ok(Outcome {
        candidates,
        best,
        verification,
        files,
        wall_time_s: start.elapsed().as_secs_f64(),
        interrupted,
        pending: None,
    })
}

/// One round: the candidates `xs` (as the search asked for them) rounded, evaluated (a design
/// evaluated before is reused), appended to the evaluations; their objective and constraints
/// as the search takes them.
fn run_round(
    p: &Problem,
    base_values: &BTreeMap<String, f64>,
    xs: &[Vec<f64>],
    candidates: &mut Vec<Candidate>,
    runner: &mut RunUps,
    round: &mut usize,
) -> Result<Vec<design_search::Outcome>, String> {
    let opts = runner.opts;
    *round += 1;
    let first = candidates.len();
    let t0 = Instant::now();
    let asked_xs = xs;
    let xs: Vec<Vec<f64>> = xs
        .iter()
        .map(|x| {
            p.variables
                .iter()
                .zip(x)
                .map(|(v, &x)| v.round(x))
                .collect()
        })
        .collect();
    // A design asked for again (values round alike) is not evaluated again: its result
    // is reused under the new number.
    let mut fresh: Vec<Vec<f64>> = vec![];
    for x in &xs {
        if !fresh.contains(x) && !candidates.iter().any(|c| &c.x == x) {
            fresh.push(x.clone());
        }
    }
    // The points as asked (not rounded): a resumed round gives the search the same points.
    let asked = serde_json::to_string(&PendingBatch {
        first,
        asked: asked_xs.to_vec(),
    })
    .map_err(|e| e.to_string())?;
    crate::output::write_whole(&opts.out.join(PENDING), asked.as_bytes())?;
    let evaluated = evaluate_batch(p, base_values, &fresh, first, runner)?;
    let mut batch: Vec<Candidate> = vec![];
    for (i, x) in xs.iter().enumerate() {
        let earlier = candidates.iter().chain(&batch).find(|c| &c.x == x);
        let c = match earlier {
            Some(same) => Candidate {
                index: first + i,
                reason: format!("the design of #{} again: {}", same.index, same.reason),
                asked: asked_xs[i].clone(),
                ..same.clone()
            },
            None => Candidate {
                index: first + i,
                asked: asked_xs[i].clone(),
                ..evaluated
                    .iter()
                    .find(|c| &c.x == x)
                    .expect("evaluated above")
                    .clone()
            },
        };
        batch.push(c);
    }
    let evaluations = batch
        .iter()
        .map(|c| as_search(p, c))
        .map(|e| (e.objectives, e.constraints))
        .collect();
    append_evaluations(&opts.out.join(EVALUATIONS), &batch)?;
    let _ = std::fs::remove_file(opts.out.join(PENDING));
    if !opts.quiet {
        for c in &batch {
            eprintln!("{}", progress_line(p, c));
        }
        candidates.extend(batch);
        eprintln!(
            "round {}: {} candidates in {:.0} s; {} evaluated, best feasible: {}",
            *round,
            xs.len(),
            t0.elapsed().as_secs_f64(),
            candidates.len(),
            best_of(p, candidates).map_or("none yet".into(), |b| describe(p, &candidates[b]))
        );
    } else {
        candidates.extend(batch);
    }
    Ok(evaluations)
}

/// An output folder holding another optimisation (another file's text) is refused: its
/// evaluations would be taken for this one's.
fn refuse_other_problem(out: &Path, text: &str) -> Result<(), String> {
    let old = out.join("optimization.toml");
    match std::fs::read_to_string(&old) {
        Ok(t) if t != text => Err(format!(
            "{} holds another optimisation (its optimization.toml differs from this file): \
             choose another --out, or remove that folder",
            out.display()
        )),
        _ => Ok(()),
    }
}

/// The nominal values of the quantities a tolerance may name, from the base design.
fn base_values(p: &Problem, s: &crate::runup::RunupSettings) -> BTreeMap<String, f64> {
    let mut v = BTreeMap::from([
        ("clearance".to_string(), s.clearance_um),
        ("dh".to_string(), s.dh_um),
        ("c".to_string(), s.c_n_per_mm),
        ("d".to_string(), s.d_n_s_per_m),
        ("m_r".to_string(), s.m_r_g),
    ]);
    for (k, text) in &p.base {
        if let Ok(x) = text.trim().parse::<f64>() {
            v.insert(k.clone(), x);
        }
    }
    v
}

/// The number of constraints the search sees: film, then whirl and class where required.
pub fn constraint_count(p: &Problem) -> usize {
    1 + usize::from(p.max_whirl_um.is_some()) + usize::from(!p.classes.is_empty())
}

/// A candidate as the search holds it: the objectives, to minimise, and the constraints.
pub(crate) fn as_search(p: &Problem, c: &Candidate) -> design_search::Evaluation {
    design_search::Evaluation {
        // The point the search asked for (candidates of earlier versions: the rounded one).
        x: if c.asked.is_empty() {
            c.x.clone()
        } else {
            c.asked.clone()
        },
        objectives: p
            .objectives
            .iter()
            .zip(&c.objectives)
            .map(|(o, &v)| evaluate::to_minimise(o, v))
            .collect(),
        constraints: c.constraints.clone(),
    }
}

/// The recommended candidate: the best feasible one by the first objective.
pub fn best_of(p: &Problem, candidates: &[Candidate]) -> Option<usize> {
    let o = &p.objectives[0];
    candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.feasible && c.objectives[0].is_finite())
        .min_by(|a, b| {
            evaluate::to_minimise(o, a.1.objectives[0])
                .total_cmp(&evaluate::to_minimise(o, b.1.objectives[0]))
        })
        .map(|(i, _)| i)
}

/// Where no candidate is feasible: the one nearest to meeting the requirement (largest margin,
/// the normalized distance to the nearest limit, negative when a limit is missed).
pub fn closest_of(candidates: &[Candidate]) -> Option<usize> {
    candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.margin.is_finite())
        .max_by(|a, b| a.1.margin.total_cmp(&b.1.margin))
        .map(|(i, _)| i)
}

/// "C = 18.2 um, c = 812 N/mm".
pub fn describe_x(p: &Problem, x: &[f64]) -> String {
    p.variables
        .iter()
        .zip(x)
        .map(|(v, x)| {
            let (short, unit) = crate::sweep::short_and_unit(&v.key);
            if unit.is_empty() {
                format!("{short} = {x}")
            } else {
                format!("{short} = {x} {unit}")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn describe(p: &Problem, c: &Candidate) -> String {
    let o = &p.objectives[0];
    format!(
        "#{} ({}; {} = {})",
        c.index,
        describe_x(p, &c.x),
        o.quantity.key(&p.variables),
        outputs::fmt(c.objectives[0])
    )
}

fn progress_line(p: &Problem, c: &Candidate) -> String {
    format!(
        "  #{} {}: {} by the {} stage, film {} um, whirl {} um ({})",
        c.index,
        describe_x(p, &c.x),
        if c.feasible { "feasible" } else { "infeasible" },
        match c.stage {
            Stage::Linear => "linear",
            Stage::Nonlinear => "nonlinear",
        },
        outputs::fmt(c.min_film_um),
        outputs::fmt(c.whirl_um),
        c.reason
    )
}

fn read_evaluations(path: &Path, p: &Problem) -> Result<Vec<Candidate>, String> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(vec![]),
        Err(e) => return Err(format!("{}: {e}", path.display())),
    };
    let mut out = vec![];
    for (i, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        match serde_json::from_str::<Candidate>(line) {
            Ok(c) if c.x.len() == p.dim() => out.push(c),
            // A line cut by a kill mid-write: the candidates after it are evaluated again.
            Ok(_) | Err(_) => {
                eprintln!(
                    "warning: {} line {}: not a candidate of this problem; it and what follows \
                     are evaluated again",
                    path.display(),
                    i + 1
                );
                break;
            }
        }
    }
    // Evaluations numbered as they were found, whatever the file held.
    for (i, c) in out.iter_mut().enumerate() {
        c.index = i;
    }
    if out.len() != text.lines().filter(|l| !l.trim().is_empty()).count() {
        let kept: String = out
            .iter()
            .map(|c| serde_json::to_string(c).expect("json") + "\n")
            .collect();
        crate::output::write_whole(path, kept.as_bytes())?;
    }
    Ok(out)
}

fn append_evaluations(path: &Path, batch: &[Candidate]) -> Result<(), String> {
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut text = String::new();
    for c in batch {
        text += &serde_json::to_string(c).map_err(|e| e.to_string())?;
        text.push('\n');
    }
    f.write_all(text.as_bytes())
        .and_then(|_| f.sync_data())
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// A label for a corner: "nominal", or each toleranced key's short name with - or +.
fn corner_label(p: &Problem, k: usize) -> String {
    if k == 0 {
        return "nominal".into();
    }
    let mask = k - 1;
    p.tolerances
        .iter()
        .enumerate()
        .map(|(bit, (key, _))| {
            let short = crate::sweep::short_and_unit(key).0;
            format!("{short}{}", if mask & (1 << bit) == 0 { '-' } else { '+' })
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The run-ups of the nonlinear stage: one cumulative study of every corner that needed one,
/// run through the sweep machinery into `OUT/nonlinear` (completed runs are skipped).
struct RunUps<'a> {
    p: &'a Problem,
    f_max_hz: f64,
    opts: &'a OptimizeOptions,
    /// Every run-up case so far (the study's cases), in order.
    all: Vec<BTreeMap<String, String>>,
    /// With external runs: the study written and its run-ups not completed.
    pending: Option<(PathBuf, usize)>,
}

impl RunUps<'_> {
    /// The run-up keys of a corner: its design, and a run-up to f_max and down again in place of
    /// f_max and t_ramp.
    fn case(&self, corner_args: &BTreeMap<String, String>) -> BTreeMap<String, String> {
        let mut a = corner_args.clone();
        a.remove("f_max");
        a.remove("t_ramp");
        a
    }

    fn note(&mut self, c: &Candidate) {
        for corner in &c.corners {
            if corner.nonlinear.is_some() {
                let case = self.case(&corner.args);
                if !self.all.contains(&case) {
                    self.all.push(case);
                }
            }
        }
    }

    /// The keys every run-up of the search shares: the run-up and run-down, and the halt at
    /// the film limit within the speed range: a run-up whose film falls below the limit has
    /// decided its corner (it fails), and the rest of it (the whirl after onset, the run-down)
    /// is the slow part. There is no halt at the whirl limit: a whirl stopped there measures
    /// just above its limit whatever the design, and the search loses how far a design is from
    /// safe (design notes, "Optimisation").
    fn fixed(&self) -> BTreeMap<String, String> {
        let t = self.p.t_ramp_s;
        let (lo, hi) = self.p.speed_range_hz;
        BTreeMap::from([
            (
                "profile".to_string(),
                format!("0:0,{t}:{f},{t2}:0", f = self.f_max_hz, t2 = 2.0 * t),
            ),
            ("halt_film".to_string(), self.p.min_film_um.to_string()),
            ("halt_speeds".to_string(), format!("{lo}:{hi}")),
        ])
    }

    /// Runs the cases `wanted` (with all earlier ones in the study) and returns each one's
    /// folder name.
    fn run(&mut self, wanted: &[BTreeMap<String, String>]) -> Result<Vec<String>, String> {
        for w in wanted {
            if !self.all.contains(w) {
                self.all.push(w.clone());
            }
        }
        let dir = self.opts.out.join("nonlinear");
        let fixed = self.fixed();
        let (study, text) = study_of(&self.p.name, &self.all, &fixed, &dir)?;
        if self.opts.external_runs {
            if let Some(n) = write_for_others(&study, &text, &dir)? {
                self.pending = Some((dir.join("study.toml"), n));
                return Err(format!("{n} run-ups are left to another runner"));
            }
            return wanted.iter().map(|w| run_of(&study, w, &fixed)).collect();
        }
        let opts = sweep_options(self.opts, dir);
        let report = sweep::sweep(&study, &text, &opts)?;
        if self.opts.stop.load(Ordering::Relaxed) || !report.interrupted.is_empty() {
            return Err("stopped during the run-ups".into());
        }
        wanted.iter().map(|w| run_of(&study, w, &fixed)).collect()
    }
}

/// How the optimisation's run-ups run as a study into `dir`: `--jobs` at a time, in folders the
/// optimisation owns (replaced without asking), stopped by its stop signal.
pub(crate) fn sweep_options(opts: &OptimizeOptions, dir: PathBuf) -> SweepOptions {
    SweepOptions {
        out: dir,
        jobs: opts.jobs,
        serial_films: 2 * opts.jobs > sweep::cores(),
        shard: None,
        exe: opts.exe.clone(),
        quiet: opts.quiet,
        overwrite: true,
        stop: opts.stop.clone(),
        checkpoint_every_s: None,
    }
}

/// With external runs: writes `dir/study.toml` and returns how many of its run-ups are not
/// completed in `dir/runs` (None: all are).
pub(crate) fn write_for_others(
    study: &Study,
    text: &str,
    dir: &Path,
) -> Result<Option<usize>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    crate::output::write_whole(&dir.join("study.toml"), text.as_bytes())?;
    let open = study
        .runs
        .iter()
        .filter(|r| !sweep::is_done(&dir.join("runs").join(&r.name), &r.args))
        .count();
    Ok((open > 0).then_some(open))
}

/// What `pending_batch.json` holds: the points a round asked for and the index of its first
/// candidate.
#[derive(serde::Serialize, serde::Deserialize)]
struct PendingBatch {
    first: usize,
    asked: Vec<Vec<f64>>,
}

/// The batch an unfinished round asked for and its first candidate's index, if its file is
/// there and fits the problem (a file of earlier versions, the bare points: its round starts
/// after the candidates recorded, `None`).
fn read_pending(path: &Path, p: &Problem) -> Option<(Option<usize>, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path).ok()?;
    let (first, xs) = match serde_json::from_str::<PendingBatch>(&text) {
        Ok(b) => (Some(b.first), b.asked),
        Err(_) => (None, serde_json::from_str::<Vec<Vec<f64>>>(&text).ok()?),
    };
    (!xs.is_empty() && xs.iter().all(|x| x.len() == p.dim())).then_some((first, xs))
}

/// The study (and its file's text) of run-up cases: every case with the `fixed` keys (its speed
/// profile, a halt); `dir` names the file in messages.
pub(crate) fn study_of(
    name: &str,
    cases: &[BTreeMap<String, String>],
    fixed: &BTreeMap<String, String>,
    dir: &Path,
) -> Result<(Study, String), String> {
    let mut text = format!("name = {}\n[fixed]\n", toml_str(&format!("{name}-runs")));
    for (k, v) in fixed {
        text += &format!("{} = {}\n", toml_key(k), toml_str(v));
    }
    // One grid per set of keys (a study's cases of one grid set the same keys): the
    // verification's runs on the search mesh set none, those on the fine mesh set `mesh`.
    type Group<'a> = (Vec<&'a String>, Vec<&'a BTreeMap<String, String>>);
    let mut groups: Vec<Group> = vec![];
    for c in cases {
        let keys: Vec<&String> = c.keys().collect();
        match groups.iter_mut().find(|g| g.0 == keys) {
            Some(g) => g.1.push(c),
            None => groups.push((keys, vec![c])),
        }
    }
    for (_, group) in groups {
        text += "[[grid]]\ncases = [\n";
        for c in group {
            let entries: Vec<String> = c
                .iter()
                .map(|(k, v)| format!("{} = {}", toml_key(k), toml_str(v)))
                .collect();
            text += &format!("  {{ {} }},\n", entries.join(", "));
        }
        text += "]\n";
    }
    let study = Study::parse(&text, &dir.join("study.toml"))?;
    Ok((study, text))
}

fn toml_str(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

fn toml_key(k: &str) -> String {
    if k.chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        k.to_string()
    } else {
        toml_str(k)
    }
}

/// The run of `study` whose flags are `case` with the `fixed` keys.
fn run_of(
    study: &Study,
    case: &BTreeMap<String, String>,
    fixed: &BTreeMap<String, String>,
) -> Result<String, String> {
    let mut want = case.clone();
    want.extend(fixed.iter().map(|(k, v)| (k.clone(), v.clone())));
    study
        .runs
        .iter()
        .find(|r: &&RunSpec| r.args == want)
        .map(|r| r.name.clone())
        .ok_or_else(|| format!("internal: no run for {want:?} in the study"))
}

/// Evaluates a batch of candidates (rounded values), numbered from `first`.
fn evaluate_batch(
    p: &Problem,
    base_values: &BTreeMap<String, f64>,
    xs: &[Vec<f64>],
    first: usize,
    runner: &mut RunUps,
) -> Result<Vec<Candidate>, String> {
    // Corners of every candidate; a candidate whose corners are no design fails as a whole.
    let mut corners: Vec<Result<Vec<Corner>, String>> = vec![];
    for x in xs {
        corners.push(p.corners(x, base_values).map(|cs| {
            cs.into_iter()
                .enumerate()
                .map(|(k, args)| Corner {
                    label: corner_label(p, k),
                    args,
                    linear: Default::default(),
                    nonlinear: None,
                    stage: Stage::Linear,
                    min_film_um: f64::NAN,
                    whirl_um: f64::NAN,
                    class: None,
                    ok: false,
                    reason: String::new(),
                })
                .collect()
        }));
    }
    // Stage 1 on all cores: each corner's linear analysis on its own.
    let jobs: Vec<(usize, usize)> = corners
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.as_ref().ok().map(|c| (i, c.len())))
        .flat_map(|(i, n)| (0..n).map(move |k| (i, k)))
        .collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let workers = sweep::cores().min(jobs.len()).max(1);
    let results: Vec<(usize, usize, evaluate::LinearResult)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = vec![];
                    loop {
                        let j = next.fetch_add(1, Ordering::Relaxed);
                        let Some(&(i, k)) = jobs.get(j) else { break };
                        let args = &corners[i].as_ref().expect("ok")[k].args;
                        mine.push((i, k, evaluate::linear_stage(p, args)));
                    }
                    mine
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("linear stage worker panicked"))
            .collect()
    });
    for (i, k, r) in results {
        if let Ok(cs) = corners[i].as_mut() {
            cs[k].linear = r;
        }
    }
    // Stage 2: the corners the linear stage leaves open, for candidates not already failed
    // (a corner statically too thin decides the candidate without run-ups). In two passes:
    // first each candidate's likeliest failure, the open corner with the lowest linear
    // threshold; the others only for candidates that pass it. An infeasible candidate costs
    // one run-up instead of one per corner, and whirling run-ups are the slow ones.
    let mut open: Vec<(usize, Vec<usize>)> = vec![];
    for (i, cs) in corners.iter().enumerate() {
        let Ok(cs) = cs else { continue };
        let decisions: Vec<_> = cs
            .iter()
            .map(|c| evaluate::linear_decision(p, &c.linear))
            .collect();
        if decisions.iter().any(|d| matches!(d, Some((false, _)))) {
            continue;
        }
        let mut ks: Vec<usize> = (0..cs.len()).filter(|&k| decisions[k].is_none()).collect();
        ks.sort_by(|&a, &b| {
            let t = |k: usize| cs[k].linear.threshold_hz.unwrap_or(f64::INFINITY);
            t(a).total_cmp(&t(b))
        });
        if !ks.is_empty() {
            open.push((i, ks));
        }
    }
    let runs = runner.opts.out.join("nonlinear").join("runs");
    for pass in 0..2 {
        let mut wanted = vec![];
        let mut wanted_at = vec![];
        for (i, ks) in &open {
            let cs = corners[*i].as_ref().expect("ok");
            let first_failed = cs[ks[0]]
                .nonlinear
                .as_ref()
                .is_some_and(|n| !evaluate::nonlinear_decision(p, n).0);
            let these: &[usize] = match pass {
                0 => &ks[..1],
                _ if first_failed => &[],
                _ => &ks[1..],
            };
            for &k in these {
                wanted.push(runner.case(&cs[k].args));
                wanted_at.push((*i, k));
            }
        }
        if wanted.is_empty() {
            continue;
        }
        let names = runner.run(&wanted)?;
        for ((i, k), name) in wanted_at.into_iter().zip(names) {
            let r = evaluate::nonlinear_result(&runs.join(&name), &name, p.speed_range_hz);
            corners[i].as_mut().expect("ok")[k].nonlinear = Some(r);
        }
    }
    Ok(corners
        .into_iter()
        .zip(xs)
        .enumerate()
        .map(|(i, (cs, x))| match cs {
            Ok(mut cs) => {
                for c in &mut cs {
                    evaluate::decide_corner(p, c);
                }
                evaluate::summarize(p, first + i, x.clone(), cs)
            }
            Err(e) => {
                let mut c = evaluate::summarize(p, first + i, x.clone(), vec![]);
                c.feasible = false;
                c.reason = e;
                (c.min_film_um, c.whirl_um, c.margin) = (f64::NAN, f64::NAN, f64::NAN);
                c.constraints = vec![f64::NAN; constraint_count(p)];
                c
            }
        })
        .collect())
}
