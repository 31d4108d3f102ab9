//! `airring sweep-orbits STUDY`: every cell of a parameter study classified from its whirl
//! orbits instead of a run-up (docs/orbits.md, "The classes from the orbits").
//!
//! A run-up answers "which whirl does the rotor fall into at this ramp rate from this start";
//! the orbits answer "which whirls exist at constant speed". Per cell:
//!
//! 1. The linear threshold f_H (`airring stability`). None up to the top speed: `stable`. Below
//!    a tenth of the top speed: `unstable_low_speed` (the run-up classifier's bound, applied to
//!    the threshold instead of the visible onset).
//! 2. Otherwise the constant-speed simulation settles at f_H (1 + `above`) (just past the
//!    threshold: the whirl the Hopf point gives birth to, or the large whirl it jumps to) and at
//!    the top speed, from the centred start; a periodic whirl is shot on the full state
//!    (`airring orbits --full-state`) for its Floquet multipliers.
//! 3. The run-up classifier's three features, read off the settled whirls with the same
//!    bounds: *large* (RMS whirl amplitude above 0.5 C or eccentricity above 1 at either speed),
//!    *speed-proportional* (whirl-frequency elasticity ln(f2/f1) / ln(s2/s1) between the two
//!    speeds at least 0.6) and *two frequencies* (the two bearings whirling at frequencies more
//!    than 5 % apart at either speed); the class is `path_class` of them, as for a run-up.
//!    A speed where the simulation came to rest and the linear analysis finds the equilibrium
//!    stable again has no whirl; a speed where no whirl settled otherwise (still growing, dying
//!    out where the equilibrium is unstable, a failed simulation) leaves the cell `undecided`,
//!    with the reason.

use super::driver::{
    find_orbits, linear_threshold, top_speed_hz, OrbitRecord, OrbitsRequest, SettledRecord,
};
use crate::analysis::classify::{path_class, Bounds, BORDERLINE_MARGIN, FREQ_SPLIT_REL};
use crate::sweep::Study;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

#[derive(Clone, Debug)]
pub struct SweepOrbitsOptions {
    pub out: PathBuf,
    /// Constant-speed simulation per speed before its whirl counts as settled [s].
    pub settle_s: f64,
    /// The first speed lies this fraction above the linear threshold.
    pub above: f64,
    /// Cells simulated at once (each steps its films one after the other when > 1).
    pub jobs: usize,
    /// A run-up study table (a sweep's study.csv) whose classes are compared cell by cell.
    pub compare: Option<PathBuf>,
    pub fmu_dir: PathBuf,
}

/// One cell's orbit class and the evidence it rests on (`cells/<run>/cell.json`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CellOrbits {
    pub run: String,
    /// The study's parameters of the cell and the settle time and first-speed offset it was
    /// computed with: a stored cell is reused only when all three are those asked for now.
    #[serde(default)]
    pub args: BTreeMap<String, String>,
    #[serde(default)]
    pub settle_s: f64,
    #[serde(default)]
    pub above: f64,
    /// The run-up defaults it was computed with (`sweep::defaults_of`): a stored cell with other
    /// ones, or none (an older airring), is computed again rather than mixed into the map.
    #[serde(default)]
    pub defaults: Option<serde_json::Value>,
    pub linear_threshold_hz: Option<f64>,
    pub linear_note: Option<String>,
    pub top_speed_hz: f64,
    /// The constant speeds simulated [Hz] (none when the threshold decides).
    pub speeds_hz: Vec<f64>,
    pub settled: Vec<SettledRecord>,
    /// The least damped mode's growth rate at each settled speed (linear analysis) [1/s].
    #[serde(default)]
    pub linear_growth_per_s: Vec<f64>,
    /// The orbits shot from the settled whirls (a shooting that stalls leaves its speed out; its
    /// settled record says why).
    pub orbits: Vec<OrbitRecord>,
    /// Whirl-frequency elasticity between the first and the last speed.
    pub elasticity: Option<f64>,
    /// "stable", "unstable_low_speed", "path1", "path2a", "path2b" or "undecided".
    pub class: String,
    pub why: String,
    #[serde(default)]
    pub borderline: bool,
    /// The run-up's class of the same cell (from `--compare`; filled on every call, so a
    /// resumed study compares with the table given now).
    #[serde(default)]
    pub runup_class: Option<String>,
    pub wall_time_s: f64,
}

