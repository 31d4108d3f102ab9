//! `airring sweep` end to end on the packed FMUs (`cargo xtask fmus` first) with `studies/smoke.toml`
//! (2 x 2 run-ups of 10 ms): table and maps written, a second invocation runs nothing, and shards
//! 1/2 + 2/2 merged give the unsharded table. The maps' content is checked on fake run folders.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("airring-sweep-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn airring(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("airring runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
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
    let _ = std::fs::remove_dir_all(&base);
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
    assert!(
        maps[1].extension().unwrap() == "png" && std::fs::metadata(&maps[1]).unwrap().len() > 1000
    );
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
