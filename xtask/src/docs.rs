//! The user documentation's checks and its generated part.
//!
//! - `cargo xtask cli-reference [--check]`: docs/reference/cli.md from the `airring` binary's own
//!   help (every subcommand's `--help`, which clap generates from the flag definitions), so the
//!   reference cannot drift from the flags; `--check` compares instead of writing.
//! - `cargo xtask docs-check`: the reference is current, every relative Markdown link in the
//!   documentation resolves, and no page but docs/archive.md keeps a dated change log (the word
//!   "session" or a date): docs say what is, git history says how it came to be.

use crate::{cargo, root, run, target_dir};
use std::path::{Path, PathBuf};
use std::process::Command;

const CLI_MD: &str = "docs/reference/cli.md";

/// Builds the debug `airring` and returns its path.
fn airring() -> Result<PathBuf, String> {
    run(
        "build airring",
        cargo().args(["build", "-p", "master", "--bin", "airring"]),
    )?;
    Ok(target_dir().join("debug/airring"))
}

fn help(exe: &Path, args: &[&str]) -> Result<String, String> {
    let out = Command::new(exe)
        .args(args)
        .arg("--help")
        .env("COLUMNS", "100")
        .output()
        .map_err(|e| format!("{}: {e}", exe.display()))?;
    if !out.status.success() {
        return Err(format!(
            "airring {} --help failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim_end().to_string())
}

/// The subcommands listed under "Commands:" in the top-level help (without `help`).
fn subcommands(top: &str) -> Vec<String> {
    top.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect()
}

/// The reference page: the top-level help, then each subcommand's.
pub fn cli_markdown(exe: &Path) -> Result<String, String> {
    let top = help(exe, &[])?;
    let mut md = String::from(
        "# Command-line reference\n\n\
         Generated from the `airring` binary's own help by `cargo xtask cli-reference`; \
         `cargo xtask docs-check` (part of `cargo xtask test`) fails when it differs from the \
         flags. Units are in each flag's text.\n\n",
    );
    let commands = subcommands(&top);
    md.push_str("## airring\n\n```text\n");
    md.push_str(&top);
    md.push_str("\n```\n\n");
    for c in &commands {
        md.push_str(&format!("## airring {c}\n\n```text\n"));
        md.push_str(&help(exe, &[c])?);
        md.push_str("\n```\n\n");
    }
    if commands.is_empty() {
        return Err("no subcommands found under 'Commands:' in `airring --help`".into());
    }
    Ok(md)
}

/// `cargo xtask cli-reference [--check]`.
pub fn cli_reference(check: bool) -> Result<(), String> {
    let md = cli_markdown(&airring()?)?;
    let path = root().join(CLI_MD);
    if check {
        let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
        if on_disk != md {
            return Err(format!(
                "{CLI_MD} differs from the binary's help: run `cargo xtask cli-reference`"
            ));
        }
        return Ok(());
    }
    std::fs::create_dir_all(path.parent().expect("docs/reference")).map_err(|e| e.to_string())?;
    std::fs::write(&path, md).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {CLI_MD}");
    Ok(())
}

/// The Markdown files the documentation consists of.
fn markdown_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p);
            }
        }
    }
    let r = root();
    let mut out = vec![];
    walk(&r.join("docs"), &mut out);
    for f in [
        "README.md",
        "ARCHITECTURE.md",
        "fmu-airfilm/BENCHMARKS.md",
        "fmu-rotor/BENCHMARKS.md",
        "master/BENCHMARKS.md",
        "fmu-rotor/MODAL.md",
    ] {
        if r.join(f).exists() {
            out.push(r.join(f));
        }
    }
    out.sort();
    out
}

/// Relative link targets in `text` (`](target)`, without `#anchor`; web and mail links left out).
fn link_targets(text: &str) -> Vec<String> {
    let mut out = vec![];
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].trim();
        let target = target.split('#').next().unwrap_or("");
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            out.push(target.to_string());
        }
    }
    out
}

/// A date written YYYY-MM-DD in `line`.
fn has_date(line: &str) -> bool {
    let b = line.as_bytes();
    b.windows(10).any(|w| {
        w.iter().enumerate().all(|(k, c)| match k {
            4 | 7 => *c == b'-',
            _ => c.is_ascii_digit(),
        }) && w[0] == b'2'
    })
}

/// `cargo xtask docs-check`.
pub fn check() -> Result<(), String> {
    let r = root();
    let mut problems = vec![];
    for file in markdown_files() {
        let text =
            std::fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        let rel = file.strip_prefix(&r).unwrap_or(&file).display().to_string();
        for target in link_targets(&text) {
            let resolved = file.parent().expect("a folder").join(&target);
            if !resolved.exists() {
                problems.push(format!("{rel}: link to {target}: no such file"));
            }
        }
        if rel == "docs/archive.md" {
            continue;
        }
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            if lower.contains("session") || has_date(line) {
                problems.push(format!(
                    "{rel}:{}: a change log in the present-tense docs (\"session\" or a date; \
                     history goes to git or docs/archive.md): {}",
                    n + 1,
                    line.trim()
                ));
            }
        }
    }
    if let Err(e) = cli_reference(true) {
        problems.push(e);
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!("docs-check:\n  {}", problems.join("\n  ")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_dates_and_subcommands_are_found() {
        assert_eq!(
            link_targets("see [a](docs/a.md#x), [w](https://x.org) and [b](../b.md)"),
            ["docs/a.md", "../b.md"]
        );
        assert!(has_date("since 2026-12-04 the default"));
        assert!(!has_date("a mesh of 10x2, tolerance 6e-4"));
        let top =
            "Usage: airring <COMMAND>\n\nCommands:\n  runup  A run-up\n          more text\n  \
                   sweep  A study\n  help   Print this\n\nOptions:\n  -h, --help  Print help";
        assert_eq!(subcommands(top), ["runup", "sweep"]);
    }
}
