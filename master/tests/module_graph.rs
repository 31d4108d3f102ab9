//! The application's modules form a directed graph: no module reaches back into one that uses it
//! (a run-up must not pull in the sweep machinery because the sweep's report page is next to the
//! run's). Read from the sources: every `crate::MODULE` path in a top-level module's files, test
//! code left out (it may cross layers to compare them).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The top-level modules declared in lib.rs.
fn modules() -> Vec<String> {
    let lib = std::fs::read_to_string(src().join("lib.rs")).unwrap();
    lib.lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|m| m.trim_end_matches(';').to_string())
        .collect()
}

/// The files of module `m`: `m.rs`, or everything under `m/`.
fn files_of(m: &str) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut out = vec![];
    let file = src().join(format!("{m}.rs"));
    if file.exists() {
        out.push(file);
    }
    let dir = src().join(m);
    if dir.is_dir() {
        walk(&dir, &mut out);
    }
    out
}

/// The code of a file without its comments and test modules (`#[cfg(test)]` and what follows
/// it; test-only files entirely).
fn non_test_code(path: &Path) -> String {
    let name = path.file_name().unwrap().to_string_lossy();
    if name == "tests.rs" || name.ends_with("_tests.rs") {
        return String::new();
    }
    let text = std::fs::read_to_string(path).unwrap();
    let code = match text.find("#[cfg(test)]") {
        Some(i) => &text[..i],
        None => &text[..],
    };
    // Comments name modules to explain (`crate::calm_steps` in a doc comment): not a use.
    code.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules that `code` names as `crate::NAME`.
fn uses(code: &str, modules: &[String]) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        // Not part of a longer path such as `fmi2::crate::` (there is none) or `the_crate::`.
        if i > 0 {
            let before = code.as_bytes()[i - 1];
            if before.is_ascii_alphanumeric() || before == b'_' {
                continue;
            }
        }
        let rest = &code[i + "crate::".len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if modules.contains(&name) {
            out.insert(name);
        }
    }
    out
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let mods = modules();
    let mut g = BTreeMap::new();
    for m in &mods {
        let mut deps = BTreeSet::new();
        for f in files_of(m) {
            deps.extend(uses(&non_test_code(&f), &mods));
        }
        deps.remove(m);
        g.insert(m.clone(), deps);
    }
    g
}

/// A cycle through the graph, if there is one (as the modules along it).
fn cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for d in &g[n] {
            match state.get(d.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|s| s == d).unwrap();
                    let mut c = stack[start..].to_vec();
                    c.push(d.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(d, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in g.keys() {
        if state.get(n).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, g, &mut state, &mut vec![]) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn the_application_modules_have_no_import_circles() {
    let g = graph();
    assert!(g.len() > 10, "{g:?}");
    if let Some(c) = cycle(&g) {
        panic!("import circle: {}", c.join(" -> "));
    }
    // A run-up does not reach the sweep machinery.
    for m in ["runup", "run", "report", "design", "calm_steps"] {
        assert!(!g[m].contains("sweep"), "{m} uses sweep: {:?}", g[m]);
    }
}

#[test]
fn the_cycle_finder_finds_a_planted_circle() {
    let mut g = BTreeMap::new();
    g.insert("a".to_string(), BTreeSet::from(["b".to_string()]));
    g.insert("b".to_string(), BTreeSet::from(["c".to_string()]));
    g.insert("c".to_string(), BTreeSet::from(["a".to_string()]));
    g.insert("d".to_string(), BTreeSet::new());
    assert_eq!(cycle(&g).unwrap(), ["a", "b", "c", "a"]);
    g.get_mut("c").unwrap().clear();
    assert!(cycle(&g).is_none());
    let mods = vec!["sweep".to_string(), "run".to_string()];
    assert_eq!(
        uses(
            "use crate::sweep::X; the_crate::run; crate::runup::y",
            &mods
        ),
        BTreeSet::from(["sweep".to_string()])
    );
}
