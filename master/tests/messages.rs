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
