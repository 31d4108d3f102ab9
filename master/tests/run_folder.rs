//! Run folders under abuse (issue #17): a folder holding a run is never replaced by accident, a
//! run that cannot start leaves it as it was, `--overwrite` replaces all of the old run, and a
//! run too large for memory is refused up front. End to end on the packed FMUs
//! (`cargo xtask fmus` first).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("airring-folder-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn airring(args: &[&str], env: &[(&str, &str)]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(root())
        .output()
        .expect("airring runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Every file under `dir` with its bytes, by relative name.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = vec![];
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if e.file_type().unwrap().is_dir() {
            out.extend(
                snapshot(&e.path())
                    .into_iter()
                    .map(|(n, b)| (format!("{name}/{n}"), b)),
            );
        } else {
            out.push((name, std::fs::read(e.path()).unwrap()));
        }
    }
    out.sort();
    out
}

fn names(snap: &[(String, Vec<u8>)]) -> Vec<&str> {
    snap.iter().map(|(n, _)| n.as_str()).collect()
}

const SHORT: &[&str] = &["runup", "--stop", "0.004", "--mesh", "8x2", "--quiet"];

fn runup(dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> (bool, String) {
    let mut args: Vec<&str> = SHORT.to_vec();
    args.extend_from_slice(&["--out", dir.to_str().unwrap()]);
    args.extend_from_slice(extra);
    airring(&args, env)
}

#[test]
fn a_folder_holding_a_run_is_kept_until_a_new_run_has_started() {
    let dir = tmp("kept").join("run");
    let (ok, err) = runup(&dir, &["--parquet", "--checkpoint-every", "0.002"], &[]);
    assert!(ok, "{err}");
    let first = snapshot(&dir);
    for f in [
        "system.toml",
        "summary.json",
        "timeseries.csv",
        "timeseries.parquet",
        "checkpoint/master.json",
    ] {
        assert!(names(&first).contains(&f), "{f} in {:?}", names(&first));
    }
    // Again into the same folder: refused, naming the way out, nothing touched.
    let (ok, err) = runup(&dir, &[], &[]);
    assert!(
        !ok && err.contains("holds a run already") && err.contains("--overwrite"),
        "{err}"
    );
    assert!(snapshot(&dir) == first, "refused run changed the folder");
    // With --overwrite, but runs that cannot start: an FMU refuses a parameter, a time grid no run
    // can cover, samples that would not fit in memory. The old run stays as it was.
    for (extra, env, expect) in [
        (vec!["--set", "film.eta=-1"], vec![], "eta"),
        (vec!["--set", "film.p_a=1e300"], vec![], "p_a"),
        (
            vec!["--output-interval", "1e-300"],
            vec![],
            "--output-interval = 1e-300 us must be a whole number of macro steps",
        ),
        (
            vec![],
            vec![("AIRRING_MEMORY_LIMIT", "1000")],
            "output samples in memory",
        ),
    ] {
        let mut args = vec!["--overwrite"];
        args.extend(extra.iter().copied());
        let (ok, err) = runup(&dir, &args, &env);
        assert!(!ok && err.contains(expect), "{args:?}: {err}");
        assert!(
            snapshot(&dir) == first,
            "{args:?}: a failed start changed the folder"
        );
    }
    // A new folder that a run could not start in is not left behind.
    let fresh = dir.with_file_name("never");
    let (ok, _) = runup(&fresh, &["--set", "film.eta=-1"], &[]);
    assert!(!ok && !fresh.exists());
    // --overwrite with a run that starts: the old run's Parquet file, figures and checkpoint go,
    // the summary is the new run's.
    let (ok, err) = runup(&dir, &["--overwrite", "--d", "500"], &[]);
    assert!(ok, "{err}");
    let second = snapshot(&dir);
    let listed = names(&second);
    assert!(!listed.contains(&"timeseries.parquet"), "{listed:?}");
    assert!(
        !listed.iter().any(|n| n.starts_with("checkpoint")),
        "{listed:?}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["settings"]["d_n_s_per_m"], 500.0, "{summary}");
    // No temporary files are left anywhere.
    assert!(!listed.iter().any(|n| n.ends_with(".tmp")), "{listed:?}");
    let _ = std::fs::remove_dir_all(dir.parent().unwrap());
}

/// A run of a few output rows (0.3 ms: 7 rows at 50 us) is classified too, as too short (it
/// once had `classification: null` below 17 rows).
#[test]
fn a_run_of_a_few_output_rows_is_too_short_not_unclassified() {
    let dir = tmp("few-rows");
    let (ok, err) = airring(
        &[
            "runup",
            "--stop",
            "0.0003",
            "--mesh",
            "8x2",
            "--quiet",
            "--out",
            dir.to_str().unwrap(),
        ],
        &[],
    );
    assert!(ok, "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["classification"], "too_short", "{summary}");
    // A folder that does not exist is named as such (was: "/no/such/run/system.toml: No such
    // file or directory").
    let (ok, err) = airring(&["classify", "/no/such/run"], &[]);
    assert!(!ok && err.contains("/no/such/run: no such folder"), "{err}");
    // A clearance no bore can have is refused in its unit.
    let (ok, err) = airring(
        &["classify", dir.to_str().unwrap(), "--clearance", "1e-9"],
        &[],
    );
    assert!(
        !ok && err.contains("--clearance = 1e-9 um must lie between 0.01 um and 10000 um"),
        "{err}"
    );
    // The run's films name their clearance: another one is refused, the same one taken.
    let (ok, err) = airring(
        &["classify", dir.to_str().unwrap(), "--clearance", "200"],
        &[],
    );
    assert!(
        !ok && err.contains("--clearance = 200 um: the run's films ran with C = 20 um and 20 um"),
        "{err}"
    );
    // (This run is too short to classify: the same clearance passes on to that refusal.)
    let (_, err) = airring(
        &["classify", dir.to_str().unwrap(), "--clearance", "20"],
        &[],
    );
    assert!(
        err.contains("too short to classify") && !err.contains("--clearance"),
        "{err}"
    );
    // A completed run has nothing to resume, and says so.
    let (ok, err) = airring(&["resume", dir.to_str().unwrap()], &[]);
    assert!(
        !ok && err.contains("the run completed (summary.json): nothing to resume"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_shorter_than_the_persistence_window_is_too_short_to_classify() {
    let dir = tmp("short");
    let (ok, err) = runup(&dir, &[], &[]);
    assert!(ok, "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["classification"], "too_short", "{summary}");
    assert!(summary["onset_time_s"].is_null());
    // The films' group: stepped in threads or one after the other as measured, every group step
    // counted, both ways probed within the first 80 steps and a choice reported.
    let gs = &summary["group_stepping"];
    let counted = gs["parallel_steps"].as_u64().unwrap() + gs["serial_steps"].as_u64().unwrap();
    assert!(counted >= summary["macro_steps"].as_u64().unwrap(), "{gs}");
    assert!(gs["serial_steps"].as_u64().unwrap() >= 40, "{gs}");
    assert!(
        ["parallel", "serial"].contains(&gs["choice"].as_str().unwrap()),
        "{gs}"
    );
    assert!(gs["last_probe_serial_us"].as_f64().unwrap() > 0.0, "{gs}");
    assert!(summary["criteria"]
        .as_str()
        .unwrap()
        .contains("less than the 0.1 s"));
    // The films' friction: the largest power loss (no quoted speed reached in 4 ms), its figure,
    // and power_loss = friction_torque * omega in the series.
    let max = &summary["power_loss_w"]["max"];
    assert!(
        max["total_w"].as_f64().is_some_and(|p| p > 0.0),
        "{summary}"
    );
    assert_eq!(
        summary["power_loss_w"]["at_speeds"]
            .as_array()
            .map(Vec::len),
        Some(0)
    );
    let plots: Vec<&str> = summary["plots"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap())
        .collect();
    assert!(
        plots.contains(&"power_loss.svg") && dir.join("power_loss.png").exists(),
        "{plots:?}"
    );
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.starts_with(&format!("{name} [")))
            .unwrap()
    };
    let (torque, power) = (col("film_C.friction_torque"), col("film_C.power_loss"));
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let omega = last[col("rotor.omega")];
    assert!(last[power] > 0.0);
    assert!(
        (last[power] - last[torque] * omega).abs() <= 1e-9 * last[power],
        "{last:?}"
    );
    // Every figure: real type, no text on other text or outside the figure.
    for p in plots.iter().filter(|p| p.ends_with(".svg")) {
        let svg = std::fs::read_to_string(dir.join(p)).unwrap();
        let bad = master::plot::layout::problems(&svg);
        assert!(bad.is_empty(), "{p}: {bad:#?}");
    }
    // One page with all of it: class, criteria, power loss, every figure inline, the data files.
    let n_svg = plots.iter().filter(|p| p.ends_with(".svg")).count();
    assert!(n_svg >= 7, "{plots:?}");
    let links = check_report(
        &dir,
        n_svg,
        &["too_short", "Friction power loss", "clearance C / T"],
    );
    for f in [
        "timeseries.csv",
        "summary.json",
        "system.toml",
        "power_loss.png",
    ] {
        assert!(links.iter().any(|l| l == f), "{f} not linked: {links:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Fault injection: a run-up that writes a checkpoint every 10 macro steps (so most of its time
/// is spent writing them) is killed outright (SIGKILL) at pseudo-random moments; `airring resume`
/// then either continues it to a series bit for bit equal to the uninterrupted run's, or refuses
/// with a message. It never panics and never produces another series.
#[test]
fn runs_killed_at_random_moments_resume_bit_identically_or_refuse() {
    let base = tmp("faults");
    let args = |dir: &Path| -> Vec<String> {
        [
            "runup",
            "--stop",
            "0.02",
            "--mesh",
            "8x2",
            "--quiet",
            "--checkpoint-every",
            "0.0002",
            "--out",
            dir.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec()
    };
    let straight = base.join("straight");
    let t0 = std::time::Instant::now();
    let st = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(args(&straight))
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let duration = t0.elapsed();
    let reference = std::fs::read(straight.join("timeseries.csv")).unwrap();
    // A small LCG: the same "random" moments on every run of the test.
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    let (mut resumed, mut refused) = (0, 0);
    for trial in 0..8 {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        let fraction = 0.1 + 0.8 * (seed >> 11) as f64 / (1u64 << 53) as f64;
        let dir = base.join(format!("trial{trial}"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_airring"))
            .args(args(&dir))
            .current_dir(root())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(duration.mul_f64(fraction));
        let _ = child.kill(); // SIGKILL
        let _ = child.wait();
        let out = Command::new(env!("CARGO_BIN_EXE_airring"))
            .args(["resume", dir.to_str().unwrap()])
            .current_dir(root())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!err.contains("panicked"), "trial {trial}: {err}");
        if out.status.success() {
            let series = std::fs::read(dir.join("timeseries.csv")).unwrap();
            assert!(
                series == reference,
                "trial {trial} (killed at {fraction:.2} of the run): resumed series differs"
            );
            resumed += 1;
        } else {
            assert_eq!(out.status.code(), Some(1), "trial {trial}: {err}");
            assert!(
                err.lines().any(|l| l.starts_with("airring: ")),
                "trial {trial}: {err}"
            );
            eprintln!(
                "trial {trial} refused: {}",
                err.lines().last().unwrap_or("")
            );
            refused += 1;
        }
    }
    eprintln!("fault injection: {resumed} resumed bit-identically, {refused} refused");
    assert!(resumed > 0, "no kill left a resumable checkpoint");
    let _ = std::fs::remove_dir_all(&base);
}

/// Every file of a run folder is whole: no temporary file left, no empty figure, a Parquet file
/// with both magic markers, a summary that parses.
fn assert_whole(dir: &Path) {
    for (name, bytes) in snapshot(dir) {
        assert!(!name.ends_with(".tmp"), "{name} left behind");
        if name.ends_with(".svg") || name.ends_with(".png") {
            assert!(!bytes.is_empty(), "{name} is empty");
        }
        if name.ends_with(".parquet") {
            assert!(
                bytes.starts_with(b"PAR1") && bytes.ends_with(b"PAR1"),
                "{name} is truncated"
            );
        }
        if name == "summary.json" {
            serde_json::from_slice::<serde_json::Value>(&bytes)
                .unwrap_or_else(|e| panic!("summary.json: {e}"));
        }
    }
}

/// A full disk (a 440 kB tmpfs, in a user and mount namespace of its own: one checkpoint of
/// ~385 kB fits beside the run's files and run.lock, a second one does not): the run fails with
/// the system's message, every file it leaves is whole, and once there is space again `airring
/// resume` continues from the last checkpoint to the uninterrupted run's series, bit for bit.
/// Skipped, with a message, where the machine allows no user namespaces.
#[test]
fn a_full_disk_fails_the_run_cleanly_and_resume_continues_once_there_is_space() {
    let base = tmp("full");
    let flags = "runup --stop 0.02 --mesh 8x2 --quiet --parquet --checkpoint-every 0.001";
    let straight = base.join("straight");
    let mut args: Vec<&str> = flags.split(' ').collect();
    args.extend(["--out", straight.to_str().unwrap()]);
    let (ok, err) = airring(&args, &[]);
    assert!(ok, "{err}");
    let bin = env!("CARGO_BIN_EXE_airring");
    let b = base.display();
    let script = format!(
        "set -u\n\
         M=$(mktemp -d)\n\
         mount -t tmpfs -o size=440k tmpfs \"$M\" || exit 77\n\
         \"{bin}\" {flags} --out \"$M/run\" 2> \"{b}/full.err\"; echo $? > \"{b}/full.rc\"\n\
         cp -r \"$M/run\" \"{b}/full\"\n\
         mount -o remount,size=50m \"$M\"\n\
         \"{bin}\" resume \"$M/run\" 2> \"{b}/resume.err\"; echo $? > \"{b}/resume.rc\"\n\
         cp -r \"$M/run\" \"{b}/resumed\"\n"
    );
    let status = Command::new("unshare")
        .args(["--user", "--map-root-user", "--mount", "sh", "-c", &script])
        .current_dir(root())
        .output();
    let ran = status
        .as_ref()
        .is_ok_and(|o| o.status.success() && base.join("full.rc").exists());
    if !ran {
        eprintln!(
            "SKIPPED: this machine gives no user and mount namespace for a small tmpfs ({:?})",
            status.map(|o| String::from_utf8_lossy(&o.stderr).into_owned())
        );
        return;
    }
    let read = |f: &str| std::fs::read_to_string(base.join(f)).unwrap();
    assert_eq!(read("full.rc").trim(), "1", "{}", read("full.err"));
    assert!(
        read("full.err").contains("No space left on device"),
        "{}",
        read("full.err")
    );
    assert!(
        !read("full.err").contains("panicked"),
        "{}",
        read("full.err")
    );
    assert_whole(&base.join("full"));
    assert_eq!(read("resume.rc").trim(), "0", "{}", read("resume.err"));
    assert_whole(&base.join("resumed"));
    assert!(
        std::fs::read(base.join("resumed/timeseries.csv")).unwrap()
            == std::fs::read(straight.join("timeseries.csv")).unwrap(),
        "the resumed series differs from the uninterrupted run's"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// `airring orbit` with a communication step that would give more rows than memory holds is
/// refused with one line (before: it aborted the process on a 4 GB allocation).
#[test]
fn an_orbit_step_too_small_for_memory_is_refused() {
    let dir = tmp("orbit");
    let input = dir.join("orbit.csv");
    std::fs::write(
        &input,
        "time,dx,dy,vx,vy,omega\n0,0,0,0,0,6283\n0.001,1e-6,0,0,0,6283\n",
    )
    .unwrap();
    let out = dir.join("out.csv");
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let (ok, err) = airring(
        &["orbit", "--input", i, "--out", o, "--step", "1e-300"],
        &[],
    );
    assert!(
        !ok && err.contains("steps") && err.contains("at most 1e7"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!out.exists());
    // A reasonable step still runs.
    let (ok, err) = airring(&["orbit", "--input", i, "--out", o, "--step", "100"], &[]);
    assert!(ok, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A report.html is well-formed XHTML, self-contained (no resource from the network: every
/// `href`/`src` is a relative file that exists), inlines `n_figures` SVG figures and mentions
/// every string of `must_show`. Returns the relative links.
pub fn check_report(dir: &Path, n_figures: usize, must_show: &[&str]) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let doc = roxmltree::Document::parse_with_options(
        &text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("report.html is not well-formed: {e}"));
    let svgs = doc
        .descendants()
        .filter(|n| n.tag_name().name() == "svg")
        .count();
    assert_eq!(svgs, n_figures, "inline figures");
    let mut links = vec![];
    for n in doc.descendants() {
        for a in ["href", "src"] {
            if let Some(v) = n.attribute(a) {
                assert!(!v.contains("://"), "external resource {v}");
                if n.tag_name().name() == "a" {
                    let path = dir.join(v.replace("%20", " "));
                    assert!(path.exists(), "link to missing {}", path.display());
                    links.push(v.to_string());
                }
            }
        }
    }
    for s in must_show {
        assert!(text.contains(s), "report.html lacks '{s}'");
    }
    links
}

/// `airring run --clearance` scales the whole run's analysis: a value no bore has is refused
/// before anything runs (0 used to panic after the whole simulation).
#[test]
fn a_run_refuses_a_clearance_no_bore_has_before_it_starts() {
    let dir = tmp("run-clearance");
    for (c, why) in [
        ("0", "--clearance = 0 um must be a finite number > 0"),
        ("-5", "--clearance = -5 um must be a finite number > 0"),
        ("NaN", "--clearance = NaN um must be a finite number > 0"),
        (
            "1e9",
            "--clearance = 1e9 um must lie between 0.01 um and 10000 um",
        ),
    ] {
        let out = dir.join(format!("c{c}"));
        let (ok, err) = airring(
            &[
                "run",
                "studies/does-not-matter.toml",
                "--out",
                out.to_str().unwrap(),
                &format!("--clearance={c}"),
            ],
            &[],
        );
        assert!(
            !ok && err.contains(why) && !err.contains("panicked"),
            "{c}: {err}"
        );
        assert!(!out.exists(), "{c}: nothing written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run that failed without a checkpoint is not "resumed" only to fail on the missing
/// checkpoint: the refusal says why and what to do.
#[test]
fn resume_without_a_checkpoint_says_why_before_it_starts() {
    let dir = tmp("resume-no-checkpoint");
    std::fs::write(dir.join("system.toml"), "").unwrap();
    let s = master::summary::RunSummary {
        error: Some("film_C: journal beyond the contact limit".into()),
        ..Default::default()
    };
    s.write(&dir).unwrap();
    let (ok, err) = airring(&["resume", dir.to_str().unwrap()], &[]);
    assert!(!ok, "{err}");
    assert!(
        err.contains(
            "no checkpoint to resume from (the run failed: film_C: journal beyond the contact \
             limit); run it again with --overwrite"
        ) && !err.contains("resuming"),
        "{err}"
    );
    // Killed (SIGKILL) before it ended, without --checkpoint-every: its summary says "running".
    let s = master::summary::RunSummary {
        status: master::summary::RunStatus::Running,
        ..Default::default()
    };
    s.write(&dir).unwrap();
    let (ok, err) = airring(&["resume", dir.to_str().unwrap()], &[]);
    assert!(
        !ok && err.contains(
            "no checkpoint to resume from (the run was killed before it ended, and \
             --checkpoint-every was not given); run it again with --overwrite"
        ),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The recorded path-1 system file at a 50 us macro step, on which its 50 us rows fall (its own
/// 20 us do not divide them).
fn recorded_path1_at_50_us() -> String {
    std::fs::read_to_string(root().join("master/tests/data/recorded/path1/system.toml"))
        .unwrap()
        .replace("macro_step = \"20 us\"", "macro_step = \"50 us\"")
}

/// `airring run --clearance / --dh` on a system whose films name their own bores is refused
/// before it starts: the summary's clearance and onset used to follow the flag while the films
/// ran with theirs (and `classify` of the same folder refused the flag).
#[test]
fn a_run_refuses_a_clearance_where_its_films_name_theirs() {
    let dir = tmp("run-clearance-films");
    let sys = dir.join("path1.toml");
    std::fs::write(&sys, recorded_path1_at_50_us()).unwrap();
    for flags in [
        &["--clearance", "60"][..],
        &["--clearance", "20", "--dh", "40"],
    ] {
        let out = dir.join("out");
        let mut args = vec!["run", sys.to_str().unwrap(), "--out", out.to_str().unwrap()];
        args.extend_from_slice(flags);
        let (ok, err) = airring(&args, &[]);
        assert!(
            !ok && err.contains(
                "the system's films film_C and film_T name their own bores (C = 20 um and 20 \
                 um, dH = 40 um and 40 um)"
            ),
            "{flags:?}: {err}"
        );
        assert!(!out.exists(), "{flags:?}: nothing written");
    }
    // --dh describes the bore of --clearance: alone it is refused by the parser.
    let (ok, err) = airring(&["run", sys.to_str().unwrap(), "--dh", "40"], &[]);
    assert!(!ok && err.contains("--clearance"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `airring run` writes rows at macro steps only, as `runup` does: an output interval that is
/// not a whole number of macro steps is refused with the file, line and field (70 us at a 50 us
/// step gave rows 50 and 100 us apart).
#[test]
fn a_run_refuses_an_output_interval_between_macro_steps() {
    let dir = tmp("run-interval");
    let text = recorded_path1_at_50_us().replace("interval = \"50 us\"", "interval = \"70 us\"");
    let sys = dir.join("s.toml");
    std::fs::write(&sys, text).unwrap();
    let out = dir.join("out");
    let (ok, err) = airring(
        &["run", sys.to_str().unwrap(), "--out", out.to_str().unwrap()],
        &[],
    );
    assert!(!ok, "{err}");
    assert!(
        err.contains(&format!(
            "{}:131: output.interval: 7e-5 s is not a whole number of macro steps (5e-5 s)",
            sys.display()
        )),
        "{err}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
