//! `airring optimize` end to end on the packed FMUs (`cargo xtask fmus` first): a small problem
//! (two variables, a clearance tolerance, path 1 run up to 700 Hz through its threshold) searched
//! with six evaluations and verified; its outputs consistent with each other; a second
//! invocation resumes without running anything; a larger budget continues; another problem in
//! the same folder and a bad file are refused.

mod common;

use common::{airring, root};
use std::path::Path;

const PROBLEM: &str = r#"
name = "fast"
[base]
preset = "path1"
f_max = 700
t_ramp = 0.5
[variables]
clearance = { min = 15, max = 25 }
c = { min = 300, max = 1500, scale = "log" }
[requirement]
min_film_um = 3.0
max_whirl_um = 1.0
speed_range_hz = [300, 700]
[tolerances]
clearance = 1
[objective]
maximize = "clearance"
[search]
budget = 6
initial = 4
batch = 2
[verify]
t_ramp = 0.5
mesh = "12x4"
"#;

fn rows(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("evaluations.csv")).unwrap();
    let mut out = vec![];
    for line in text.lines().skip(1) {
        // The reason (last field) may be quoted and hold commas; the others do not.
        let fields: Vec<String> = line.splitn(13, ',').map(String::from).collect();
        out.push(fields);
    }
    out
}

