//! The packed binaries: exactly the 34 fmi2* symbols (the FMI 3.0 twins: exactly the 75 fmi3*
//! ones), no unexpected shared-library dependencies, and the GLIBC symbol versions they need
//! (printed for the docs).

use integration_tests::fmu_path;
use std::collections::BTreeSet;
use std::process::Command;

pub const FMUS: &[&str] = &["oscillator", "airfilm", "rotor"];

const FMI2_FUNCTIONS: [&str; 34] = [
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

/// The FMU's binary, unpacked into a temporary folder that is removed on drop.
struct Unpacked(
    #[allow(dead_code)] fmi2::importer::UnpackedDir,
    std::path::PathBuf,
);

/// The FMI 3.0 twins, as `fmi3/<id>` under target/fmu.
pub const FMI3_FMUS: &[&str] = &["fmi3/airfilm", "fmi3/rotor"];

fn unpacked_so(id: &str) -> Unpacked {
    let dir = fmi2::importer::unpack(&fmu_path(id)).unwrap();
    let so = match id.strip_prefix("fmi3/") {
        Some(stem) => dir.path().join(format!("binaries/x86_64-linux/{stem}.so")),
        None => dir.path().join(format!("binaries/linux64/{id}.so")),
    };
    Unpacked(dir, so)
}

fn exported(so: &std::path::Path) -> BTreeSet<String> {
    let nm = tool("nm", &["-D", "--defined-only"], so);
    nm.lines()
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            let (_addr, kind, name) = (it.next()?, it.next()?, it.next()?);
            // Text (code) and data symbols; absolute version nodes are not symbols we export.
            matches!(kind, "T" | "D" | "B" | "R" | "W" | "V").then(|| name.to_string())
        })
        .collect()
}

#[test]
fn the_fmi3_twins_export_exactly_the_fmi3_functions() {
    let expected: BTreeSet<String> = fmi3::FUNCTIONS.iter().map(|s| s.to_string()).collect();
    assert_eq!(expected.len(), 75);
    for id in FMI3_FMUS {
        let so = unpacked_so(id);
        assert_eq!(exported(&so.1), expected, "{id}: exported symbols");
    }
}

fn tool(cmd: &str, args: &[&str], so: &std::path::Path) -> String {
    let out = Command::new(cmd)
        .args(args)
        .arg(so)
        .output()
        .unwrap_or_else(|e| panic!("{cmd} is needed (binutils): {e}"));
    assert!(
        out.status.success(),
        "{cmd} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn only_fmi2_symbols_are_exported() {
    for id in FMUS {
        let so = unpacked_so(id);
        let expected: BTreeSet<String> = FMI2_FUNCTIONS.iter().map(|s| s.to_string()).collect();
        assert_eq!(exported(&so.1), expected, "{id}: exported symbols");
    }
}

#[test]
fn depends_only_on_the_c_runtime() {
    let allowed = [
        "linux-vdso",
        "libc.so",
        "libm.so",
        "libgcc_s.so",
        "ld-linux",
        "libdl.so",
        "libpthread.so",
        "librt.so",
    ];
    for id in FMUS.iter().chain(FMI3_FMUS) {
        let so = unpacked_so(id);
        let ldd = tool("ldd", &[], &so.1);
        for line in ldd.lines().map(str::trim).filter(|l| !l.is_empty()) {
            assert!(
                allowed.iter().any(|a| line.contains(a)),
                "{id}: unexpected dependency '{line}'"
            );
        }
        let objdump = tool("objdump", &["-T"], &so.1);
        let max_glibc = objdump
            .split_whitespace()
            .filter_map(|w| w.trim_start_matches('(').strip_prefix("GLIBC_"))
            .filter_map(|v| {
                let mut p = v
                    .split('.')
                    .map(|x| x.trim_end_matches(')').parse::<u32>().unwrap_or(0));
                Some((p.next()?, p.next().unwrap_or(0), p.next().unwrap_or(0)))
            })
            .max()
            .unwrap();
        println!(
            "{id}.so needs GLIBC {}.{}.{}",
            max_glibc.0, max_glibc.1, max_glibc.2
        );
        // The table in docs/fmu-guide.md, "Portability": a change that needs a newer glibc must
        // update it (2.35 natively on Debian 12; 2.14 with `cargo xtask fmus --glibc 2.17`).
        assert!(
            max_glibc <= (2, 35, 0),
            "{id}.so needs GLIBC {max_glibc:?}, newer than docs/fmu-guide.md states"
        );
    }
}
