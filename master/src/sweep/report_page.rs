//! A sweep's page, `report.html` in its folder: its maps inline, its table, a link to each run's
//! own page (the run's page and the shared page parts are `crate::report`'s).

use super::RunRecord;
use crate::report::{escape, fmt_opt, href, inline_svg, page, relative};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Writes `out/report.html` for a sweep: its maps inline, its table, a link to each run's page.
pub fn write_sweep_report(
    out: &Path,
    title: &str,
    table: &Path,
    maps: &[PathBuf],
    records: &[RunRecord],
) -> Result<PathBuf, String> {
    let mut b = String::new();
    let _ = writeln!(b, "<h1>Sweep {}</h1>", escape(title));
    let _ = writeln!(
        b,
        "<p>{} runs. Table: <a href=\"{}\">{}</a></p>",
        records.len(),
        href(&relative(table, out)),
        escape(&relative(table, out))
    );
    let svgs: Vec<&PathBuf> = maps
        .iter()
        .filter(|m| m.extension().is_some_and(|e| e == "svg"))
        .collect();
    if !svgs.is_empty() {
        b.push_str("<h2>Bifurcation maps</h2>\n");
        for m in svgs {
            if let Some(svg) = inline_svg(m) {
                let _ = writeln!(
                    b,
                    "<div class=\"figure\">{svg}<p><a href=\"{}\">{}</a></p></div>",
                    href(&relative(m, out)),
                    escape(&relative(m, out))
                );
            }
        }
    }
    b.push_str(
        "<h2>Runs</h2>\n<table>\n<tr><th>run</th><th>status</th><th>class</th>\
                <th>onset [Hz]</th><th>max eps C</th><th>max eps T</th><th>wall [s]</th></tr>\n",
    );
    let mut sorted: Vec<&RunRecord> = records.iter().collect();
    sorted.sort_by_key(|r| r.index);
    for r in sorted {
        let page = r.dir.join("report.html");
        let name = if page.is_file() {
            format!(
                "<a href=\"{}\">{}</a>",
                href(&relative(&page, out)),
                escape(&r.name)
            )
        } else {
            escape(&r.name)
        };
        let _ = writeln!(
            b,
            "<tr><td>{name}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&r.status),
            escape(r.classification.as_deref().unwrap_or("-")),
            fmt_opt(r.onset_speed_hz, 0, ""),
            fmt_opt(r.max_eps_c, 3, ""),
            fmt_opt(r.max_eps_t, 3, ""),
            fmt_opt(r.wall_time_s, 0, "")
        );
    }
    b.push_str("</table>\n");
    let path = out.join("report.html");
    crate::output::write_whole(
        &path,
        page(&format!("AirRing sweep {title}"), &b).as_bytes(),
    )?;
    Ok(path)
}
