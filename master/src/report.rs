//! `report.html`: one page per run folder and per sweep folder that shows what happened, readable
//! in any browser without a network: the figures are inlined (their SVG text), the data files are
//! linked relatively. Written whenever `summary.json` is (also for failed and interrupted runs) and
//! at the end of every sweep and merge. The page is well-formed XHTML (tests parse it as XML).

use crate::summary::RunSummary;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Escapes text for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A file name or relative path as a link target (each component percent-encoded where needed).
pub(crate) fn href(rel: &str) -> String {
    let mut out = String::new();
    for b in rel.bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'/' | b'~' => {
                out.push(b as char)
            }
            _ => {
                let _ = write!(out, "%{b:02X}");
            }
        }
    }
    out
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1000px;margin:2em auto;padding:0 1em;\
color:#222}table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;\
text-align:left;font-size:90%}th{background:#f0f0f0}.figure{margin:1.5em 0}.figure svg{max-width:100%;\
height:auto}.class{font-size:130%;font-weight:bold}.note{color:#a33}code{background:#f4f4f4}";

pub(crate) fn page(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>\n\
         <meta charset=\"utf-8\"/>\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n{body}\
         </body>\n</html>\n",
        escape(title)
    )
}

/// The SVG text of a figure file, without its XML declaration, to inline in the page.
pub(crate) fn inline_svg(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    let start = text.find("<svg")?;
    Some(text[start..].to_string())
}

pub(crate) fn fmt_opt(v: Option<f64>, digits: usize, unit: &str) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.digits$}{unit}"))
}

/// A table of a JSON object's entries (nested objects flattened with dots).
fn settings_rows(v: &serde_json::Value, prefix: &str, out: &mut String) {
    match v {
        serde_json::Value::Object(map) => {
            for (k, v) in map {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                settings_rows(v, &key, out);
            }
        }
        other => {
            let text = match other {
                serde_json::Value::String(s) => s.clone(),
                o => o.to_string(),
            };
            let _ = writeln!(
                out,
                "<tr><td><code>{}</code></td><td>{}</td></tr>",
                escape(prefix),
                escape(&text)
            );
        }
    }
}

/// Writes `dir/report.html` for the run whose summary is `s`.
pub fn write_run_report(dir: &Path, s: &RunSummary) -> Result<PathBuf, String> {
    let name = dir.file_name().map_or_else(
        || dir.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let mut b = String::new();
    let _ = writeln!(b, "<h1>Run {}</h1>", escape(&name));
    let _ = writeln!(
        b,
        "<p>Status: <b>{}</b>{}</p>",
        s.status.as_str(),
        s.t_end_s
            .map(|t| format!(", simulated to t = {t:.4} s"))
            .unwrap_or_default()
    );
    if let Some(e) = &s.error {
        let _ = writeln!(b, "<p class=\"note\">Error: {}</p>", escape(e));
    }
    let _ = writeln!(b, "<h2>Result</h2>");
    let _ = writeln!(
        b,
        "<p class=\"class\">Classification: {}</p>",
        escape(
            s.classification
                .as_deref()
                .unwrap_or("none (no run-up analysis)")
        )
    );
    if let Some(n) = &s.classification_note {
        let _ = writeln!(b, "<p class=\"note\">{}</p>", escape(n));
    }
    b.push_str("<table>\n");
    let mut rows = vec![
        ("onset time", fmt_opt(s.onset_time_s, 4, " s")),
        ("onset speed", fmt_opt(s.onset_speed_hz, 0, " Hz")),
        (
            "first bearing",
            s.first_bearing.clone().unwrap_or_else(|| "-".into()),
        ),
        ("max eccentricity C (|dr| / C)", fmt_opt(s.max_eps_c, 4, "")),
        ("max eccentricity T (|dr| / C)", fmt_opt(s.max_eps_t, 4, "")),
        (
            "clearance C / T",
            s.clearance_um
                .map_or("-".into(), |c| format!("{} um / {} um", c.c, c.t)),
        ),
        ("wall time", fmt_opt(s.wall_time_s, 1, " s")),
        (
            "macro steps (retried)",
            match (s.macro_steps, s.retried_macro_steps) {
                (Some(n), Some(r)) => format!("{n} ({r})"),
                _ => "-".into(),
            },
        ),
    ];
    if let Some(h) = &s.hysteresis {
        rows.push((
            "whirl stops (coming down)",
            match (h.whirl_stop_speed_hz, h.persists_to_end) {
                (Some(f), _) => format!("{f:.0} Hz at {:.4} s", h.whirl_stop_time_s.unwrap_or(0.0)),
                (None, true) => "persists to the end of the run".into(),
                (None, false) => "-".into(),
            },
        ));
        rows.push(("run-down from", format!("{:.4} s", h.run_down_from_s)));
    }
    for (k, v) in rows {
        let _ = writeln!(b, "<tr><th>{}</th><td>{}</td></tr>", escape(k), escape(&v));
    }
    b.push_str("</table>\n");
    if s.borderline == Some(true) {
        let _ = writeln!(
            b,
            "<p class=\"note\">Borderline: a criterion that decided the class lies within 10 % of \
             its bound; a slightly different run may fall into the neighbouring class.</p>"
        );
    }
    if let Some(margins) = s.margins.as_ref().filter(|m| !m.is_empty()) {
        b.push_str("<table>\n<tr><th>criterion</th><th>value</th><th>bound</th><th>margin</th><th>decides the class</th></tr>\n");
        for c in margins {
            let _ = writeln!(
                b,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&c.name),
                fmt_opt(c.value, 4, ""),
                c.bound,
                c.margin
                    .map_or("-".into(), |m| format!("{:+.1} %", 100.0 * m)),
                if c.deciding { "yes" } else { "no" }
            );
        }
        b.push_str("</table>\n");
    }
    if let Some(c) = &s.criteria {
        let _ = writeln!(b, "<p>Criteria: {}</p>", escape(c));
    }
    if let Some(p) = &s.power_loss_w {
        b.push_str("<h2>Friction power loss of the air films</h2>\n<table>\n");
        b.push_str("<tr><th>speed [Hz]</th><th>bearing C [W]</th><th>bearing T [W]</th><th>both [W]</th></tr>\n");
        for a in p.at_speeds.iter().chain(std::iter::once(&p.max)) {
            let _ = writeln!(
                b,
                "<tr><td>{:.0}{}</td><td>{:.3}</td><td>{:.3}</td><td>{:.3}</td></tr>",
                a.speed_hz,
                if std::ptr::eq(a, &p.max) {
                    " (maximum)"
                } else {
                    ""
                },
                a.c_w,
                a.t_w,
                a.total_w
            );
        }
        let _ = writeln!(
            b,
            "</table>\n<p>At the quoted speeds: means over {} ms where the run-up passes them.</p>",
            p.window_s * 1e3
        );
    }
    let figures: Vec<&String> = s
        .plots
        .iter()
        .flatten()
        .filter(|f| f.ends_with(".svg"))
        .collect();
    if !figures.is_empty() {
        b.push_str("<h2>Figures</h2>\n");
        for f in figures {
            if let Some(svg) = inline_svg(&dir.join(f)) {
                let png = f.trim_end_matches(".svg").to_string() + ".png";
                let _ = writeln!(
                    b,
                    "<div class=\"figure\">{svg}<p><a href=\"{}\">{}</a> · <a href=\"{}\">{}</a></p></div>",
                    href(f),
                    escape(f),
                    href(&png),
                    escape(&png)
                );
            }
        }
    }
    if let Some(e) = &s.plot_error {
        let _ = writeln!(b, "<p class=\"note\">Figures: {}</p>", escape(e));
    }
    b.push_str("<h2>Settings</h2>\n<table>\n");
    settings_rows(&s.settings, "", &mut b);
    b.push_str("</table>\n<h2>Files</h2>\n<ul>\n");
    for f in [
        "timeseries.csv",
        "timeseries.parquet",
        "summary.json",
        "system.toml",
        "runup.log",
    ] {
        if dir.join(f).is_file() {
            let _ = writeln!(b, "<li><a href=\"{}\">{}</a></li>", href(f), escape(f));
        }
    }
    b.push_str("</ul>\n");
    let path = dir.join("report.html");
    crate::output::write_whole(&path, page(&format!("AirRing run {name}"), &b).as_bytes())?;
    Ok(path)
}