/// The constant speeds of a cell with threshold `threshold_hz`: `above` past it, and the top
/// speed when that lies more than 5 % higher.
pub fn cell_speeds(threshold_hz: f64, top_hz: f64, above: f64) -> Vec<f64> {
    let first = ((threshold_hz * (1.0 + above)).min(top_hz) * 10.0).round() / 10.0;
    if top_hz > 1.05 * first {
        vec![first, top_hz]
    } else {
        vec![first]
    }
}

/// A cell's class from its orbits.
#[derive(Clone, Debug, PartialEq)]
pub struct OrbitClass {
    pub class: String,
    pub why: String,
    pub elasticity: Option<f64>,
    /// A deciding criterion lies within `BORDERLINE_MARGIN` of its bound (as for a run-up).
    pub borderline: bool,
}

fn decided(class: &str, why: String) -> OrbitClass {
    OrbitClass {
        class: class.into(),
        why,
        elasticity: None,
        borderline: false,
    }
}

/// The class of a cell from its threshold and the whirls settled at its speeds (module
/// documentation); `linear_growth_per_s` holds the least damped mode's growth rate at each
/// settled speed (empty when unknown).
pub fn orbit_class(
    threshold_hz: Option<f64>,
    top_hz: f64,
    settled: &[SettledRecord],
    linear_growth_per_s: &[f64],
    b: &Bounds,
) -> OrbitClass {
    let Some(f_h) = threshold_hz else {
        return decided(
            "stable",
            format!("no linear threshold up to {top_hz} Hz: no whirl branch is born in range"),
        );
    };
    if f_h < b.low_speed_fraction * top_hz {
        return decided(
            "unstable_low_speed",
            format!(
                "linear threshold {f_h:.1} Hz below {} of the top speed",
                b.low_speed_fraction
            ),
        );
    }
    if settled.is_empty() {
        return decided("undecided", "no speed simulated".into());
    }
    // The speeds with a whirl; a speed whose simulation came to rest where the linear analysis
    // finds the equilibrium stable again (an unstable band that closes below the top speed)
    // has none; any other speed without a settled whirl leaves the cell open.
    let mut whirls: Vec<&SettledRecord> = vec![];
    let mut quiet = vec![];
    for (k, s) in settled.iter().enumerate() {
        let restabilized = linear_growth_per_s.get(k).is_some_and(|g| *g < 0.0);
        match s.motion.as_str() {
            "periodic" | "quasi-periodic" => whirls.push(s),
            "equilibrium" | "decaying" if restabilized => quiet.push(s.speed_hz),
            _ => {
                return decided(
                    "undecided",
                    format!(
                        "at {:.1} Hz (threshold {f_h:.1} Hz) no whirl settled: {}{}",
                        s.speed_hz,
                        s.motion,
                        s.message
                            .as_ref()
                            .map_or(String::new(), |m| format!(" ({m})"))
                    ),
                );
            }
        }
    }
    let quiet_text = if quiet.is_empty() {
        String::new()
    } else {
        format!(
            "; the equilibrium is stable again at {} Hz (linear analysis and simulation)",
            quiet
                .iter()
                .map(|f| format!("{f:.0}"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    if whirls.is_empty() {
        return decided(
            "stable",
            format!("threshold {f_h:.1} Hz, but no whirl at the speeds simulated{quiet_text}"),
        );
    }
    let settled = whirls;
    let mut largest = (0.0_f64, 0.0_f64, 0.0_f64); // (rms amplitude / C, eps, at speed)
    let mut large = false;
    let mut two_freq = false;
    for s in &settled {
        let rms = s
            .whirl_rms_c
            .unwrap_or(0.0)
            .max(s.whirl_rms_t.unwrap_or(0.0));
        let eps = s.max_eps_c.unwrap_or(0.0).max(s.max_eps_t.unwrap_or(0.0));
        if rms > b.large_whirl_amp_rel || eps > b.large_eps {
            large = true;
        }
        if rms >= largest.0 {
            largest = (rms, eps, s.speed_hz);
        }
        // Two frequencies as the run-up classifier counts them: the bearings whirling at
        // frequencies more than FREQ_SPLIT_REL apart (a spread of one bearing's periods alone
        // is a whirl still modulated, not two whirls).
        if let Some([fc, ft]) = s.bearing_whirl_frequencies_hz {
            two_freq |= (fc - ft).abs() > FREQ_SPLIT_REL * fc.max(ft);
        }
    }
    let elasticity = match (settled.first(), settled.last()) {
        (Some(a), Some(z)) if settled.len() > 1 => {
            match (a.whirl_frequency_hz, z.whirl_frequency_hz) {
                (Some(fa), Some(fz)) if fa > 0.0 && fz > 0.0 => {
                    Some((fz / fa).ln() / (z.speed_hz / a.speed_hz).ln())
                }
                _ => None,
            }
        }
        _ => None,
    };
    let proportional = elasticity.is_some_and(|e| e >= b.proportional_elasticity);
    let class = path_class(large, proportional, two_freq);
    let max_eps = settled
        .iter()
        .map(|s| s.max_eps_c.unwrap_or(0.0).max(s.max_eps_t.unwrap_or(0.0)))
        .fold(0.0, f64::max);
    let why = format!(
        "threshold {f_h:.1} Hz; large={large} (largest RMS whirl amplitude {:.3} C at {:.0} Hz vs {}, \
         largest eps {max_eps:.3} vs {}); speed-proportional={proportional} (elasticity {} vs {}); \
         two-frequencies={two_freq}{quiet_text}",
        largest.0,
        largest.2,
        b.large_whirl_amp_rel,
        b.large_eps,
        elasticity.map_or("-".into(), |e| format!("{e:.3}")),
        b.proportional_elasticity,
    );
    // Borderline as for a run-up: a large whirl whose every exceeding size criterion lies
    // within the margin of its bound, a moderate one with a size criterion within the margin
    // under it, or an elasticity within the margin of its bound where it decides 1 against 2b.
    let rel = |v: f64, bound: f64| (v - bound) / bound;
    let sizes = [
        rel(largest.0, b.large_whirl_amp_rel),
        rel(max_eps, b.large_eps),
    ];
    let size_borderline = if large {
        sizes
            .iter()
            .filter(|m| **m > 0.0)
            .all(|m| *m < BORDERLINE_MARGIN)
            && !two_freq
    } else {
        sizes.iter().any(|m| m.abs() < BORDERLINE_MARGIN)
    };
    let elasticity_borderline = large
        && elasticity.is_some_and(|e| rel(e, b.proportional_elasticity).abs() < BORDERLINE_MARGIN);
    OrbitClass {
        class: class.as_str().into(),
        why,
        elasticity,
        borderline: size_borderline || elasticity_borderline,
    }
}

/// `airring sweep-orbits`: every cell of `study` (resumable: a cell with its cell.json is read,
/// not simulated again); writes orbit_classes.csv and orbit_classes.json into `opts.out`.
pub fn sweep_orbits(
    study: &Study,
    opts: &SweepOrbitsOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Vec<CellOrbits>, String> {
    if !(opts.settle_s.is_finite() && opts.settle_s > 0.0) {
        return Err(format!(
            "--settle {} s: must be a positive time",
            opts.settle_s
        ));
    }
    if !(opts.above.is_finite() && opts.above > 0.0 && opts.above <= 1.0) {
        return Err(format!(
            "--above {}: the first speed's distance above the threshold must lie in (0, 1]",
            opts.above
        ));
    }
    if opts.jobs == 0 {
        return Err("--jobs 0: at least one cell at a time".into());
    }
    let runup_classes = match &opts.compare {
        Some(p) => Some(read_classes(p)?),
        None => None,
    };
    // Every cell's settings first: a bad cell is refused before hours of simulation.
    let mut settings = Vec::with_capacity(study.runs.len());
    for spec in &study.runs {
        // The linear settings ignore the run-up's imbalance keys: refuse them here, as
        // `airring orbits` refuses an imbalance.
        for key in ["imbalance_c", "imbalance_t"] {
            if let Some(v) = spec.args.get(key) {
                if !v.trim().parse::<f64>().is_ok_and(|m| m == 0.0) {
                    return Err(format!(
                        "run {}: {key} = {v}: an imbalance forces the rotor at its spin frequency, \
                         its whirls are then not periodic orbits; leave it out of the study",
                        spec.name
                    ));
                }
            }
        }
        let mut s = crate::sweep::linear::settings_for(&spec.args)
            .map_err(|e| format!("run {}: {e}", spec.name))?;
        s.serial_films = opts.jobs > 1;
        super::cosim_flow::check_autonomous(&s).map_err(|e| format!("run {}: {e}", spec.name))?;
        settings.push(s);
    }
    let cells_dir = opts.out.join("cells");
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    cosim::files::real_folder(&cells_dir).map_err(|e| format!("{}: {e}", cells_dir.display()))?;
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<CellOrbits, String>>>> =
        Mutex::new(vec![None; study.runs.len()]);
    let n = study.runs.len();
    std::thread::scope(|scope| {
        for _ in 0..opts.jobs.min(n.max(1)) {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::SeqCst);
                if k >= n {
                    break;
                }
                let name = &study.runs[k].name;
                let dir = cells_dir.join(name);
                let line = |m: &str| progress(&format!("[{}/{n}] {name}: {m}", k + 1));
                let cell = match read_cell(&dir, &settings[k]) {
                    Some(c)
                        if c.args != study.runs[k].args
                            || c.settle_s != opts.settle_s
                            || c.above != opts.above =>
                    {
                        let e = format!(
                            "{} holds this cell computed with other parameters or settings \
                             ({:?}, --settle {}, --above {}; asked for now: {:?}, --settle {}, \
                             --above {}): give another --out, or remove that folder to compute it again",
                            dir.join("cell.json").display(),
                            c.args,
                            c.settle_s,
                            c.above,
                            study.runs[k].args,
                            opts.settle_s,
                            opts.above
                        );
                        line(&format!("failed: {e}"));
                        Err(e)
                    }
                    Some(c)
                        if c.defaults.as_ref()
                            == Some(&crate::sweep::defaults_of(&study.runs[k].args)) =>
                    {
                        line(&format!("{} (done earlier)", c.class));
                        Ok(c)
                    }
                    stale => {
                        if stale.is_some() {
                            line(
                                "stored with other run-up defaults (an older airring): \
                                 computing it again",
                            );
                        }
                        // A panic in one cell is that cell's failure, not the study's end.
                        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                            classify_cell(
                                name,
                                &study.runs[k].args,
                                &settings[k],
                                opts,
                                &dir,
                                &line,
                            )
                        }))
                        .unwrap_or_else(|p| {
                            Err(format!(
                                "internal error: {}",
                                p.downcast_ref::<&str>()
                                    .map(|s| s.to_string())
                                    .or_else(|| p.downcast_ref::<String>().cloned())
                                    .unwrap_or_default()
                            ))
                        });
                        match &r {
                            Ok(c) => {
                                line(&format!("{} ({:.0} s): {}", c.class, c.wall_time_s, c.why))
                            }
                            Err(e) => line(&format!("failed: {e}")),
                        }
                        r
                    }
                };
                results.lock().unwrap_or_else(|e| e.into_inner())[k] = Some(cell);
            });
        }
    });
    let results = results.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut cells = Vec::with_capacity(n);
    let mut failed = vec![];
    for (spec, r) in study.runs.iter().zip(results) {
        match r {
            Some(Ok(mut c)) => {
                c.runup_class = runup_classes.as_ref().and_then(|m| m.get(&c.run)).cloned();
                cells.push(c)
            }
            Some(Err(e)) => failed.push(format!("{}: {e}", spec.name)),
            None => failed.push(format!("{}: not run", spec.name)),
        }
    }
    write_tables(&opts.out, &cells)?;
    if !failed.is_empty() {
        return Err(format!(
            "{} of {n} cells failed (the others are written to {}; run again to retry):\n{}",
            failed.len(),
            opts.out.display(),
            failed.join("\n")
        ));
    }
    Ok(cells)
}

