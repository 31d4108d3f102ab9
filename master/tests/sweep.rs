//! `airring sweep` end to end on the packed FMUs (`cargo xtask fmus` first) with `studies/smoke.toml`
//! (2 x 2 run-ups of 10 ms): table and maps written, a second invocation runs nothing, and shards
//! 1/2 + 2/2 merged give the unsharded table. The maps' content is checked on fake run folders.

mod common;

use common::{airring, root};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let d = common::tmp("sweep", name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The table without the wall-time column (the only one that differs between repeated runs).
fn table(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string())
        .collect()
}

#[test]
fn smoke_study_runs_resumes_and_shards_merge() {
    assert!(
        root().join("target/fmu/rotor.fmu").exists()
            && root().join("target/fmu/airfilm.fmu").exists(),
        "run `cargo xtask fmus` first"
    );
    let base = tmp("smoke");
    let full = base.join("full");
    let full_s = full.to_str().unwrap();
    let (ok, err) = airring(&[
        "sweep",
        "studies/smoke.toml",
        "--out",
        full_s,
        "--jobs",
        "2",
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains("4 runs, 0 already completed, 4 to run"),
        "{err}"
    );
    let rows = table(&full.join("study.csv"));
    assert_eq!(rows.len(), 5, "{rows:?}");
    assert!(rows[0].starts_with("run,preset,clearance [um],dh [um],c [N/mm],d [N s/m]"));
    assert!(
        rows[1].starts_with("C20_dH40_c500_d50,path1,20,40,500,50,"),
        "{rows:?}"
    );
    for r in &rows[1..] {
        assert!(r.contains(",completed,"), "{r}");
    }
    for f in ["bifurcation_map.svg", "bifurcation_map.png", "study.toml"] {
        assert!(full.join(f).exists(), "{f}");
    }
    let svg = std::fs::read_to_string(full.join("bifurcation_map.svg")).unwrap();
    assert!(svg.contains(">c [N/mm]<") && svg.contains(">1000<") && svg.contains(">500<"));
    // The sweep's page: well-formed, the map inline, the table and every run's own page linked,
    // nothing from the network.
    let page = std::fs::read_to_string(full.join("report.html")).unwrap();
    let doc = roxmltree::Document::parse_with_options(
        &page,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(doc.descendants().any(|n| n.tag_name().name() == "svg"));
    let links: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("href"))
        .collect();
    assert!(links.contains(&"study.csv"), "{links:?}");
    for l in &links {
        assert!(!l.contains("://") && full.join(l).exists(), "{l}");
    }
    assert_eq!(
        links.iter().filter(|l| l.ends_with("/report.html")).count(),
        4,
        "{links:?}"
    );
    // The classes' sensitivity to the bounds: one row per run, its class and 12 moved ones.
    let out = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(["sweep-sensitivity", full_s])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("large_eps x1.2: 0 changed"));
    let sens = std::fs::read_to_string(full.join("sensitivity.csv")).unwrap();
    let lines: Vec<&str> = sens.lines().collect();
    assert_eq!(lines.len(), 5, "{sens}");
    assert_eq!(lines[0].split(',').count(), 14, "{}", lines[0]);
    let summary = full.join("runs/C20_dH40_c1000_d500/summary.json");
    let mtime = std::fs::metadata(&summary).unwrap().modified().unwrap();

    // Resumable: everything completed, nothing runs again.
    let (ok, err) = airring(&["sweep", "studies/smoke.toml", "--out", full_s]);
    assert!(ok, "{err}");
    assert!(err.contains("4 already completed, 0 to run"), "{err}");
    assert_eq!(
        std::fs::metadata(&summary).unwrap().modified().unwrap(),
        mtime
    );
    assert_eq!(table(&full.join("study.csv")), rows);

    // Shards into separate folders, merged.
    let a = base.join("a");
    let b = base.join("b");
    let merged = base.join("merged");
    for (dir, shard) in [(&a, "1/2"), (&b, "2/2")] {
        let (ok, err) = airring(&[
            "sweep",
            "studies/smoke.toml",
            "--out",
            dir.to_str().unwrap(),
            "--shard",
            shard,
            "--jobs",
            "2",
        ]);
        assert!(ok, "{err}");
        assert!(
            err.contains("2 runs, 0 already completed, 2 to run"),
            "{err}"
        );
    }
    assert!(a.join("study_shard-1-of-2.csv").exists());
    assert!(
        a.join("runs/C20_dH40_c500_d50").exists() && !a.join("runs/C20_dH40_c500_d500").exists()
    );
    let (ok, err) = airring(&[
        "sweep-merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert_eq!(table(&merged.join("study.csv")), rows);
    assert!(merged.join("bifurcation_map.png").exists());

    // Shards sharing one output folder (a Slurm array on a shared file system), then merged there.
    let shared = base.join("shared");
    for shard in ["1/2", "2/2"] {
        let (ok, err) = airring(&[
            "sweep",
            "studies/smoke.toml",
            "--out",
            shared.to_str().unwrap(),
            "--shard",
            shard,
        ]);
        assert!(ok, "{err}");
        assert!(err.contains("2 runs, 0 already completed"), "{err}");
    }
    let (ok, err) = airring(&["sweep-merge", shared.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert_eq!(table(&shared.join("study.csv")), rows);

    // A run made with other run-up defaults (an older airring) runs again.
    let meta_path = full.join("runs/C20_dH40_c500_d50/sweep_run.json");
    let mut meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&meta_path).unwrap()).unwrap();
    assert_eq!(
        meta["defaults"]["macro_step_us"],
        master::runup::DEFAULT_MACRO_STEP_US,
        "{meta}"
    );
    meta["defaults"]["macro_step_us"] = 10.0.into();
    std::fs::write(&meta_path, meta.to_string()).unwrap();
    let (ok, err) = airring(&["sweep", "studies/smoke.toml", "--out", full_s]);
    assert!(ok, "{err}");
    assert!(err.contains("3 already completed, 1 to run"), "{err}");
    // So does one made with another film-mesh rule (16 x 3 uniform up to bearing number 20,
    // recorded without a grading, as an older airring wrote it).
    let mut meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&meta_path).unwrap()).unwrap();
    let g = master::runup::GRADED_MESH_GRADING;
    let two = master::runup::TWO_ACROSS_FILM_TOLERANCE;
    let one = master::runup::DEFAULT_FILM_TOLERANCE;
    assert_eq!(
        meta["defaults"]["film_mesh_rule"],
        serde_json::json!([
            [10, 2, g, two],
            [10, 2, g, two],
            [10, 3, g, one],
            [10, 3, g, one],
            [20, 4, 1.0, one],
            [20, 4, 1.0, one],
            [20, 6, 1.0, one]
        ]),
        "{meta}"
    );
    meta["defaults"]["film_mesh_rule"] =
        serde_json::json!([[16, 3], [16, 3], [20, 4], [20, 4], [20, 6]]);
    std::fs::write(&meta_path, meta.to_string()).unwrap();
    let (ok, err) = airring(&["sweep", "studies/smoke.toml", "--out", full_s]);
    assert!(ok, "{err}");
    assert!(err.contains("3 already completed, 1 to run"), "{err}");

    // A changed flag is a different run-up: completed runs with other flags are not replaced
    // without --overwrite, and run again with it.
    let changed = base.join("changed.toml");
    let text = std::fs::read_to_string(root().join("studies/smoke.toml")).unwrap();
    std::fs::write(&changed, text.replace("stop = 0.01", "stop = 0.012")).unwrap();
    let (ok, err) = airring(&["sweep", changed.to_str().unwrap(), "--out", full_s]);
    assert!(
        !ok && err.contains("4 completed run(s) there were made with other flags")
            && err.contains("--overwrite"),
        "{err}"
    );
    let (ok, err) = airring(&[
        "sweep",
        changed.to_str().unwrap(),
        "--out",
        full_s,
        "--overwrite",
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains("4 runs, 0 already completed, 4 to run"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// Position (x, y) of the SVG text element that reads `label`.
fn text_at(doc: &roxmltree::Document, label: &str) -> (f64, f64) {
    let n = doc
        .descendants()
        .find(|n| n.has_tag_name("text") && n.text() == Some(label))
        .unwrap_or_else(|| panic!("no text '{label}' in the map"));
    let xy = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
    (xy("x"), xy("y"))
}

/// A fake run folder as a sweep leaves it.
fn fake(dir: &Path, index: usize, c: f64, d: f64, dh: f64, class: &str, onset: Option<f64>) {
    let name = format!("C15_dH{dh}_c{c}_d{d}");
    let run = dir.join("runs").join(&name);
    std::fs::create_dir_all(&run).unwrap();
    let meta = serde_json::json!({"name": name, "index": index,
        "args": {"clearance": "15", "dh": dh.to_string(), "c": c.to_string(), "d": d.to_string()}});
    std::fs::write(run.join("sweep_run.json"), meta.to_string()).unwrap();
    let s = serde_json::json!({"status": if class == "failed" {"failed"} else {"completed"},
        "classification": if class == "failed" { serde_json::Value::Null } else { class.into() },
        "onset_time_s": onset.map(|f| f / 2000.0 * 3.0), "onset_speed_hz": onset,
        "max_eps_C": 0.5, "max_eps_T": 0.4, "wall_time_s": 170.0});
    std::fs::write(run.join("summary.json"), s.to_string()).unwrap();
}

#[test]
fn maps_mark_every_class_with_onset_speed_per_case() {
    let dir = tmp("maps");
    let classes = [
        ("stable", None),
        ("path1", Some(1234.0)),
        ("path2a", Some(900.0)),
        ("path2b", Some(700.0)),
        ("unstable_low_speed", Some(150.0)),
        ("failed", None),
    ];
    let mut k = 0;
    for (i, c) in [500.0, 1000.0, 1500.0].iter().enumerate() {
        for (j, d) in [50.0, 500.0].iter().enumerate() {
            let (class, onset) = classes[2 * i + j];
            fake(&dir, k, *c, *d, 30.0, class, onset);
            k += 1;
        }
    }
    fake(&dir, k, 1000.0, 50.0, 0.0, "path1", Some(1500.0));
    let (table, maps, n) = master::sweep::merge(std::slice::from_ref(&dir), &dir).unwrap();
    assert_eq!(n, 7);
    let csv = std::fs::read_to_string(table).unwrap();
    let row = csv
        .lines()
        .find(|l| l.starts_with("C15_dH30_c1000_d500,15,30,1000,500,completed,path2b,"))
        .expect("the path 2b row");
    assert!(row.ends_with(",700.0,0.5,0.4,170.0"), "{row}");
    let svg = std::fs::read_to_string(&maps[0]).unwrap();
    // Two panels (dH = 30 and dH = 0), titled by what differs between them.
    assert!(
        svg.contains(">dH = 30 um<") && svg.contains(">dH = 0 um<"),
        "{svg}"
    );
    // Each class: its name once in the legend and its (short) label in a cell (path 1 twice).
    for (legend, cell) in [
        ("stable", "stable"),
        ("path 1", "path 1"),
        ("path 2a", "path 2a"),
        ("path 2b", "path 2b"),
        ("unstable low", "unst.low"),
        ("failed", "failed"),
    ] {
        let count = |label: &str| svg.matches(&format!(">{label}<")).count();
        let n = if legend == cell {
            count(legend)
        } else {
            count(legend).min(1) + count(cell).min(1)
        };
        assert!(n >= 2, "{legend} / {cell}: {n}");
    }
    for hz in [">1234 Hz<", ">900 Hz<", ">700 Hz<", ">150 Hz<", ">1500 Hz<"] {
        assert!(svg.contains(hz), "{hz}");
    }
    // Cells sit where their c and d put them: c across (left to right), d upwards.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let at = |label: &str| text_at(&doc, label);
    let (c500_d500, c1000_d50, c1000_d500, c1500_d50) =
        (at("1234 Hz"), at("900 Hz"), at("700 Hz"), at("150 Hz"));
    assert!(
        c500_d500.0 < c1000_d50.0 && c1000_d50.0 < c1500_d50.0,
        "c across"
    );
    assert!(
        (c1000_d50.0 - c1000_d500.0).abs() < 1e-9,
        "one c, one column"
    );
    assert!(
        c1000_d500.1 < c1000_d50.1,
        "d upwards (SVG y grows downwards)"
    );
    assert!((c1000_d50.1 - c1500_d50.1).abs() < 1e-9, "one d, one row");
    assert!(
        maps[1].extension().unwrap() == "png" && std::fs::metadata(&maps[1]).unwrap().len() > 1000
    );
    let bad = master::plot::layout::problems(&svg);
    assert!(bad.is_empty(), "{bad:#?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A map larger than the paper's 3 x 3: 7 c values, 6 d values, 5 step heights (two rows of
/// panels), every cell kind (onset speeds, failed and interrupted runs, a borderline class): no
/// text overlaps other text or leaves its panel, and the PNG has the SVG's size.
#[test]
fn large_maps_keep_their_text_apart_and_inside_the_panels() {
    let dir = tmp("large-map");
    let classes = [
        ("stable", None),
        ("path1", Some(1234.0)),
        ("path2a", Some(900.0)),
        ("path2b", Some(700.0)),
        ("unstable_low_speed", Some(150.0)),
        ("failed", None),
        ("unstable_linear", Some(1999.0)),
    ];
    let mut k = 0;
    for dh in [0.0, 10.0, 20.0, 30.0, 40.0] {
        for c in [100.0, 250.0, 500.0, 1000.0, 1500.0, 2000.0, 10000.0] {
            for d in [5.0, 50.0, 200.0, 500.0, 2000.0, 20000.0] {
                let (class, onset) = classes[k % classes.len()];
                fake(&dir, k, c, d, dh, class, onset);
                k += 1;
            }
        }
    }
    let (_, maps, n) = master::sweep::merge(std::slice::from_ref(&dir), &dir).unwrap();
    assert_eq!(n, 5 * 7 * 6);
    let svg = std::fs::read_to_string(&maps[0]).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let panels = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("panel"))
        .count();
    assert_eq!(panels, 5);
    let bad = master::plot::layout::problems(&svg);
    assert!(bad.is_empty(), "{bad:#?}");
    let png = std::fs::read(&maps[1]).unwrap();
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    let root = doc.root_element();
    assert_eq!(root.attribute("width"), Some(w.to_string().as_str()));
    assert_eq!(root.attribute("height"), Some(h.to_string().as_str()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `airring sweep --linear` predicts the smoke study's map: per point the same threshold as
/// `airring stability` with the same flags, a visible onset only where the growth exponent reaches
/// the calibrated level, and the predicted map files.
#[test]
fn linear_prediction_matches_the_stability_command_point_by_point() {
    let out = tmp("linear");
    let out_s = out.to_str().unwrap();
    let (ok, err) = airring(&[
        "sweep",
        "studies/smoke.toml",
        "--linear",
        "--speeds",
        "300:2000:300",
        "--out",
        out_s,
        "--quiet",
    ]);
    assert!(ok, "{err}");
    for f in [
        "study_linear.csv",
        "study_linear_table.csv",
        "bifurcation_map_linear.svg",
        "bifurcation_map_linear.png",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("study_linear.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 4);
    // Point c = 1000 N/mm, d = 50 N s/m (smoke mesh 8x2): same threshold through `airring stability`.
    let row = rows
        .iter()
        .find(|r| r.starts_with("C20_dH40_c1000_d50,"))
        .expect("row");
    let f: Vec<&str> = row.split(',').collect();
    let threshold: f64 = f[1].parse().unwrap();
    let n_fmax: f64 = f[3].parse().unwrap();
    let onset: f64 = f[4].parse().unwrap();
    let stab = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args([
            "stability",
            "--preset",
            "path1",
            "--c",
            "1000",
            "--d",
            "50",
            "--mesh",
            "8x2",
            "--speeds",
            "300:2000:300",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&stab.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("threshold speed of instability:"))
        .expect("threshold line");
    let t_cli: f64 = line.split_whitespace().nth(4).unwrap().parse().unwrap();
    assert!((threshold - t_cli).abs() < 0.06, "{threshold} vs {t_cli}");
    // Unstable (N at f_max far above the visible level) with the onset between threshold and f_max.
    assert!(
        n_fmax > 12.0 && onset > threshold && onset < 2000.0,
        "{row}"
    );
}

/// A one-run study of 2 s of path 1 into `base/out` (past its whirl onset: a run-up of 0.4 s on
/// the coarse mesh took 0.1 s, and could end before the signal came), stopped once its run-up
/// has made progress by `kill -TERM TARGET`, where `target(pid)` names the sweep's process (its
/// pid) or its process group (minus it). The run-up must stop with a checkpoint and an "interrupted" summary, and the
/// sweep must not report success. The study file's path.
fn interrupted_one_run_sweep(base: &Path, target: impl Fn(u32) -> String) -> PathBuf {
    use std::os::unix::process::CommandExt;
    let study = base.join("one.toml");
    std::fs::write(
        &study,
        "name = \"one\"\n[fixed]\npreset = \"path1\"\nstop = 2\nmesh = \"8x2\"\n[[grid]]\nc = [1000]\n",
    )
    .unwrap();
    let out = base.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(["sweep", study.to_str().unwrap(), "--jobs", "1", "--out"])
        .arg(&out)
        .current_dir(root())
        .stderr(std::process::Stdio::null())
        .process_group(0)
        .spawn()
        .unwrap();
    // Wait until the run-up has made progress, then SIGTERM the target.
    let log = out.join("runs/c1000/runup.log");
    let t0 = std::time::Instant::now();
    while !std::fs::read_to_string(&log).is_ok_and(|l| l.contains("%)")) {
        assert!(
            t0.elapsed().as_secs() < 120,
            "no progress in {}",
            log.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(Command::new("kill")
        .args(["-TERM", "--", &target(child.id())])
        .status()
        .unwrap()
        .success());
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "an interrupted sweep does not report success"
    );
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("runs/c1000/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(summary["status"], "interrupted", "{summary}");
    let t_stop = summary["t_end_s"].as_f64().expect("t_end_s");
    assert!(t_stop > 0.0 && t_stop < 2.0, "{summary}");
    assert!(out.join("runs/c1000/checkpoint/master.json").exists());
    study
}

/// `kill PID` of the sweep alone (`timeout`, a batch system that signals the main process): the
/// sweep passes the stop on to its run-up, which used to run on to its end (it shared the
/// sweep's process group and so got only a signal sent to the whole group).
#[test]
fn sigterm_to_the_sweep_alone_stops_its_run_up() {
    let base = tmp("sigterm_pid");
    interrupted_one_run_sweep(&base, |pid| pid.to_string());
    let _ = std::fs::remove_dir_all(&base);
}

/// A batch system's time limit (SIGTERM to the whole job, as Slurm sends it) stops a sweep and
/// its run-up cleanly: the run-up writes a checkpoint and an "interrupted" summary, and the same
/// sweep command afterwards resumes it from that checkpoint instead of starting again at t = 0.
#[test]
fn sigterm_interrupts_a_sweep_and_the_next_sweep_resumes_from_the_checkpoint() {
    let base = tmp("sigterm");
    let study = interrupted_one_run_sweep(&base, |pid| format!("-{pid}"));
    let out = base.join("out");
    let (ok, err) = airring(&[
        "sweep",
        study.to_str().unwrap(),
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("runs/c1000/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(summary["status"], "completed", "{summary}");
    // Resumed, not restarted: the time series has one row per output interval from 0 to 2 s
    // (a restart would have truncated and rewritten it; a double run would have duplicates).
    let csv = std::fs::read_to_string(out.join("runs/c1000/timeseries.csv")).unwrap();
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(
        times.windows(2).all(|w| w[1] > w[0]),
        "times strictly increase"
    );
    assert!(*times.last().unwrap() > 1.999, "{:?}", times.last());
    let log = std::fs::read_to_string(out.join("runs/c1000/runup.log")).unwrap();
    // The log keeps the first attempt and appends the resumed one.
    assert!(log.contains("resuming"), "the second run resumed: {log}");
    assert!(
        log.find("stop signal").unwrap_or(usize::MAX) < log.find("resuming").unwrap(),
        "{log}"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// The pid of the process whose command line holds every one of `parts`.
fn pid_of(parts: &[&str]) -> Option<u32> {
    std::fs::read_dir("/proc").ok()?.flatten().find_map(|e| {
        let pid: u32 = e.file_name().to_str()?.parse().ok()?;
        let cmd = std::fs::read(e.path().join("cmdline")).ok()?;
        let cmd = String::from_utf8_lossy(&cmd).replace('\0', " ");
        parts.iter().all(|p| cmd.contains(p)).then_some(pid)
    })
}

/// A run-up killed outright (SIGKILL: no handler, no summary of its own) after a checkpoint:
/// the sweep marks it interrupted with its settings kept, and the next sweep resumes it from the
/// checkpoint (issue #17 items 4 and 5): its summary is then complete.
#[test]
fn a_killed_runup_resumes_from_its_checkpoint_with_a_complete_summary() {
    let base = tmp("sigkill");
    let study = base.join("one.toml");
    std::fs::write(
        &study,
        "name = \"one\"\n[fixed]\npreset = \"path1\"\nstop = 0.3\nmesh = \"8x2\"\n[[grid]]\nd = [60]\n",
    )
    .unwrap();
    let out = base.join("out");
    let sweep = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(["sweep", study.to_str().unwrap(), "--jobs", "1", "--quiet"])
        .args(["--checkpoint-every", "0.01", "--out"])
        .arg(&out)
        .current_dir(root())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let run = out.join("runs/d60");
    let t0 = std::time::Instant::now();
    let read_step = || -> Option<u64> {
        let m = std::fs::read_to_string(run.join("checkpoint/master.json")).ok()?;
        serde_json::from_str::<serde_json::Value>(&m).ok()?["step_index"].as_u64()
    };
    // A summary that says "running" while the run-up works, with its settings in it.
    while read_step().is_none_or(|k| k < 1000) {
        assert!(
            t0.elapsed().as_secs() < 120,
            "no checkpoint in {}",
            run.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let running: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    assert_eq!(running["status"], "running", "{running}");
    assert_eq!(running["settings"]["d_n_s_per_m"], 60.0, "{running}");
    let pid = pid_of(&["runup", run.to_str().unwrap()]).expect("the run-up's process");
    assert!(Command::new("kill")
        .args(["-KILL", &pid.to_string()])
        .status()
        .unwrap()
        .success());
    let status = sweep.wait_with_output().unwrap().status;
    assert!(
        !status.success(),
        "a sweep with a killed run-up reports failure"
    );
    let killed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    assert_eq!(killed["status"], "interrupted", "{killed}");
    assert!(
        killed["error"].as_str().unwrap().contains("killed"),
        "{killed}"
    );
    assert_eq!(killed["settings"]["d_n_s_per_m"], 60.0, "{killed}");

    let (ok, err) = airring(&[
        "sweep",
        study.to_str().unwrap(),
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let log = std::fs::read_to_string(run.join("runup.log")).unwrap();
    assert!(log.contains("resuming"), "resumed, not restarted: {log}");
    let done: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    assert_eq!(done["status"], "completed", "{done}");
    assert_eq!(done["settings"]["d_n_s_per_m"], 60.0, "{done}");
    assert_eq!(done["settings"]["preset"], "path1", "{done}");
    assert!(done["classification"].is_string(), "{done}");
    assert!(
        done["max_eps_C"].as_f64().is_some_and(|e| e > 0.0),
        "{done}"
    );
    assert!(done["clearance_um"]["C"].as_f64() == Some(20.0), "{done}");
    let plots = done["plots"].as_array().expect("plots");
    assert!(!plots.is_empty());
    for p in plots {
        assert!(run.join(p.as_str().unwrap()).exists(), "{p}");
    }
    let csv = std::fs::read_to_string(run.join("timeseries.csv")).unwrap();
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(
        times.windows(2).all(|w| w[1] > w[0]),
        "times strictly increase"
    );
    assert!(*times.last().unwrap() > 0.299, "{:?}", times.last());
    let _ = std::fs::remove_dir_all(&base);
}

/// `airring runup --set` reaches the FMU: with film_T's clearance set to 25 um (film_C keeps the
/// preset's 20 um; per-bearing geometry needs the contact in the films), each film's reported
/// eccentricity is its journal's displacement over its own clearance. A parameter the FMU does
/// not have stops the run-up before it starts, naming it.
#[test]
fn set_flags_reach_the_fmus() {
    let dir = tmp("set");
    let (ok, err) = airring(&[
        "runup",
        "--stop",
        "0.004",
        "--mesh",
        "8x2",
        "--contact",
        "film",
        "--set",
        "film_T.C=25 um",
        "--quiet",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let sys = std::fs::read_to_string(dir.join("system.toml")).unwrap();
    assert!(sys.contains("C = \"25 um\""), "{sys}");
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| h.starts_with(name)).unwrap();
    let last: Vec<f64> = lines
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    for (side, c_m) in [("C", 20e-6), ("T", 25e-6)] {
        let d =
            last[col(&format!("rotor.dx_{side} "))].hypot(last[col(&format!("rotor.dy_{side} "))]);
        let eps = last[col(&format!("film_{side}.eps "))];
        assert!(d > 1e-7, "the journal has moved: {d}");
        assert!(
            (eps - d / c_m).abs() < 1e-6 * eps.max(1e-3),
            "{side}: eps {eps} vs {}",
            d / c_m
        );
    }
    let (ok, err) = airring(&[
        "runup",
        "--set",
        "film.bogus=1",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("no parameter 'bogus'"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A study of several grids also gets a map per grid that varies another parameter than c (the
/// paper's step-height study: dH across, d upwards), from the study file the sweep leaves in its
/// folder; grids that vary c are in the main map only.
#[test]
fn a_grid_over_another_parameter_gets_its_own_map() {
    let dir = tmp("gridmaps");
    std::fs::write(
        dir.join("study.toml"),
        "[[grid]]\nname = \"cases\"\nclearance = 15\ndh = 30\nc = [500, 1000]\nd = [50]\n\
         [[grid]]\nname = \"step height\"\nclearance = 15\nc = 1000\ndh = [0, 30]\nd = [50, 500]\n",
    )
    .unwrap();
    fake(&dir, 0, 500.0, 50.0, 30.0, "stable", None);
    fake(&dir, 1, 1000.0, 50.0, 30.0, "path1", Some(864.0));
    fake(&dir, 2, 1000.0, 50.0, 0.0, "unstable_low_speed", Some(7.0));
    fake(&dir, 3, 1000.0, 500.0, 0.0, "unstable_low_speed", Some(8.0));
    fake(&dir, 4, 1000.0, 500.0, 30.0, "stable", None);
    let (_, maps, n) = master::sweep::merge(std::slice::from_ref(&dir), &dir).unwrap();
    assert_eq!(n, 5);
    let names: Vec<String> = maps
        .iter()
        .map(|m| m.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "bifurcation_map.svg",
            "bifurcation_map.png",
            "bifurcation_map_step_height.svg",
            "bifurcation_map_step_height.png"
        ]
    );
    let svg = std::fs::read_to_string(dir.join("bifurcation_map_step_height.svg")).unwrap();
    let bad = master::plot::layout::problems(&svg);
    assert!(bad.is_empty(), "{bad:#?}");
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let at = |label: &str| text_at(&doc, label);
    at("dH [um]");
    // One panel: dH = 0 left of dH = 30 in the d = 50 row, d = 500 above d = 50.
    let (dh0_d50, dh30_d50, dh0_d500) = (at("7 Hz"), at("864 Hz"), at("8 Hz"));
    assert!(dh0_d50.0 < dh30_d50.0 && (dh0_d50.1 - dh30_d50.1).abs() < 1e-9);
    assert!((dh0_d50.0 - dh0_d500.0).abs() < 1e-9 && dh0_d500.1 < dh0_d50.1);
    assert!(
        svg.contains(">c = 1000 N/mm<") || svg.contains("c = 1000 N/mm"),
        "common flags"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--jobs 0` is refused before anything runs (it was taken, printed "0 at a time" and ran the
/// study one run-up at a time).
#[test]
fn jobs_must_be_one_or_more() {
    let base = tmp("jobs0");
    let out = base.join("out");
    for cmd in ["sweep", "sweep-orbits"] {
        let (ok, err) = airring(&[
            cmd,
            "studies/smoke.toml",
            "--out",
            out.to_str().unwrap(),
            "--jobs",
            "0",
        ]);
        assert!(
            !ok && err.contains("0 run-ups at a time would run none: give 1 or more"),
            "{cmd}: {err}"
        );
        assert!(!out.exists(), "{cmd}: nothing written");
    }
    let _ = std::fs::remove_dir_all(&base);
}
