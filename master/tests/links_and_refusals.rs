//! AirRing writes only inside the folder it is given, and a refusal leaves everything as it was.
//! A symbolic link inside a run or sweep folder (a shared scratch space, a linked results
//! folder, or one planted) is replaced or refused, never followed for writing or deleting.
//! End to end on the packed FMUs (`cargo xtask fmus` first).

mod common;

use common::{airring, root};
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let d = common::tmp("links", name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const SHORT: &[&str] = &[
    "runup",
    "--stop",
    "0.004",
    "--mesh",
    "8x2",
    "--quiet",
    "--parquet",
    "--checkpoint-every",
    "0.002",
];

fn runup(dir: &Path, extra: &[&str]) -> (bool, String) {
    let mut args: Vec<&str> = SHORT.to_vec();
    args.extend_from_slice(&["--out", dir.to_str().unwrap()]);
    args.extend_from_slice(extra);
    airring(&args)
}

/// Every entry under `dir` by relative name: a file with its bytes, a link with its target
/// (not followed), a folder with its entries.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = vec![];
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let t = e.file_type().unwrap();
        if t.is_symlink() {
            let target = std::fs::read_link(e.path()).unwrap();
            out.push((
                format!("{name} ->"),
                target.to_string_lossy().as_bytes().to_vec(),
            ));
        } else if t.is_dir() {
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

/// The relative paths of the files under `dir` (links and folders left out).
fn files(dir: &Path) -> Vec<String> {
    snapshot(dir)
        .into_iter()
        .map(|(n, _)| n)
        .filter(|n| !n.ends_with(" ->"))
        .collect()
}

/// Links under `dir`, anywhere below.
fn links(dir: &Path) -> Vec<String> {
    snapshot(dir)
        .into_iter()
        .map(|(n, _)| n)
        .filter(|n| n.ends_with(" ->"))
        .collect()
}

/// Plants, for every file `p` a finished run or sweep wrote (and its temporary name `p.tmp`), a
/// link in `into` pointing at a victim file of its own in `victims`. Returns the victims.
fn plant_links(outputs: &[String], into: &Path, victims: &Path) -> Vec<PathBuf> {
    std::fs::create_dir_all(victims).unwrap();
    let mut planted = vec![];
    for (k, rel) in outputs.iter().enumerate() {
        for name in [rel.clone(), format!("{rel}.tmp")] {
            let link = into.join(&name);
            std::fs::create_dir_all(link.parent().unwrap()).unwrap();
            let victim = victims.join(format!("victim-{k}-{}", name.replace('/', "_")));
            std::fs::write(&victim, format!("victim {name}")).unwrap();
            std::os::unix::fs::symlink(&victim, &link).unwrap();
            planted.push(victim);
        }
    }
    planted
}

fn assert_victims_untouched(victims: &[PathBuf]) {
    for v in victims {
        let text = std::fs::read_to_string(v)
            .unwrap_or_else(|e| panic!("{}: removed or unreadable ({e})", v.display()));
        assert!(text.starts_with("victim "), "{}: overwritten", v.display());
    }
}

/// A run-up with --overwrite into a folder whose every output file (series, system file,
/// summary, report, figures, Parquet, their temporary names) is a link to another file, and whose
/// checkpoint folder is a link to another folder: every link is replaced by the run's own file,
/// nothing outside the folder changes, and the series is that of a run into a fresh folder.
#[test]
fn a_run_up_replaces_links_in_its_folder_and_writes_nothing_through_them() {
    assert!(
        root().join("target/fmu/rotor.fmu").exists(),
        "run `cargo xtask fmus` first"
    );
    let base = tmp("runup");
    let a = base.join("A");
    let (ok, err) = runup(&a, &[]);
    assert!(ok, "{err}");
    let outputs: Vec<String> = files(&a)
        .into_iter()
        .filter(|f| !f.starts_with("checkpoint/"))
        .collect();
    for f in [
        "timeseries.csv",
        "system.toml",
        "summary.json",
        "report.html",
        "timeseries.parquet",
    ] {
        assert!(outputs.iter().any(|o| o == f), "{f} in {outputs:?}");
    }
    assert!(outputs.iter().any(|o| o.ends_with(".svg")), "{outputs:?}");
    let b = base.join("B");
    std::fs::create_dir_all(&b).unwrap();
    let victims = plant_links(&outputs, &b, &base.join("victims"));
    // The checkpoint folder: a link to another run's checkpoint, which must keep its files.
    let other_cp = base.join("other-checkpoint");
    std::fs::create_dir_all(&other_cp).unwrap();
    std::fs::write(other_cp.join("rotor.1-2.state"), "theirs").unwrap();
    std::fs::write(other_cp.join("master.json"), "theirs").unwrap();
    std::os::unix::fs::symlink(&other_cp, b.join("checkpoint")).unwrap();
    let (ok, err) = runup(&b, &["--overwrite"]);
    assert!(ok, "{err}");
    assert_victims_untouched(&victims);
    assert_eq!(
        std::fs::read_to_string(other_cp.join("rotor.1-2.state")).unwrap(),
        "theirs"
    );
    assert_eq!(
        std::fs::read_to_string(other_cp.join("master.json")).unwrap(),
        "theirs"
    );
    let left: Vec<String> = links(&b)
        .into_iter()
        .filter(|l| !l.ends_with(".tmp ->"))
        .collect();
    assert!(left.is_empty(), "links left in the run folder: {left:?}");
    assert!(b.join("checkpoint/master.json").is_file());
    assert!(
        std::fs::read(a.join("timeseries.csv")).unwrap()
            == std::fs::read(b.join("timeseries.csv")).unwrap(),
        "the series differs from a run into a fresh folder"
    );

    // export-ssp --overwrite onto a link: the link is replaced by the archive.
    let ssp_victim = base.join("victims/archive");
    std::fs::write(&ssp_victim, "victim archive").unwrap();
    let ssp = base.join("system.ssp");
    std::os::unix::fs::symlink(&ssp_victim, &ssp).unwrap();
    let sys = a.join("system.toml");
    let (ok, err) = airring(&[
        "export-ssp",
        sys.to_str().unwrap(),
        "--out",
        ssp.to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("exists"),
        "a link counts as existing: {err}"
    );
    let (ok, err) = airring(&[
        "export-ssp",
        sys.to_str().unwrap(),
        "--out",
        ssp.to_str().unwrap(),
        "--overwrite",
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        std::fs::read_to_string(&ssp_victim).unwrap(),
        "victim archive"
    );
    assert!(!std::fs::symlink_metadata(&ssp).unwrap().is_symlink());
    assert!(std::fs::read(&ssp).unwrap().starts_with(b"PK"));
    let _ = std::fs::remove_dir_all(&base);
}

/// An interrupted run (its summary says so; its checkpoint is at 2 of 4 ms).
fn interrupted_run(dir: &Path) {
    let (ok, err) = runup(dir, &[]);
    assert!(ok, "{err}");
    let path = dir.join("summary.json");
    let mut s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    s["status"] = "interrupted".into();
    std::fs::write(&path, serde_json::to_string_pretty(&s).unwrap()).unwrap();
}

/// `resume` refuses a checkpoint folder that is a link (it would write new generations into the
/// link's target and delete the files there that are not its own), and a series cut short; in
/// both cases the folder, and the link's target, stay byte for byte as they were (a refused
/// resume once rewrote summary.json into a "running" stub, losing the interrupted part's results).
#[test]
fn a_refused_resume_changes_nothing_and_follows_no_link() {
    let base = tmp("resume");
    let run = base.join("run");
    interrupted_run(&run);
    let cp = base.join("elsewhere");
    std::fs::rename(run.join("checkpoint"), &cp).unwrap();
    std::fs::write(cp.join("another-run.1-1.state"), "theirs").unwrap();
    std::os::unix::fs::symlink(&cp, run.join("checkpoint")).unwrap();
    let (before, before_cp) = (snapshot(&run), snapshot(&cp));
    let (ok, err) = airring(&["resume", run.to_str().unwrap()]);
    assert!(!ok && err.contains("is a symbolic link"), "{err}");
    assert!(
        snapshot(&run) == before,
        "a refused resume changed the run folder"
    );
    assert!(
        snapshot(&cp) == before_cp,
        "a refused resume changed the link's target"
    );

    // The checkpoint back in place, the series cut: refused, nothing changed.
    std::fs::remove_file(run.join("checkpoint")).unwrap();
    std::fs::remove_file(cp.join("another-run.1-1.state")).unwrap();
    std::fs::rename(&cp, run.join("checkpoint")).unwrap();
    let series = std::fs::read(run.join("timeseries.csv")).unwrap();
    std::fs::write(run.join("timeseries.csv"), &series[..series.len() / 4]).unwrap();
    let before = snapshot(&run);
    let (ok, err) = airring(&["resume", run.to_str().unwrap()]);
    assert!(!ok, "{err}");
    assert!(
        snapshot(&run) == before,
        "a refused resume changed the run folder: {err}"
    );
    // Missing altogether: the same.
    std::fs::remove_file(run.join("timeseries.csv")).unwrap();
    let before = snapshot(&run);
    let (ok, err) = airring(&["resume", run.to_str().unwrap()]);
    assert!(!ok, "{err}");
    assert!(
        snapshot(&run) == before,
        "a refused resume changed the run folder: {err}"
    );

    // With the series whole again the resume goes ahead (the refusals above were the only
    // obstacle) and completes.
    std::fs::write(run.join("timeseries.csv"), &series).unwrap();
    let (ok, err) = airring(&["resume", run.to_str().unwrap()]);
    assert!(ok, "{err}");
    let _ = std::fs::remove_dir_all(&base);
}

/// `resume` of a run still going (its lock held by a live process on this host), without a
/// checkpoint: it is in progress, not "killed".
#[test]
fn resume_of_a_live_run_says_it_is_in_progress() {
    let dir = tmp("live");
    std::fs::write(dir.join("system.toml"), "").unwrap();
    let s = master::summary::RunSummary {
        status: master::summary::RunStatus::Running,
        ..Default::default()
    };
    s.write(&dir).unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    // This test's own process is alive.
    std::fs::write(
        dir.join("run.lock"),
        format!("{} {}\n", std::process::id(), host.trim()),
    )
    .unwrap();
    let (ok, err) = airring(&["resume", dir.to_str().unwrap()]);
    assert!(
        !ok && err.contains("a run is in progress here") && !err.contains("killed"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sweep into a folder whose every output (the runs' files, the table, maps, report, study
/// file, logs, their temporary names) is a link: every link is replaced, no victim changes.
/// Then `sweep-sensitivity` names a run it leaves out because its summary.json is unreadable.
#[test]
fn a_sweep_replaces_links_in_its_folder_and_sensitivity_names_what_it_leaves_out() {
    let base = tmp("sweep");
    let study = base.join("study.toml");
    std::fs::write(
        &study,
        "name = \"links\"\n[fixed]\npreset = \"path1\"\nstop = 0.004\nmacro_step = 20\n\
         mesh = \"8x2\"\n[[grid]]\nc = [500, 1000]\n",
    )
    .unwrap();
    let first = base.join("first");
    let (ok, err) = airring(&[
        "sweep",
        study.to_str().unwrap(),
        "--out",
        first.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let outputs = files(&first);
    assert!(
        outputs.iter().any(|o| o.ends_with("/timeseries.csv"))
            && outputs.iter().any(|o| o == "study.csv")
            && outputs.iter().any(|o| o.ends_with("/sweep_run.json")),
        "{outputs:?}"
    );
    let second = base.join("second");
    let victims = plant_links(&outputs, &second, &base.join("victims"));
    let (ok, err) = airring(&[
        "sweep",
        study.to_str().unwrap(),
        "--out",
        second.to_str().unwrap(),
        "--quiet",
        "--overwrite",
    ]);
    assert!(ok, "{err}");
    assert_victims_untouched(&victims);
    let left: Vec<String> = links(&second)
        .into_iter()
        .filter(|l| !l.ends_with(".tmp ->"))
        .collect();
    assert!(left.is_empty(), "links left in the sweep folder: {left:?}");

    // A run folder that is itself a link is refused, not written into.
    let third = base.join("third");
    std::fs::create_dir_all(third.join("runs")).unwrap();
    let elsewhere = base.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let run_name = outputs
        .iter()
        .find_map(|o| o.strip_prefix("runs/"))
        .and_then(|o| o.split('/').next())
        .unwrap()
        .to_string();
    std::os::unix::fs::symlink(&elsewhere, third.join("runs").join(&run_name)).unwrap();
    let (ok, err) = airring(&[
        "sweep",
        study.to_str().unwrap(),
        "--out",
        third.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!ok && err.contains("symbolic link"), "{err}");
    assert!(std::fs::read_dir(&elsewhere).unwrap().next().is_none());

    // sweep-sensitivity: the run whose summary.json cannot be read is named.
    std::fs::write(
        first.join("runs").join(&run_name).join("summary.json"),
        "{ not json",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(["sweep-sensitivity", first.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("1 runs left out")
            && text.contains(&format!("{run_name}: summary.json unreadable")),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// `sweep-merge` joins the shards of one study only: folders of different studies (another stop
/// time, another name) are refused naming what differs, and so are runs of one name made with
/// different flags where no study file tells.
#[test]
fn sweep_merge_refuses_folders_of_different_studies() {
    let base = tmp("merge");
    let smoke = std::fs::read_to_string(root().join("studies/smoke.toml")).unwrap();
    let run = |dir: &Path, name: &str, mesh: &str| {
        let r = dir.join("runs").join(name);
        std::fs::create_dir_all(&r).unwrap();
        std::fs::write(
            r.join("sweep_run.json"),
            serde_json::json!({"name": name, "index": 0, "args": {"c": "500", "mesh": mesh},
                               "defaults": {"macro_step_us": 50.0}})
            .to_string(),
        )
        .unwrap();
    };
    let (a, b) = (base.join("a"), base.join("b"));
    for d in [&a, &b] {
        run(d, "C20_c500", "8x2");
    }
    std::fs::write(a.join("study.toml"), &smoke).unwrap();
    std::fs::write(
        b.join("study.toml"),
        smoke
            .replace("stop = 0.01", "stop = 0.02")
            .replace("name = \"smoke\"", "name = \"other\""),
    )
    .unwrap();
    let out = base.join("merged");
    let (ok, err) = airring(&[
        "sweep-merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("different studies")
            && err.contains("fixed.stop")
            && err.contains("name"),
        "{err}"
    );
    assert!(!out.exists(), "a refused merge wrote {}", out.display());
    // Without study files: the runs of one name differ in their flags.
    let (c, d) = (base.join("c"), base.join("d"));
    run(&c, "C20_c500", "8x2");
    run(&d, "C20_c500", "20x6");
    let (ok, err) = airring(&[
        "sweep-merge",
        c.to_str().unwrap(),
        d.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("run C20_c500") && err.contains("args.mesh"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&base);
}

/// Runs `script` (sh) in a user and mount namespace of its own, where it may mount a small
/// tmpfs; false (the test is skipped, with a message) where the machine allows no such
/// namespace.
fn in_namespace(script: &str, marker: &Path) -> bool {
    let status = std::process::Command::new("unshare")
        .args(["--user", "--map-root-user", "--mount", "sh", "-c", script])
        .current_dir(root())
        .output();
    let ran = status
        .as_ref()
        .is_ok_and(|o| o.status.success() && marker.exists());
    if !ran {
        eprintln!(
            "SKIPPED: this machine gives no user and mount namespace for a small tmpfs ({:?})",
            status.map(|o| String::from_utf8_lossy(&o.stderr).into_owned())
        );
    }
    ran
}

/// Outputs that do not fit on the disk are errors the caller sees: figures that cannot be
/// written fail the run (exit status 1, the figures named), though summary.json is complete; a
/// series that fills the disk is named as what failed, not the summary that could not be written
/// after it; an SSP archive that does not fit leaves no truncated file under its name and no
/// debug output of the zip library.
#[test]
fn outputs_that_do_not_fit_on_the_disk_are_errors_naming_what_failed() {
    let base = tmp("full");
    let straight = base.join("straight");
    let flags = "runup --stop 0.004 --mesh 8x2 --quiet";
    let mut args: Vec<&str> = flags.split(' ').collect();
    args.extend(["--out", straight.to_str().unwrap()]);
    let (ok, err) = airring(&args);
    assert!(ok, "{err}");
    let size = |f: &str| std::fs::metadata(straight.join(f)).unwrap().len();
    // Room for the series, the system file, the summary (twice: its temporary copy) and the lock,
    // with a page each to spare, but not for the figures.
    let data = size("timeseries.csv") + size("system.toml") + 2 * size("summary.json") + 5 * 4096;
    let figures: u64 = files(&straight)
        .iter()
        .filter(|f| f.ends_with(".png") || f.ends_with(".svg"))
        .map(|f| size(f))
        .sum();
    assert!(figures > 8 * 4096, "figures of {figures} bytes");
    let fits_data_kb = data.div_ceil(4096) * 4;
    // Room for the system file, the lock, the "running" summary and its temporary copy, and
    // half the series: the series itself fills the disk.
    let pages = |bytes: u64| bytes.div_ceil(4096);
    let half_kb =
        4 * (pages(size("system.toml")) + 1 + 2 * pages(1000) + pages(size("timeseries.csv")) / 2);
    let bin = env!("CARGO_BIN_EXE_airring");
    let b = base.display();
    let sys = straight.join("system.toml");
    let sys = sys.display();
    let script = format!(
        "set -u\n\
         M=$(mktemp -d)\n\
         mount -t tmpfs -o size={fits_data_kb}k tmpfs \"$M\" || exit 77\n\
         \"{bin}\" {flags} --out \"$M/figs\" 2> \"{b}/figs.err\"; echo $? > \"{b}/figs.rc\"\n\
         cp -r \"$M/figs\" \"{b}/figs\"\n\
         umount \"$M\"\n\
         mount -t tmpfs -o size={half_kb}k tmpfs \"$M\"\n\
         \"{bin}\" {flags} --out \"$M/series\" 2> \"{b}/series.err\"; echo $? > \"{b}/series.rc\"\n\
         \"{bin}\" export-ssp \"{sys}\" --out \"$M/system.ssp\" 2> \"{b}/ssp.err\"; echo $? > \"{b}/ssp.rc\"\n\
         ls \"$M\" > \"{b}/ssp.ls\"\n\
         touch \"{b}/done\"\n"
    );
    if !in_namespace(&script, &base.join("done")) {
        return;
    }
    let read = |f: &str| std::fs::read_to_string(base.join(f)).unwrap();
    // Figures: the run fails and says which outputs are missing; the summary written before
    // the figures keeps the results.
    assert_eq!(read("figs.rc").trim(), "1", "{}", read("figs.err"));
    assert!(
        read("figs.err").contains("figures not written"),
        "{}",
        read("figs.err")
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(base.join("figs/summary.json")).unwrap())
            .unwrap();
    assert!(summary["classification"].is_string(), "{summary}");
    assert_eq!(summary["status"], "completed", "{summary}");
    // The series fills the disk: it is named first.
    let e = read("series.err");
    assert_eq!(read("series.rc").trim(), "1", "{e}");
    let first_error = e
        .lines()
        .find(|l| l.contains("No space left"))
        .unwrap_or("");
    assert!(
        first_error.contains("timeseries.csv")
            && first_error.find("timeseries.csv")
                < first_error.find("summary.json").or(Some(usize::MAX)),
        "{e}"
    );
    // The archive does not fit: refused, nothing under its name, no debug line.
    let e = read("ssp.err");
    assert_eq!(read("ssp.rc").trim(), "1", "{e}");
    assert!(
        e.contains("No space left") && !e.contains("ZipWriter"),
        "{e}"
    );
    assert!(!read("ssp.ls").contains("system.ssp"), "{}", read("ssp.ls"));
    let _ = std::fs::remove_dir_all(&base);
}