/// The least damped mode's growth rate [1/s] at each speed (empty when the analysis fails: the
/// class then treats a speed at rest as undecided).
fn growth_at(settings: &crate::runup::RunupSettings, speeds_hz: &[f64]) -> Vec<f64> {
    crate::stability::analyse(settings, speeds_hz)
        .map(|r| r.speeds.iter().map(|s| s.max_growth_per_s()).collect())
        .unwrap_or_default()
}

/// A cell done earlier, its class decided again from its stored evidence (so a changed
/// decision applies without simulating again); the linear growth rates at its speeds are
/// computed when the file predates them.
fn read_cell(dir: &Path, settings: &crate::runup::RunupSettings) -> Option<CellOrbits> {
    let text = std::fs::read_to_string(dir.join("cell.json")).ok()?;
    let mut c: CellOrbits = serde_json::from_str(&text).ok()?;
    if c.linear_growth_per_s.is_empty() && !c.settled.is_empty() {
        let speeds: Vec<f64> = c.settled.iter().map(|r| r.speed_hz).collect();
        c.linear_growth_per_s = growth_at(settings, &speeds);
    }
    let oc = orbit_class(
        c.linear_threshold_hz,
        c.top_speed_hz,
        &c.settled,
        &c.linear_growth_per_s,
        &Bounds::default(),
    );
    (c.class, c.why, c.elasticity, c.borderline) = (oc.class, oc.why, oc.elasticity, oc.borderline);
    Some(c)
}

