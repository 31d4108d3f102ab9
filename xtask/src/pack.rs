//! Building and packing the FMUs, and the generated modelDescription.xml files.

use super::{cargo, root, run, target_dir};
use fmi_core::model::Model;
use fmi_core::variables::ModelInfo;
use std::io::Write;

/// Every FMU we ship or test: (cargo package, library file stem, interface).
fn fmus_table() -> Vec<(&'static str, &'static str, ModelInfo, bool)> {
    vec![
        // (package, lib stem, info, shipped: has a checked-in modelDescriptions/<id>.xml)
        (
            "fmu-airfilm",
            "fmu_airfilm",
            fmu_airfilm::shell::AirFilmFmu::info(),
            true,
        ),
        (
            "fmu-rotor",
            "fmu_rotor",
            fmu_rotor::shell::RotorFmu::info(),
            true,
        ),
        (
            "fmu-oscillator",
            "fmu_oscillator",
            fmu_oscillator::Oscillator::info(),
            false,
        ),
    ]
}

/// `--features` for a clippy run over the export code of every FMU crate.
pub fn features() -> String {
    fmus_table()
        .iter()
        .map(|(pkg, ..)| format!("{pkg}/fmu"))
        .collect::<Vec<_>>()
        .join(",")
}

/// Builds and packs the FMUs. With `glibc = Some("2.17")` the libraries are linked by cargo-zigbuild
/// against that glibc version (`--target x86_64-unknown-linux-gnu.2.17`), so they load on older
/// Linux distributions; see docs/fmu-guide.md, "Portability".
pub fn fmus(glibc: Option<&str>) -> Result<(), String> {
    let table = fmus_table();
    let mut cmd = cargo();
    let lib_dir = match glibc {
        None => {
            cmd.args(["build", "--release", "--lib"]);
            target_dir().join("release")
        }
        Some(v) => {
            let ok = std::process::Command::new("cargo-zigbuild")
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success());
            if !ok {
                return Err(
                    "--glibc needs cargo-zigbuild and zig: `pip install ziglang==0.17.1` and \
                     `cargo install cargo-zigbuild --version 0.24.1 --locked`"
                        .into(),
                );
            }
            cmd.args(["zigbuild", "--release", "--lib", "--target"])
                .arg(format!("x86_64-unknown-linux-gnu.{v}"));
            target_dir().join("x86_64-unknown-linux-gnu/release")
        }
    };
    // One build for all FMUs: no FMU crate links another (the rotor and the air film share
    // the `bearing` library, which exports nothing), so unified features put each crate's
    // fmi2* exports into its own library only. tests/fmu_binaries.rs checks the export lists.
    for (pkg, ..) in &table {
        cmd.args(["-p", pkg]);
    }
    cmd.args(["--features", &features()]);
    run("build FMU binaries", &mut cmd)?;
    let out_dir = target_dir().join("fmu");
    std::fs::create_dir_all(&out_dir).map_err(|e| e.to_string())?;
    for (_, stem, info, _) in &table {
        let so = lib_dir.join(format!("lib{stem}.so"));
        let fmu = out_dir.join(format!("{}.fmu", info.model_identifier));
        pack(info, &so, &fmu, Fmi::V2)?;
        eprintln!("    packed {}", fmu.display());
    }
    // The FMI 3.0 twins: thin cdylibs over the same model crates, built in a second invocation so
    // the model crates come without their fmi2 `fmu` feature (each library exports one version).
    let mut cmd = cargo();
    match glibc {
        None => cmd.args(["build", "--release", "--lib"]),
        Some(v) => cmd
            .args(["zigbuild", "--release", "--lib", "--target"])
            .arg(format!("x86_64-unknown-linux-gnu.{v}")),
    };
    for (pkg, ..) in fmi3_table() {
        cmd.args(["-p", pkg]);
    }
    run("build FMI 3.0 FMU binaries", &mut cmd)?;
    let out_dir = out_dir.join("fmi3");
    std::fs::create_dir_all(&out_dir).map_err(|e| e.to_string())?;
    for (_, stem, info) in fmi3_table() {
        let so = lib_dir.join(format!("lib{stem}.so"));
        let fmu = out_dir.join(format!("{}.fmu", info.model_identifier));
        pack(&info, &so, &fmu, Fmi::V3)?;
        eprintln!("    packed {}", fmu.display());
    }
    Ok(())
}

/// The FMI 3.0 twins: (cargo package, library file stem, interface).
fn fmi3_table() -> Vec<(&'static str, &'static str, ModelInfo)> {
    vec![
        (
            "fmu-airfilm-fmi3",
            "fmu_airfilm_fmi3",
            fmu_airfilm::shell::AirFilmFmu::info(),
        ),
        (
            "fmu-rotor-fmi3",
            "fmu_rotor_fmi3",
            fmu_rotor::shell::RotorFmu::info(),
        ),
    ]
}

