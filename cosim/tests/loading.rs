//! Loading a system's FMUs (`cosim::slave::LoadedFmus`): one file named by several instances is
//! unpacked and opened once, unless its description asks for one instance per process. Needs the
//! packed test FMU (`cargo xtask fmus`).

mod common;

use common::{fmu_dir, tmp};
use cosim::slave::{Fmu, LoadedFmus};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The folder an FMU was unpacked into.
fn unpacked_dir(fmu: &Fmu) -> PathBuf {
    match fmu {
        Fmu::V2(f) => f.dir.clone(),
        Fmu::V3(f) => f.dir.clone(),
    }
}

/// A copy of `src` (an .fmu) whose modelDescription.xml says canBeInstantiatedOnlyOncePerProcess.
fn once_per_process_copy(src: &Path, dst: &Path) {
    let mut archive = zip::ZipArchive::new(std::fs::File::open(src).unwrap()).unwrap();
    let mut out = zip::ZipWriter::new(std::fs::File::create(dst).unwrap());
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).unwrap();
        let name = entry.name().to_string();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        if name == "modelDescription.xml" {
            let xml = String::from_utf8(bytes).unwrap();
            let flag = r#"canBeInstantiatedOnlyOncePerProcess="false""#;
            assert!(xml.contains(flag), "the test FMU declares the flag false");
            bytes = xml
                .replace(flag, r#"canBeInstantiatedOnlyOncePerProcess="true""#)
                .into_bytes();
        }
        if entry.is_dir() {
            out.add_directory(name, zip::write::SimpleFileOptions::default())
                .unwrap();
        } else {
            out.start_file(name, zip::write::SimpleFileOptions::default())
                .unwrap();
            out.write_all(&bytes).unwrap();
        }
    }
    out.finish().unwrap();
}

#[test]
fn one_file_named_twice_is_loaded_once() {
    let path = fmu_dir().join("oscillator.fmu");
    let mut loaded = LoadedFmus::default();
    let a = loaded.get(&path).unwrap();
    let b = loaded.get(&path).unwrap();
    assert!(
        Arc::ptr_eq(&a, &b),
        "the second instance shares the first's FMU"
    );
    // Another spelling of the same file is the same FMU.
    let dotted = fmu_dir().join(".").join("oscillator.fmu");
    assert!(Arc::ptr_eq(&a, &loaded.get(&dotted).unwrap()));
    assert!(!a.description().can_be_instantiated_only_once_per_process);
    // Two instances of the one library, each with its own state.
    let log: fmi_core::LogHandler = Arc::new(|_: &fmi_core::LogRecord| {});
    let s1 = a.instantiate("a", false, log.clone()).unwrap();
    let s2 = b.instantiate("b", false, log).unwrap();
    let x0 = a.description().variable("x0").unwrap().vr;
    let x = a.description().variable("x").unwrap().vr;
    for (s, x_start) in [(&s1, 1.0), (&s2, -2.0)] {
        s.setup_experiment(None, 0.0, Some(1.0)).unwrap();
        s.enter_initialization_mode().unwrap();
        s.set_real(&[x0], &[x_start]).unwrap();
        s.exit_initialization_mode().unwrap();
    }
    let (mut x1, mut x2) = ([0.0], [0.0]);
    s1.get_real(&[x], &mut x1).unwrap();
    s2.get_real(&[x], &mut x2).unwrap();
    assert_eq!((x1, x2), ([1.0], [-2.0]));
}

#[test]
fn an_fmu_instantiated_once_per_process_gets_a_copy_per_instance() {
    let dir = tmp("loading_once_per_process");
    let path = dir.join("oscillator_once.fmu");
    once_per_process_copy(&fmu_dir().join("oscillator.fmu"), &path);
    let mut loaded = LoadedFmus::default();
    let a = loaded.get(&path).unwrap();
    let b = loaded.get(&path).unwrap();
    assert!(a.description().can_be_instantiated_only_once_per_process);
    assert!(!Arc::ptr_eq(&a, &b), "each instance has an FMU of its own");
    assert_ne!(
        unpacked_dir(&a),
        unpacked_dir(&b),
        "each copy is unpacked apart, so each has a library image of its own"
    );
}