fn classify_cell(
    name: &str,
    args: &BTreeMap<String, String>,
    settings: &crate::runup::RunupSettings,
    opts: &SweepOrbitsOptions,
    dir: &Path,
    progress: &dyn Fn(&str),
) -> Result<CellOrbits, String> {
    let t0 = std::time::Instant::now();
    let top = top_speed_hz(settings);
    let (threshold, linear_note) = linear_threshold(settings);
    if let (None, Some(note)) = (threshold, &linear_note) {
        if note.starts_with("the linear analysis failed") {
            return Err(note.clone());
        }
    }
    let b = Bounds::default();
    let decided_by_threshold = threshold.is_none_or(|f| f < b.low_speed_fraction * top);
    let (speeds, settled, orbits, growth) = if decided_by_threshold {
        (vec![], vec![], vec![], vec![])
    } else {
        let speeds = cell_speeds(threshold.unwrap_or(top), top, opts.above);
        let req = OrbitsRequest {
            settings: settings.clone(),
            speeds_hz: speeds.clone(),
            settle_s: opts.settle_s,
            continuation: false,
            full_state: true,
            fmu_dir: opts.fmu_dir.clone(),
            out_dir: dir.to_path_buf(),
        };
        let report = find_orbits(&req, &mut |m| progress(m))?;
        let speeds_settled: Vec<f64> = report.settled.iter().map(|r| r.speed_hz).collect();
        let growth = growth_at(settings, &speeds_settled);
        (speeds, report.settled, report.orbits, growth)
    };
    let oc = orbit_class(threshold, top, &settled, &growth, &b);
    let cell = CellOrbits {
        run: name.into(),
        args: args.clone(),
        settle_s: opts.settle_s,
        above: opts.above,
        defaults: Some(crate::sweep::defaults_of(args)),
        linear_threshold_hz: threshold,
        linear_note,
        top_speed_hz: top,
        speeds_hz: speeds,
        settled,
        linear_growth_per_s: growth,
        orbits,
        elasticity: oc.elasticity,
        class: oc.class,
        why: oc.why,
        borderline: oc.borderline,
        runup_class: None,
        wall_time_s: t0.elapsed().as_secs_f64(),
    };
    cosim::files::real_folder(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let text = serde_json::to_string_pretty(&cell).map_err(|e| e.to_string())?;
    let path = dir.join("cell.json");
    cosim::files::write_whole(&path, text.as_bytes())
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(cell)
}

/// The fields of one CSV line; a field in double quotes may hold commas.
fn csv_fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(String::new()),
            c => out.last_mut().expect("never empty").push(c),
        }
    }
    out
}

