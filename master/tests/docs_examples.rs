//! The files the user documentation shows are files AirRing reads: every TOML example of a
//! design, a study and a system file in docs/ parses with the parser it documents (a format
//! change that leaves the docs behind fails here).

use std::path::{Path, PathBuf};

fn docs() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs")
}

/// The ```toml blocks of a page, in order.
fn toml_blocks(page: &str) -> Vec<String> {
    let text = std::fs::read_to_string(docs().join(page)).unwrap();
    let mut out = vec![];
    let mut rest = text.as_str();
    while let Some(i) = rest.find("```toml\n") {
        let body = &rest[i + 8..];
        let end = body.find("```").unwrap();
        out.push(body[..end].to_string());
        rest = &body[end + 3..];
    }
    out
}

#[test]
fn the_design_file_examples_parse() {
    for page in ["design.md", "reference/design-file.md"] {
        let blocks = toml_blocks(page);
        assert!(!blocks.is_empty(), "{page}: no TOML example");
        let d = master::design::Design::parse(&blocks[0]).unwrap_or_else(|e| panic!("{page}: {e}"));
        assert!(
            d.sources.iter().any(|s| s.starts_with("[bearing.turbine]")),
            "{page}: {:?}",
            d.sources
        );
    }
}

#[test]
fn the_study_file_examples_parse() {
    let path = docs().join("example.toml");
    for (page, k) in [
        ("reference/study-file.md", 0),
        ("tutorial.md", 0),
        ("design.md", 1),
    ] {
        let block = &toml_blocks(page)[k];
        if block.contains("design = [") {
            // Names design files of the user's own; the keys themselves must still be known.
            let t: toml::Table = block.parse().unwrap_or_else(|e| panic!("{page}: {e}"));
            assert!(t.contains_key("grid"), "{page}");
            continue;
        }
        master::sweep::Study::parse(block, &path).unwrap_or_else(|e| panic!("{page}: {e}"));
    }
}

#[test]
fn the_system_file_example_parses() {
    let block = &toml_blocks("reference/system-file.md")[0];
    let dir = std::env::temp_dir().join(format!("airring-docs-system-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("system.toml");
    std::fs::write(&path, block).unwrap();
    let sys = cosim::System::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sys.file.fmu.len(), 2);
    let _ = std::fs::remove_dir_all(&dir);
}
