//! A negative number given as its own argument ("--d -1") reaches the command's own check, which
//! names the flag and its unit, instead of the argument parser's "unexpected argument '-1'"
//! (every subcommand with numeric flags, not only `runup`).

mod common;

use common::{airring, tmp};

#[test]
fn negative_numbers_reach_the_commands_checks() {
    let dir = tmp("negative-numbers", "modal");
    let out = dir.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["modal", "--speed", "-10", "--out", out],
            "--speed -10 Hz must lie",
        ),
        (
            &["modal", "--speed", "500", "--d", "-1", "--out", out],
            "--d = -1 N s/m must be",
        ),
        (
            &["modal", "--speed", "500", "--m-r", "-2", "--out", out],
            "--m-r = -2 g must be",
        ),
        (
            &[
                "orbits",
                "--preset",
                "path2a",
                "--speeds",
                "500:500:1",
                "--settle",
                "-1",
                "--out",
                out,
            ],
            "--settle -1 s",
        ),
    ];
    for (args, expected) in cases {
        let (ok, err) = airring(args);
        assert!(!ok, "{args:?} accepted");
        assert!(
            err.contains(expected) && !err.contains("unexpected argument"),
            "{args:?}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