#[derive(Clone, Copy, PartialEq)]
enum Fmi {
    V2,
    V3,
}

fn pack(
    info: &ModelInfo,
    so: &std::path::Path,
    fmu: &std::path::Path,
    version: Fmi,
) -> Result<(), String> {
    let binary = shipped_binary(so)?;
    let file = std::fs::File::create(fmu).map_err(|e| format!("{}: {e}", fmu.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    let (description, platform) = match version {
        Fmi::V2 => (fmi2::xml::model_description(info), "linux64"),
        Fmi::V3 => (fmi3::xml::model_description(info), "x86_64-linux"),
    };
    let mut entries: Vec<(String, Vec<u8>)> = vec![
        ("modelDescription.xml".into(), description.into_bytes()),
        (
            format!("binaries/{platform}/{}.so", info.model_identifier),
            binary,
        ),
        (
            "documentation/index.html".into(),
            fmi2::xml::documentation(info).into_bytes(),
        ),
    ];
    // Reference results in the FMI Cross-Check layout (scripts/make_reference_results.py); they
    // were made with the FMI 2.0 FMUs, and FMPy simulates the FMI 3.0 twins to the same numbers
    // (tests/python/test_reference_results.py checks both).
    let reference = root()
        .join("modelDescriptions/reference")
        .join(info.model_identifier);
    if let Ok(dir) = std::fs::read_dir(&reference) {
        let mut files: Vec<std::path::PathBuf> = dir.flatten().map(|e| e.path()).collect();
        files.sort();
        for f in files.into_iter().filter(|f| f.is_file()) {
            let name = f
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            let data = std::fs::read(&f).map_err(|e| format!("{}: {e}", f.display()))?;
            entries.push((format!("documentation/reference/{name}"), data));
        }
    }
    for (name, data) in entries {
        zip.start_file(name, opts).map_err(|e| e.to_string())?;
        zip.write_all(&data).map_err(|e| e.to_string())?;
    }
    zip.finish().map_err(|e| e.to_string())?;
    Ok(())
}

/// The library as an FMU ships it: without its debug sections (`objcopy --strip-debug`; the
/// symbol tables stay, so exports, panic messages and profiles keep their names). The release
/// profile's line tables are for profiling the libraries in target/; in an FMU they were 11.7 of
/// rotor.so's 12.7 MB, and every importer decompresses the whole library on every load (in a
/// path-1 run-up ~85 ms of the master's 145 ms before the first step, for three FMUs). Without
/// `objcopy` the library is packed as built, with a warning.
fn shipped_binary(so: &std::path::Path) -> Result<Vec<u8>, String> {
    let stripped = so.with_extension("stripped.so");
    let status = std::process::Command::new("objcopy")
        .arg("--strip-debug")
        .arg(so)
        .arg(&stripped)
        .status();
    let binary = match status {
        Ok(s) if s.success() => std::fs::read(&stripped),
        Ok(s) => {
            return Err(format!(
                "objcopy --strip-debug {} failed ({s})",
                so.display()
            ))
        }
        Err(e) => {
            eprintln!(
                "warning: objcopy not found ({e}): {} is packed with its debug sections",
                so.display()
            );
            std::fs::read(so)
        }
    };
    let _ = std::fs::remove_file(&stripped);
    binary.map_err(|e| format!("{}: {e}", so.display()))
}

/// Writes (or with `check`, compares) `modelDescriptions/<id>.xml` for the shipped FMUs, and
/// `modelDescriptions/fmi3/<id>.xml` for their FMI 3.0 twins.
pub fn descriptions(check: bool) -> Result<(), String> {
    let dir = root().join("modelDescriptions");
    let v2 = fmus_table()
        .into_iter()
        .filter(|t| t.3)
        .map(|(_, _, info, _)| {
            (
                dir.join(format!("{}.xml", info.model_identifier)),
                fmi2::xml::model_description(&info),
            )
        });
    let v3 = fmi3_table().into_iter().map(|(_, _, info)| {
        (
            dir.join("fmi3")
                .join(format!("{}.xml", info.model_identifier)),
            fmi3::xml::model_description(&info),
        )
    });
    for (path, xml) in v2.chain(v3) {
        if check {
            let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
            if on_disk != xml {
                return Err(format!(
                    "{} is not what the code generates: run `cargo xtask descriptions`",
                    path.display()
                ));
            }
        } else {
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
            }
            std::fs::write(&path, xml).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!("    wrote {}", path.display());
        }
    }
    Ok(())
}
