//! Helpers of the library's integration tests.

use std::path::{Path, PathBuf};

/// `target/fmu`, which must hold `oscillator.fmu`.
pub fn fmu_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .join("target/fmu");
    assert!(
        d.join("oscillator.fmu").exists(),
        "run `cargo xtask fmus` first"
    );
    d
}

/// A fresh temporary folder for one test.
pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cosim-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
