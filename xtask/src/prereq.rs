//! What `cargo xtask test` needs besides Rust, checked before anything is built: a failure two
//! minutes into clippy ("Unable to find libclang") tells a new user nothing about what to install.
//!
//! Each missing piece is installed where that is safe to do unasked (root on a Debian-like system:
//! `apt-get`; rustup for rustfmt and clippy); elsewhere the task stops at once with the one command
//! that installs everything missing.

use std::path::Path;
use std::process::{Command, Stdio};

/// One prerequisite: what it is for, how to tell it is there, and its Debian packages.
struct Need {
    what: &'static str,
    present: fn() -> bool,
    debian: &'static [&'static str],
    /// Needed by the full suite only (the Python tests), not by `--quick`.
    full_only: bool,
}

fn runs(cmd: &str, args: &[&str]) -> bool {
    Command::new(cmd)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Files named like `prefix*` in any of `dirs` (one level, plus `llvm-*/lib`).
fn library_present(prefixes: &[&str]) -> bool {
    let mut dirs: Vec<std::path::PathBuf> = [
        "/usr/lib",
        "/usr/lib64",
        "/usr/local/lib",
        "/usr/lib/x86_64-linux-gnu",
        "/usr/lib/aarch64-linux-gnu",
        "/lib/x86_64-linux-gnu",
    ]
    .iter()
    .map(Into::into)
    .collect();
    if let Ok(entries) = std::fs::read_dir("/usr/lib") {
        for e in entries.flatten() {
            if e.file_name().to_string_lossy().starts_with("llvm-") {
                dirs.push(e.path().join("lib"));
            }
        }
    }
    if let Some(p) = std::env::var_os("LIBCLANG_PATH") {
        dirs.push(p.into());
    }
    dirs.iter().any(|d| {
        std::fs::read_dir(d).is_ok_and(|entries| {
            entries.flatten().any(|e| {
                let n = e.file_name().to_string_lossy().into_owned();
                prefixes.iter().any(|p| n.starts_with(p))
            })
        })
    })
}

/// clang's own headers (`stddef.h`), which bindgen's libclang reads.
fn clang_headers_present() -> bool {
    let Ok(llvms) = std::fs::read_dir("/usr/lib") else {
        return false;
    };
    llvms.flatten().any(|llvm| {
        let clang = llvm.path().join("lib/clang");
        llvm.file_name().to_string_lossy().starts_with("llvm-")
            && std::fs::read_dir(&clang).is_ok_and(|versions| {
                versions
                    .flatten()
                    .any(|v| v.path().join("include/stddef.h").exists())
            })
    }) || Path::new("/usr/include/clang").exists()
}

fn needs() -> Vec<Need> {
    vec![
        Need {
            what: "a C compiler (cc: the FMI importers' log shim)",
            present: || runs("cc", &["--version"]),
            debian: &["gcc"],
            full_only: false,
        },
        Need {
            what: "binutils (nm, objdump, objcopy: the FMU export and packing checks)",
            present: || {
                runs("nm", &["--version"])
                    && runs("objdump", &["--version"])
                    && runs("objcopy", &["--version"])
            },
            debian: &["binutils"],
            full_only: false,
        },
        Need {
            what: "Python 3 with venv (the FMPy, libcosim, ecos and Dask tests)",
            present: || runs("python3", &["-c", "import venv, ensurepip"]),
            debian: &["python3", "python3-venv"],
            full_only: true,
        },
        Need {
            what: "libclang (bindgen in rust-fmi, the independent FMI 3.0 importer of the tests)",
            // libclang.so.1, libclang-14.so.1; not libclang-cpp.so (another library).
            present: || library_present(&["libclang.so", "libclang-1", "libclang-2"]),
            debian: &["libclang1-14"],
            full_only: false,
        },
        Need {
            what: "clang's headers (read by bindgen's libclang)",
            present: clang_headers_present,
            debian: &["libclang-common-14-dev"],
            full_only: false,
        },
        Need {
            what: "libtbb12 (ecos, a third-party FMI master the tests run our FMUs in)",
            present: || library_present(&["libtbb.so.12"]),
            debian: &["libtbb12"],
            full_only: true,
        },
    ]
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// Checks every prerequisite; installs the missing ones where it may (root with apt-get), or
/// returns one message naming what is missing and the command that installs it.
pub fn ensure(full: bool) -> Result<(), String> {
    let mut missing_components = vec![];
    for (component, probe) in [("rustfmt", "fmt"), ("clippy", "clippy")] {
        if !runs(
            &std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()),
            &[probe, "--version"],
        ) {
            missing_components.push(component);
        }
    }
    if !missing_components.is_empty() {
        let mut cmd = Command::new("rustup");
        cmd.args(["component", "add"]).args(&missing_components);
        eprintln!(
            "==> prerequisites: rustup component add {}",
            missing_components.join(" ")
        );
        if !cmd.status().is_ok_and(|s| s.success()) {
            return Err(format!(
                "missing Rust components {}: install them with `rustup component add {}`",
                missing_components.join(", "),
                missing_components.join(" ")
            ));
        }
    }
    let missing: Vec<Need> = needs()
        .into_iter()
        .filter(|n| (full || !n.full_only) && !(n.present)())
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let mut packages: Vec<&str> = missing
        .iter()
        .flat_map(|n| n.debian.iter().copied())
        .collect();
    packages.dedup();
    let list = missing
        .iter()
        .map(|n| format!("  - {}", n.what))
        .collect::<Vec<_>>()
        .join("\n");
    let apt = runs("apt-get", &["--version"]);
    if apt && is_root() {
        eprintln!(
            "==> prerequisites: installing {} (missing:\n{list})",
            packages.join(" ")
        );
        let update = Command::new("apt-get").args(["update", "-q"]).status();
        let install = Command::new("apt-get")
            .args(["install", "-y", "-q", "--no-install-recommends"])
            .args(&packages)
            .env("DEBIAN_FRONTEND", "noninteractive")
            .status();
        let still: Vec<&str> = needs()
            .into_iter()
            .filter(|n| (full || !n.full_only) && !(n.present)())
            .map(|n| n.what)
            .collect();
        if update.is_ok_and(|s| s.success())
            && install.is_ok_and(|s| s.success())
            && still.is_empty()
        {
            return Ok(());
        }
        return Err(format!(
            "apt-get could not install {} (still missing: {})",
            packages.join(" "),
            still.join("; ")
        ));
    }
    let how = if apt {
        format!(
            "sudo apt-get install --no-install-recommends {}",
            packages.join(" ")
        )
    } else {
        format!(
            "your system's packages for the above (Debian/Ubuntu names: {})",
            packages.join(" ")
        )
    };
    Err(format!(
        "the tests need what this machine lacks:\n{list}\ninstall it with:\n  {how}\n(then run \
         `cargo xtask test` again; run as root on Debian/Ubuntu it installs them itself)"
    ))
}
