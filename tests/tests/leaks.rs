//! Loading and unloading an FMU's library loses no memory: a master that loads an FMU per run
//! (or per study cell) for hours must not grow. A small C host (as any FMI master in C) loads
//! each packed library twice, instantiates and frees an instance, unloads it, under valgrind's
//! leak check. (rotor.so once lost 3 664 bytes per load: the speed-table names built at run time
//! and leaked for `&'static str`.) Skipped, with a message, where valgrind or cc is missing.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

const HOST: &str = r#"
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
typedef void *(*inst_t)(const char *, int, const char *, const char *, const void *, int, int);
typedef void (*free_t)(void *);
static void logger(void *env, const char *name, int status, const char *cat, const char *msg, ...) {
    (void)env; (void)name; (void)status; (void)cat; (void)msg;
}
static void *alloc(size_t n, size_t s) { return calloc(n, s); }
struct callbacks {
    void (*logger)(void *, const char *, int, const char *, const char *, ...);
    void *(*alloc)(size_t, size_t);
    void (*free)(void *);
    void (*step_finished)(void *, int);
    void *env;
};
int main(int argc, char **argv) {
    struct callbacks cb = {logger, alloc, free, NULL, NULL};
    if (argc < 4) return 1;
    for (int k = 0; k < 2; k++) {
        void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
        if (!lib) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 2; }
        inst_t inst = (inst_t)dlsym(lib, "fmi2Instantiate");
        free_t fr = (free_t)dlsym(lib, "fmi2FreeInstance");
        void *c = inst(argv[3], 1, argv[2], "file:///tmp", &cb, 0, 0);
        if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 3; }
        fr(c);
        dlclose(lib);
    }
    puts("loaded and unloaded twice");
    return 0;
}
"#;

fn tool(name: &str) -> bool {
    Command::new(name)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The FMU's library and GUID, unpacked into `dir`.
fn unpack(fmu: &Path, dir: &Path, stem: &str) -> (PathBuf, String) {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .unwrap()
        .read_to_string(&mut xml)
        .unwrap();
    let guid = xml
        .split("guid=\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .unwrap()
        .to_string();
    let mut lib = vec![];
    zip.by_name(&format!("binaries/linux64/{stem}.so"))
        .unwrap()
        .read_to_end(&mut lib)
        .unwrap();
    let path = dir.join(format!("{stem}.so"));
    std::fs::write(&path, lib).unwrap();
    (path, guid)
}

#[test]
fn loading_and_unloading_the_fmus_loses_no_memory() {
    if !(tool("valgrind") && tool("cc")) {
        eprintln!("SKIPPED: valgrind or cc is not installed");
        return;
    }
    let root = integration_tests::workspace_root();
    let dir = std::env::temp_dir().join(format!("airring-leaks-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let c = dir.join("host.c");
    std::fs::write(&c, HOST).unwrap();
    let host = dir.join("host");
    let built = Command::new("cc")
        .args(["-O1", "-o"])
        .arg(&host)
        .arg(&c)
        .arg("-ldl")
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    for stem in ["rotor", "airfilm"] {
        let fmu = root.join(format!("target/fmu/{stem}.fmu"));
        assert!(fmu.exists(), "run `cargo xtask fmus` first");
        let (lib, guid) = unpack(&fmu, &dir, stem);
        let out = Command::new("valgrind")
            .args([
                "--leak-check=full",
                "--errors-for-leak-kinds=definite,indirect",
            ])
            .arg("--error-exitcode=9")
            .arg(&host)
            .arg(&lib)
            .arg(&guid)
            .arg(stem)
            .output()
            .unwrap();
        let report = String::from_utf8_lossy(&out.stderr);
        assert!(
            String::from_utf8_lossy(&out.stdout).contains("loaded and unloaded twice"),
            "{stem}: {report}"
        );
        let lost = |kind: &str| {
            report
                .lines()
                .find(|l| l.contains(&format!("{kind} lost:")))
                .and_then(|l| l.split(&format!("{kind} lost:")).nth(1))
                .and_then(|r| r.split_whitespace().next())
                .map_or(0, |n| n.replace(',', "").parse::<u64>().unwrap())
        };
        assert_eq!(lost("definitely"), 0, "{stem}: {report}");
        assert_eq!(lost("indirectly"), 0, "{stem}: {report}");
        assert!(out.status.success(), "{stem}: {report}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
