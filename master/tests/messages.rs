//! Every flag is checked before any work, and numbers in messages are short: what a new user
//! met in the third abuse round (`orbits --clearance nan` settled for a second and named a
//! generated file it left behind; 1e300 printed as 301 digits).

mod common;

use common::airring;

/// No run of 40 or more digits in `text` (a number printed in full instead of with an exponent).
fn has_long_number(text: &str) -> bool {
    let mut run = 0;
    for c in text.chars() {
        run = if c.is_ascii_digit() { run + 1 } else { 0 };
        if run >= 40 {
            return true;
        }
    }
    false
}

#[test]
fn orbits_checks_every_flag_before_any_work() {
    let out = common::tmp("messages", "orbits");
    for (flag, value, expect) in [
        ("--clearance", "nan", "--clearance"),
        ("--c", "-5", "--c"),
        ("--settle", "inf", "--settle"),
        ("--speeds", "600:100:10", "--speeds"),
    ] {
        let mut args = vec!["orbits", "--out", out.to_str().unwrap()];
        if flag != "--speeds" {
            args.extend(["--speeds", "600"]);
        }
        args.extend([flag, value]);
        let t0 = std::time::Instant::now();
        let (ok, err) = airring(&args);
        assert!(!ok && err.contains(expect), "{flag} {value}: {err}");
        assert!(
            !err.contains("settling") && !err.contains("system-"),
            "{flag} {value}: {err}"
        );
        assert!(!out.exists(), "{flag} {value}: --out was created");
        // Refused at once, not after a simulation (a second of settling takes seconds).
        assert!(
            t0.elapsed().as_secs_f64() < 5.0,
            "{flag} {value}: {:?}",
            t0.elapsed()
        );
    }
}

#[test]
fn tiny_and_huge_numbers_are_printed_with_an_exponent() {
    let dir = common::tmp("messages", "numbers");
    std::fs::create_dir_all(&dir).unwrap();
    // A profile point at 1e300 s: the run-up's header line.
    let (_, err) = airring(&[
        "runup",
        "--profile",
        "0:0,1e300:100",
        "--stop",
        "0.001",
        "--mesh",
        "8x2",
        "--quiet",
        "--out",
        dir.join("profile").to_str().unwrap(),
    ]);
    assert!(err.contains("1e300"), "{err}");
    assert!(!has_long_number(&err), "{err}");
    // A system file's macro step of 1e-300 s.
    let (ok, _) = airring(&[
        "runup",
        "--stop",
        "0.001",
        "--mesh",
        "8x2",
        "--quiet",
        "--out",
        dir.join("run").to_str().unwrap(),
    ]);
    assert!(ok);
    let text = std::fs::read_to_string(dir.join("run/system.toml")).unwrap();
    let start = text.find("macro_step = ").unwrap();
    let end = start + text[start..].find('\n').unwrap();
    let sys = dir.join("tiny.toml");
    std::fs::write(
        &sys,
        format!(
            "{}macro_step = \"1e-300 s\"{}",
            &text[..start],
            &text[end..]
        ),
    )
    .unwrap();
    let (ok, err) = airring(&[
        "run",
        sys.to_str().unwrap(),
        "--out",
        dir.join("tiny").to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("1e-300 s"), "{err}");
    assert!(!has_long_number(&err), "{err}");
    // `orbit --step 1e-300` [us].
    let csv = dir.join("orbit.csv");
    std::fs::write(&csv, "time,dx,dy,omega\n0,0,0,100\n0.001,0,0,100\n").unwrap();
    let (ok, err) = airring(&[
        "orbit",
        "--input",
        csv.to_str().unwrap(),
        "--out",
        dir.join("orbit-out.csv").to_str().unwrap(),
        "--step",
        "1e-300",
    ]);
    assert!(!ok, "{err}");
    assert!(!has_long_number(&err), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A stop signal that arrives after the last macro step (while the figures are drawn) does not
/// announce a checkpoint: none is written, and the message says the run has ended. The signal
/// is sent once summary.json holds the class, which is written before the figures; where the
/// run is over before the test sees that (a very fast machine), it tries a longer run.
#[test]
fn a_stop_signal_after_the_last_macro_step_announces_no_checkpoint() {
    for (attempt, stop) in ["0.02", "0.05", "0.1"].iter().enumerate() {
        let dir = common::tmp("messages", &format!("late-signal-{attempt}"));
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_airring"))
            .args(["runup", "--stop", stop, "--mesh", "8x2", "--quiet", "--out"])
            .arg(&dir)
            .current_dir(common::root())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut signalled = false;
        while child.try_wait().unwrap().is_none() {
            let classified = std::fs::read_to_string(dir.join("summary.json"))
                .ok()
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
                .is_some_and(|s| s["classification"].is_string());
            if classified {
                // SAFETY: signals our own child process.
                unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
                signalled = true;
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        if !signalled || !err.contains("stop signal") {
            let _ = std::fs::remove_dir_all(&dir);
            continue;
        }
        assert!(
            err.contains("after the run's last macro step")
                && !err.contains("checkpoint and summary are written"),
            "{err}"
        );
        assert!(!dir.join("checkpoint").exists());
        assert!(out.status.success(), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
    eprintln!("SKIPPED: every run ended before its summary could be seen");
}
