//! Project tasks: `cargo xtask <task>`.
//!
//! - `fmus [--glibc V]` build the release cdylibs and pack target/fmu/{airfilm,rotor,oscillator}.fmu
//!   (`--glibc 2.17`: linked by cargo-zigbuild against that glibc, for older Linux)
//! - `descriptions`    regenerate modelDescriptions/*.xml from the variable tables (`--check`: compare only)
//! - `test`            everything CI runs: fmt, clippy, docs, fmus, descriptions --check, cargo test, pytest
//!   (its prerequisites checked first, installed where it may: prereq.rs)
//! - `test --quick`    the edit loop's tier: fmt, clippy, the libraries' and binaries' unit tests
//! - `cli-reference [--check]`  docs/reference/cli.md from the binary's help (docs.rs)
//! - `docs-check`      the CLI reference is current, doc links resolve, no change log in docs/
//! - `runup [ARGS]`    build the FMUs and the master, then `airring runup ARGS` (default: the path-1 run-up)
//! - `bench`           the benchmarks of the hot loops (medians), then the run-up benchmark
//! - `bench runup [--preset P] [--stop S] [--runs N] [--load] [--fmu-dir D] [--design F]`: the whole run-up,
//!   medians of wall time, macro steps, time in each FMU and the master's share (`bench.rs`)

mod bench;
mod docs;
mod pack;
mod prereq;

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Where cargo puts its builds: `$CARGO_TARGET_DIR` (relative to the workspace root, as cargo
/// reads it from the root), else `target/`. The FMUs are packed into its `fmu/`.
fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) if !d.is_empty() => root().join(d),
        _ => root().join("target"),
    }
}

/// Runs a command in the workspace root, echoing it; an error names the failed step.
fn run(step: &str, cmd: &mut Command) -> Result<(), String> {
    cmd.current_dir(root());
    eprintln!("==> {step}: {:?}", cmd);
    let status = cmd
        .status()
        .map_err(|e| format!("{step}: cannot start: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{step} failed ({status})"))
    }
}

fn cargo() -> Command {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
}

fn venv_python() -> Result<PathBuf, String> {
    let venv = root().join(".venv");
    let py = venv.join("bin").join("python");
    let ready = py.exists()
        && Command::new(&py)
            .args([
                "-c",
                "import fmpy, pytest, numpy, libcosimpy, importlib.metadata as m; m.version('ecospy'); assert m.version('ross-rotordynamics') == '2.3.0'",
            ])
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
    if !ready {
        run(
            "python venv",
            Command::new("python3").args(["-m", "venv"]).arg(&venv),
        )?;
        run(
            "pip install",
            Command::new(&py).args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                "-r",
                "tests/python/requirements.txt",
            ]),
        )?;
    }
    Ok(py)
}

fn test(quick: bool) -> Result<(), String> {
    prereq::ensure(!quick)?;
    run(
        "format check",
        cargo().args(["fmt", "--all", "--", "--check"]),
    )?;
    run(
        "clippy",
        cargo().args([
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ]),
    )?;
    if quick {
        // Unit tests only: the integration tests (tests/ folders) run co-simulations, FMPy and
        // packed FMUs.
        return run(
            "cargo test (unit)",
            cargo().args(["test", "--workspace", "--lib", "--bins", "--no-fail-fast"]),
        );
    }
    run(
        "clippy (FMU exports)",
        cargo()
            .args([
                "clippy",
                "--lib",
                "-p",
                "fmu-airfilm",
                "-p",
                "fmu-rotor",
                "-p",
                "fmu-oscillator",
                "--features",
            ])
            .arg(pack::features())
            .args(["--", "-D", "warnings"]),
    )?;
    run(
        "docs",
        cargo()
            .args(["doc", "--workspace", "--no-deps"])
            .env("RUSTDOCFLAGS", "-D warnings"),
    )?;
    pack::fmus(None)?;
    pack::descriptions(true)?;
    docs::check()?;
    let py = venv_python()?;
    // The tests' temporary folders (run folders, unpacked FMUs, the third-party masters' own
    // scratch) go to one folder under the target directory, emptied before the tests and removed
    // after a green run: a test that leaves its folder behind cannot fill the machine's /tmp
    // over repeated runs. A red run keeps it for a look.
    let tmp = target_dir().join("test-tmp");
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?;
    run(
        "cargo test",
        cargo().args(["test", "--workspace"]).env("TMPDIR", &tmp),
    )?;
    run(
        "pytest",
        Command::new(py)
            .args(["-m", "pytest", "-q", "tests/python"])
            .env("TMPDIR", &tmp),
    )?;
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
}

fn runup(args: &[String]) -> Result<(), String> {
    pack::fmus(None)?;
    run(
        "build master",
        cargo().args(["build", "--release", "-p", "master"]),
    )?;
    let mut cmd = Command::new(target_dir().join("release/airring"));
    cmd.arg("runup");
    if args.is_empty() {
        cmd.args(["--preset", "path1"]);
    }
    cmd.args(args);
    run("airring runup", &mut cmd)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("fmus") => match args.get(1).map(String::as_str) {
            None => pack::fmus(None),
            Some("--glibc") => match args.get(2) {
                Some(v) => pack::fmus(Some(v)),
                None => Err("--glibc expects a version, e.g. 2.17".into()),
            },
            Some(other) => Err(format!("fmus: unknown argument '{other}'")),
        },
        Some("descriptions") => pack::descriptions(args.iter().any(|a| a == "--check")),
        Some("test") => match args.get(1).map(String::as_str) {
            None => test(false),
            Some("--quick") => test(true),
            Some(other) => Err(format!("test: unknown argument '{other}' (test [--quick])")),
        },
        Some("runup") => runup(&args[1..]),
        Some("cli-reference") => docs::cli_reference(args.iter().any(|a| a == "--check")),
        Some("docs-check") => docs::check(),
        Some("bench") => match args.get(1).map(String::as_str) {
            Some("runup") => {
                bench::Options::parse(&args[2..]).and_then(|o| bench::runup(&o))
            }
            None => run("bench", cargo().args(["bench", "--workspace"])).and_then(|_| {
                bench::Options::parse(&[]).and_then(|o| bench::runup(&o))
            }),
            Some(other) => Err(format!("bench: unknown argument '{other}' (bench [runup ...])")),
        },
        _ => Err(
            "usage: cargo xtask fmus [--glibc V] | descriptions [--check] | test [--quick] | cli-reference [--check] | docs-check | runup [ARGS] | bench [runup [--preset P] [--stop S] [--runs N] [--load] [--fmu-dir D] [--design F]]".into(),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}