/// A fresh folder for one test with the optimisation file NAME.toml holding `text` in it.
fn problem_file(name: &str, text: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let base = common::tmp("optimize", name);
    std::fs::create_dir_all(&base).unwrap();
    let file = base.join(format!("{name}.toml"));
    std::fs::write(&file, text).unwrap();
    (base, file)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_small_problem_is_searched_verified_resumed_and_continued() {
    assert!(
        root().join("target/fmu/rotor.fmu").exists(),
        "run `cargo xtask fmus` first"
    );
    let base = common::tmp("optimize", "fast");
    std::fs::create_dir_all(&base).unwrap();
    let file = base.join("fast.toml");
    std::fs::write(&file, PROBLEM).unwrap();
    let out = base.join("out");
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());
    let (ok, err) = airring(&["optimize", f, "--out", o, "--jobs", "2", "--quiet"]);
    assert!(ok, "{err}");
    let table = rows(&out);
    assert_eq!(table.len(), 6, "{table:?}");
    // Columns: index, C, c, stage, feasible, film, whirl, threshold, power, margin, objective,
    // run-ups, reason.
    let mut best_feasible = f64::NEG_INFINITY;
    for r in &table {
        let (c, stage, feasible) = (r[1].parse::<f64>().unwrap(), &r[3], &r[4] == "true");
        assert!((15.0..=25.0).contains(&c), "{r:?}");
        assert!(stage == "linear" || stage == "nonlinear", "{r:?}");
        let runs: usize = r[11].parse().unwrap();
        // A candidate goes to run-ups only where the linear stage left a corner open.
        assert_eq!(stage == "nonlinear", runs > 0, "{r:?}");
        if let Ok(film) = r[5].parse::<f64>() {
            // The film can be no thicker than the clearance plus the step and ring travel
            // allow: a sanity bound on what was read from the run folders.
            assert!(film > 0.0 && film < c + 40.0, "{r:?}");
            assert_eq!(
                feasible,
                r[12].starts_with("all ") || r[12].contains("again: all"),
                "{r:?}"
            );
            if feasible {
                assert!(film >= 3.0, "{r:?}");
                best_feasible = best_feasible.max(c);
            }
        }
    }
    let optimum = json(&out.join("optimum.json"));
    let rec = &optimum["recommended"];
    assert_eq!(
        rec["variables"]["clearance"]["value"].as_f64().unwrap(),
        best_feasible,
        "the recommendation is the feasible candidate with the largest clearance"
    );
    assert_eq!(rec["corners"].as_array().unwrap().len(), 3);
    // Verified at its three corners on both meshes; the two meshes agree within 5 % in film
    // thickness (a mesh error above that would leave the recommendation resting on the mesh).
    let v = &optimum["verification"];
    assert_eq!(v["corners"].as_array().unwrap().len(), 3, "{v}");
    let film = v["min_film_um"].as_f64().unwrap();
    assert!(v["film_error_um"].as_f64().unwrap() < 0.05 * film, "{v}");
    assert_eq!(
        v["verified"].as_bool().unwrap() && v["resolved"].as_bool().unwrap(),
        err.contains("(verified)"),
        "{err}"
    );
    let design = std::fs::read_to_string(out.join("recommended.toml")).unwrap();
    let c = rec["variables"]["clearance"]["value"].as_f64().unwrap();
    assert!(design.contains(&format!("C = \"{c} um\"")), "{design}");
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("<h2>Recommended: C = "), "{page}");
    assert!(out.join("safe_set_clearance_c.svg").exists());

    // Again: everything is there, nothing runs.
    let before = std::fs::read_to_string(out.join("evaluations.jsonl")).unwrap();
    let (ok, err) = airring(&["optimize", f, "--out", o, "--jobs", "2"]);
    assert!(ok, "{err}");
    assert!(err.contains("budget 6, 6 evaluated before"), "{err}");
    assert!(!err.contains("round "), "{err}");
    assert!(err.contains("already completed, 0 to run"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("evaluations.jsonl")).unwrap(),
        before
    );

    // A larger budget continues the search.
    let (ok, err) = airring(&[
        "optimize",
        f,
        "--out",
        o,
        "--budget",
        "7",
        "--no-verify",
        "--quiet",
    ]);
    assert!(ok, "{err}");
    assert_eq!(rows(&out).len(), 7);

    // Another problem into the same folder is refused; so is a bad file.
    let other = base.join("other.toml");
    std::fs::write(
        &other,
        PROBLEM.replace("min_film_um = 3.0", "min_film_um = 4.0"),
    )
    .unwrap();
    let (ok, err) = airring(&["optimize", other.to_str().unwrap(), "--out", o]);
    assert!(!ok && err.contains("holds another optimisation"), "{err}");
    std::fs::write(
        &other,
        PROBLEM.replace("c = { min = 300", "cc = { min = 300"),
    )
    .unwrap();
    let (ok, err) = airring(&["optimize", other.to_str().unwrap(), "--out", o]);
    assert!(!ok, "{err}");
    assert!(
        err.contains("other.toml: [variables] 'cc' is no design quantity"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// With --external-runs the run-ups are left to another runner (here `airring sweep`, as Dask
/// or Slurm would run the same study file): the command exits with status 3 and the study's
/// path on stdout until they are done, and then gives the same evaluations as running them
/// itself.
#[test]
fn run_ups_left_to_another_runner_give_the_same_evaluations() {
    let base = common::tmp("optimize", "external");
    std::fs::create_dir_all(&base).unwrap();
    let file = base.join("fast.toml");
    let problem = PROBLEM
        .replace("budget = 6", "budget = 4")
        .replace("name = \"fast\"", "name = \"ext\"");
    std::fs::write(&file, problem).unwrap();
    let f = file.to_str().unwrap();
    let own = base.join("own");
    let (ok, err) = airring(&[
        "optimize",
        f,
        "--out",
        own.to_str().unwrap(),
        "--no-verify",
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let ext = base.join("ext");
    let mut handed_over = 0;
    loop {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_airring"))
            .args([
                "optimize",
                f,
                "--out",
                ext.to_str().unwrap(),
                "--no-verify",
                "--quiet",
            ])
            .arg("--external-runs")
            .current_dir(root())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        match out.status.code() {
            Some(0) => break,
            Some(3) => {
                handed_over += 1;
                assert!(handed_over < 5, "{err}");
                let study = String::from_utf8_lossy(&out.stdout).trim().to_string();
                assert!(study.ends_with("nonlinear/study.toml"), "{study}");
                assert!(err.contains("run-ups wait in"), "{err}");
                let folder = Path::new(&study)
                    .parent()
                    .unwrap()
                    .to_str()
                    .unwrap()
                    .to_string();
                let (ok, err) = airring(&["sweep", &study, "--out", &folder, "--quiet"]);
                assert!(ok, "{err}");
            }
            code => panic!("exit {code:?}: {err}"),
        }
    }
    assert!(handed_over >= 1, "the problem's first round needs run-ups");
    let table = |d: &Path| std::fs::read_to_string(d.join("evaluations.csv")).unwrap();
    assert_eq!(table(&own), table(&ext));
    let _ = std::fs::remove_dir_all(&base);
}

/// The evaluations of a search, line by line, without the wall times (which differ run to run).
fn evaluations(dir: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(dir.join("evaluations.jsonl"))
        .unwrap()
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            if let Some(o) = v.as_object_mut() {
                o.retain(|k, _| !k.contains("wall"));
            }
            v
        })
        .collect()
}

/// A search stopped in the middle of a round and started again gives the evaluations of a
/// search that ran through: the same points asked, the same values, in the same order. Stopped
/// by Ctrl-C (SIGINT) and killed with SIGKILL, each sent to the whole process group (the
/// optimisation and its run-ups), as a terminal or a batch system sends it.
#[test]
fn a_search_interrupted_or_killed_resumes_to_the_same_evaluations() {
    let base = common::tmp("optimize", "sigkill");
    std::fs::create_dir_all(&base).unwrap();
    let file = base.join("fast.toml");
    std::fs::write(&file, PROBLEM.replace("budget = 6", "budget = 8")).unwrap();
    let f = file.to_str().unwrap();
    let whole = base.join("whole");
    let (ok, err) = airring(&[
        "optimize",
        f,
        "--out",
        whole.to_str().unwrap(),
        "--no-verify",
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let a = evaluations(&whole);
    assert_eq!(a.len(), 8);
    // Killed after its last round was recorded and before its pending batch was removed: the
    // batch is not evaluated again.
    let stale = base.join("stale");
    std::fs::create_dir_all(&stale).unwrap();
    for f in ["optimization.toml", "evaluations.jsonl", "evaluations.csv"] {
        std::fs::copy(whole.join(f), stale.join(f)).unwrap();
    }
    let last: Vec<&serde_json::Value> = a[6..].iter().map(|e| &e["asked"]).collect();
    std::fs::write(
        stale.join("pending_batch.json"),
        serde_json::json!({ "first": 6, "asked": last }).to_string(),
    )
    .unwrap();
    let (ok, err) = airring(&[
        "optimize",
        f,
        "--out",
        stale.to_str().unwrap(),
        "--no-verify",
        "--quiet",
    ]);
    assert!(ok, "{err}");
    assert_eq!(evaluations(&stale), a, "a recorded round evaluated again");
    assert!(!stale.join("pending_batch.json").exists());
    for (signal, name) in [(libc::SIGINT, "SIGINT"), (libc::SIGKILL, "SIGKILL")] {
        let stopped = base.join(name);
        let at = stop_in_a_round(f, &stopped, signal);
        let (ok, err) = airring(&[
            "optimize",
            f,
            "--out",
            stopped.to_str().unwrap(),
            "--no-verify",
            "--quiet",
        ]);
        assert!(ok, "{name}: {err}");
        let b = evaluations(&stopped);
        assert_eq!(b.len(), 8, "{name}");
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                x == y,
                "{name} after {at} evaluations: evaluation {i} differs, asked {} against {}",
                x["asked"],
                y["asked"]
            );
        }
    }
}

/// Starts the search of `file` into `out` and sends `signal` to its process group once the
/// first round of the search proper (after the four initial points) has started: one of its
/// candidates is in, the other is not. Returns the evaluations there were.
fn stop_in_a_round(file: &str, out: &Path, signal: i32) -> usize {
    use std::os::unix::process::CommandExt;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_airring"))
        .args([
            "optimize",
            file,
            "--out",
            out.to_str().unwrap(),
            "--no-verify",
            "--quiet",
        ])
        .current_dir(root())
        .process_group(0)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let lines = || {
        std::fs::read_to_string(out.join("evaluations.jsonl"))
            .map(|t| t.lines().count())
            .unwrap_or(0)
    };
    let t0 = std::time::Instant::now();
    while lines() < 5 {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the search ended before it was stopped"
        );
        assert!(
            t0.elapsed().as_secs() < 600,
            "no fifth evaluation in 10 minutes"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    // SAFETY: kill(2) on the child's own process group (process_group(0) made it its leader).
    let r = unsafe { libc::kill(-(child.id() as i32), signal) };
    assert_eq!(r, 0);
    let _ = child.wait();
    let at = lines();
    assert!(
        at < 8,
        "stopped after the search had ended: {at} evaluations"
    );
    at
}

/// A requirement no design in the box meets: the command says so, names the candidate nearest
/// to meeting it and the limit it misses, and writes no recommendation.
#[test]
fn a_requirement_nothing_meets_names_the_nearest_design_and_its_missed_limit() {
    // A film of 40 um in a clearance of 15-25 um: the linear stage fails every corner.
    let (base, file) = problem_file(
        "unmeetable",
        &PROBLEM
            .replace("min_film_um = 3.0", "min_film_um = 40.0")
            .replace("budget = 6", "budget = 4\nmethod = \"random\"")
            .replace("initial = 4\n", ""),
    );
    let out = base.join("out");
    let (ok, err) = airring(&[
        "optimize",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "an answer, if a negative one: {err}");
    let last = err.lines().last().unwrap_or("");
    assert!(
        last.contains("no design meets the requirement; nearest: #")
            && last.contains("below the limit 40 um"),
        "{last}"
    );
    assert!(!out.join("recommended.toml").exists());
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        page.contains("Nearest to meeting it: candidate #"),
        "report.html"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// Two objectives: the search runs egobox's multi-objective criterion and writes the Pareto
/// front of the feasible candidates, each on it unbeaten in both objectives by any feasible one.
#[test]
fn two_objectives_give_a_pareto_front() {
    let (base, file) = problem_file(
        "two",
        &PROBLEM
            .replace("name = \"fast\"", "name = \"two\"")
            .replace(
                "[objective]\nmaximize = \"clearance\"\n",
                "[[objective]]\nmaximize = \"clearance\"\n[[objective]]\nminimize = \"c\"\n",
            )
            .replace("budget = 6", "budget = 8"),
    );
    let out = base.join("out");
    let (ok, err) = airring(&[
        "optimize",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--no-verify",
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let evals = evaluations(&out);
    assert_eq!(evals.len(), 8);
    let feasible: Vec<(f64, f64)> = evals
        .iter()
        .filter(|e| e["feasible"].as_bool().unwrap())
        .map(|e| (e["x"][0].as_f64().unwrap(), e["x"][1].as_f64().unwrap()))
        .collect();
    assert!(!feasible.is_empty(), "{evals:?}");
    let front = std::fs::read_to_string(out.join("pareto.csv")).unwrap();
    let rows: Vec<&str> = front.lines().skip(1).collect();
    assert!(!rows.is_empty(), "{front}");
    for r in &rows {
        let f: Vec<f64> = r
            .split(',')
            .skip(1)
            .take(2)
            .map(|v| v.parse().unwrap())
            .collect();
        // Maximise C, minimise c: nothing feasible has a larger C and a smaller c.
        assert!(
            !feasible
                .iter()
                .any(|(c, k)| (*c >= f[0] && *k < f[1]) || (*c > f[0] && *k <= f[1])),
            "{r} is beaten: {feasible:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&base);
}