/// `path` relative to `base` when it lies below it, else as it is.
/// `path` as a link from a page in `base`: below it as it is, elsewhere (a merged sweep's runs
/// in the shards' folders) through "..", found from both folders' real locations.
pub(crate) fn relative(path: &Path, base: &Path) -> String {
    if let Ok(below) = path.strip_prefix(base) {
        return below.to_string_lossy().into_owned();
    }
    // The file itself may not exist (a run that wrote no page): its folder does.
    let real = |p: &Path| {
        p.canonicalize().ok().or_else(|| {
            let dir = p.parent()?.canonicalize().ok()?;
            Some(dir.join(p.file_name()?))
        })
    };
    let (Some(p), Some(b)) = (real(path), base.canonicalize().ok()) else {
        return path.to_string_lossy().into_owned();
    };
    let (pc, bc): (Vec<_>, Vec<_>) = (p.components().collect(), b.components().collect());
    let common = pc.iter().zip(&bc).take_while(|(x, y)| x == y).count();
    let mut rel = PathBuf::new();
    for _ in common..bc.len() {
        rel.push("..");
    }
    rel.extend(&pc[common..]);
    rel.to_string_lossy().into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_links_are_escaped() {
        assert_eq!(escape("a<b & \"c\"'"), "a&lt;b &amp; &quot;c&quot;&#39;");
        assert_eq!(href("runs/C15 x/report.html"), "runs/C15%20x/report.html");
        // A merged sweep links the runs in its shards' folders through "..".
        let root = std::env::temp_dir().join(format!("airring-rel-{}", std::process::id()));
        let run = root.join("sh1/runs/c500");
        std::fs::create_dir_all(&run).unwrap();
        std::fs::create_dir_all(root.join("shm")).unwrap();
        assert_eq!(
            relative(&run.join("report.html"), &root.join("shm")),
            "../sh1/runs/c500/report.html"
        );
        assert_eq!(
            relative(&root.join("shm/study.csv"), &root.join("shm")),
            "study.csv"
        );
        let _ = std::fs::remove_dir_all(&root);
        assert_eq!(href("a&b\"<"), "a%26b%22%3C");
    }
}
