//! Helpers the application's end-to-end tests share: the workspace root, a fresh temporary
//! folder per test and process, and `airring` run from the root.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// `<temp>/airring-<suite>-<name>-<pid>`, removed if it exists (not created).
pub fn tmp(suite: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("airring-{suite}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `airring ARGS` in the workspace root: (success, stderr).
pub fn airring(args: &[&str]) -> (bool, String) {
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