/// run -> classification of a sweep's study table.
pub fn read_classes(path: &Path) -> Result<BTreeMap<String, String>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header = csv_fields(lines.next().unwrap_or(""));
    let col = |name: &str| {
        header.iter().position(|h| h == name).ok_or_else(|| {
            format!(
                "{}: no column '{name}' (not a sweep's study.csv?)",
                path.display()
            )
        })
    };
    let (run, class) = (col("run")?, col("classification")?);
    Ok(lines
        .filter(|l| !l.trim().is_empty())
        .map(csv_fields)
        .filter_map(|f| Some((f.get(run)?.clone(), f.get(class)?.clone())))
        .collect())
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or(String::new(), |x| format!("{x:.digits$}"))
}

/// orbit_classes.csv (one row per cell: threshold, per speed the settled whirl, the class and,
/// with a run-up table, its class) and orbit_classes.json (every cell's record).
fn write_tables(out: &Path, cells: &[CellOrbits]) -> Result<(), String> {
    let mut s = String::from(
        "run,threshold_speed [Hz],orbit_class,borderline,runup_class,agree,elasticity [1],\
         speed_1 [Hz],motion_1,max_eps_C_1 [1],max_eps_T_1 [1],whirl_rms_1 [C],whirl_frequency_1 [Hz],leading_multiplier_1 [1],\
         speed_2 [Hz],motion_2,max_eps_C_2 [1],max_eps_T_2 [1],whirl_rms_2 [C],whirl_frequency_2 [Hz],leading_multiplier_2 [1],\
         wall_time [s]\n",
    );
    for c in cells {
        let rc = c.runup_class.clone();
        let agree = rc
            .as_ref()
            .map_or(String::new(), |r| (r == &c.class).to_string());
        s.push_str(&format!(
            "{},{},{},{},{},{},{}",
            c.run,
            opt(c.linear_threshold_hz, 1),
            c.class,
            c.borderline,
            rc.unwrap_or_default(),
            agree,
            opt(c.elasticity, 3)
        ));
        for k in 0..2 {
            match c.settled.get(k) {
                Some(r) => {
                    let rms = match (r.whirl_rms_c, r.whirl_rms_t) {
                        (Some(a), Some(b)) => Some(a.max(b)),
                        _ => None,
                    };
                    let mult = c
                        .orbits
                        .iter()
                        .find(|o| o.speed_hz == r.speed_hz)
                        .map(|o| o.leading_multiplier);
                    s.push_str(&format!(
                        ",{},{},{},{},{},{},{}",
                        r.speed_hz,
                        r.motion,
                        opt(r.max_eps_c, 4),
                        opt(r.max_eps_t, 4),
                        opt(rms, 4),
                        opt(r.whirl_frequency_hz, 1),
                        opt(mult, 4)
                    ));
                }
                None => s.push_str(",,,,,,,"),
            }
        }
        s.push_str(&format!(",{:.1}\n", c.wall_time_s));
    }
    let csv = out.join("orbit_classes.csv");
    cosim::files::write_whole(&csv, s.as_bytes()).map_err(|e| format!("{}: {e}", csv.display()))?;
    let json = out.join("orbit_classes.json");
    let text = serde_json::to_string_pretty(cells).map_err(|e| e.to_string())?;
    cosim::files::write_whole(&json, text.as_bytes())
        .map_err(|e| format!("{}: {e}", json.display()))
}
