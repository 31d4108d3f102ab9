//! Bifurcation maps as the paper's Fig. 17, laid out as a `plot::Scene` (SVG + PNG), text measured
//! with the embedded font.

use super::study::{keys_in, short_and_unit, Params, NUMERICS};
use super::{RunRecord, Study};
use crate::plot::font::text_width_px;
use crate::plot::{Anchor, Figure, Rgb, Scene};
use std::path::{Path, PathBuf};

/// Run-up classes, their names in the legend and their (shorter) labels in a map cell.
const CLASS_NAMES: &[(&str, &str, &str)] = &[
    ("stable", "stable", "stable"),
    ("path1", "path 1", "path 1"),
    ("path2a", "path 2a", "path 2a"),
    ("path2b", "path 2b", "path 2b"),
    ("unstable_low_speed", "unstable low", "unst.low"),
    ("unstable_linear", "lin. unst.", "lin. unst."),
    ("too_short", "too short", "too short"),
];

fn legend_color(name: &str) -> Rgb {
    LEGEND
        .iter()
        .find(|e| e.0 == name)
        .map_or(Rgb(240, 240, 240), |e| e.1)
}

/// What a map cell shows: its fill and a short label.
fn cell_style(r: &RunRecord) -> (Rgb, String) {
    let class = r
        .classification
        .as_deref()
        .and_then(|c| CLASS_NAMES.iter().find(|e| e.0 == c));
    if r.status == "completed" {
        // A borderline class carries a marker (explained under the legend).
        let mark = if r.borderline == Some(true) { " *" } else { "" };
        return match class {
            Some(&(_, name, label)) => (legend_color(name), format!("{label}{mark}")),
            None => (Rgb(240, 240, 240), "unclassified".into()),
        };
    }
    // A run that failed after its onset (the journal reached the contact limit or the film's
    // Newton iteration gave up in a violent whirl) keeps the unstable class it had reached: an
    // unstable run that ends in contact is no less unstable. Its label carries "(f)". A run
    // stopped by hand after its onset likewise, with "(i)".
    let interrupted = r.status == "interrupted";
    let reached =
        class.filter(|e| r.onset_time_s.is_some() && !["stable", "unstable_linear"].contains(&e.0));
    match reached {
        Some(&(_, name, label)) => {
            let marker = if interrupted { "i" } else { "f" };
            (legend_color(name), format!("{label} ({marker})"))
        }
        None if interrupted => (Rgb(225, 225, 225), "interrupted".into()),
        None => (legend_color("failed"), "failed".into()),
    }
}

/// The legend of the maps, in this order.
pub const LEGEND: &[(&str, Rgb)] = &[
    ("stable", Rgb(166, 219, 160)),
    ("path 1", Rgb(146, 197, 222)),
    ("path 2a", Rgb(253, 219, 132)),
    ("path 2b", Rgb(244, 165, 130)),
    ("unstable low", Rgb(214, 96, 77)),
    ("lin. unst.", Rgb(203, 180, 227)),
    ("failed", Rgb(190, 190, 190)),
    ("too short", Rgb(240, 240, 240)),
];

/// Text sizes [px] of the maps.
const TITLE_PX: f64 = 15.0;
const LABEL_PX: f64 = 13.0;
const CELL_PX: f64 = 12.0;

/// Width of a legend entry [px]: swatch, its name, a gap.
fn legend_entry_w(name: &str) -> f64 {
    24.0 + text_width_px(name, CELL_PX) + 22.0
}

/// "C = 15 um" for a flag and its value.
fn labelled(k: &str, v: &str) -> String {
    let (short, unit) = short_and_unit(k);
    if unit.is_empty() {
        format!("{short} = {v}")
    } else {
        format!("{short} = {v} {unit}")
    }
}

fn fmt_num(v: f64) -> String {
    if v == v.round() && v.abs() < 1e12 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// The map panels: runs grouped by every flag except the one `across` (c in the paper's maps), d
/// and the numerical settings (in KEYS order), in the order of first appearance; and the flags
/// that make up the key. Cells of one panel may come from runs with different numerics (the
/// table lists them).
fn map_panels<'a>(
    records: &'a [RunRecord],
    across: &str,
) -> (Vec<String>, Vec<(Params, Vec<&'a RunRecord>)>) {
    let panel_keys: Vec<String> = keys_in(records.iter().map(|r| &r.args))
        .into_iter()
        .filter(|k| k != across && k != "d" && !NUMERICS.contains(&k.as_str()))
        .collect();
    let key_of = |r: &RunRecord| -> Params {
        panel_keys
            .iter()
            .filter_map(|k| r.args.get(k).map(|v| (k.clone(), v.clone())))
            .collect()
    };
    let mut panels: Vec<(Params, Vec<&RunRecord>)> = Vec::new();
    for r in records {
        let k = key_of(r);
        match panels.iter_mut().find(|p| p.0 == k) {
            Some(p) => p.1.push(r),
            None => panels.push((k, vec![r])),
        }
    }
    (panel_keys, panels)
}

/// Bifurcation maps as the paper's Fig. 17: one panel per combination of the parameters other than
/// c and d (the (C, dH) cases), c [N/mm] across, d [N s/m] upwards, each cell coloured by the run's
/// class and labelled with the onset speed. Writes `<stem>.svg` and `<stem>.png` into `dir`.
pub fn plot_maps(records: &[RunRecord], dir: &Path, stem: &str) -> std::io::Result<Vec<PathBuf>> {
    plot_maps_across(records, dir, stem, "c")
}

/// Further maps for a study of several grids: one per grid whose points vary a parameter other
/// than c across d (the paper's step-height study: dH across, d upwards), written as
/// `<stem>_<grid name>.svg/png`. Grids that vary c are in the main map already.
pub fn plot_grid_maps(
    records: &[RunRecord],
    study: &Study,
    dir: &Path,
    stem: &str,
) -> std::io::Result<Vec<PathBuf>> {
    let mut names: Vec<&str> = study
        .runs
        .iter()
        .flat_map(|r| r.grids.iter().map(String::as_str))
        .collect();
    names.sort();
    names.dedup();
    let mut out = Vec::new();
    if names.len() < 2 {
        return Ok(out);
    }
    for g in names {
        let recs: Vec<RunRecord> = records
            .iter()
            .filter(|r| {
                study
                    .runs
                    .iter()
                    .any(|s| s.name == r.name && s.grids.iter().any(|x| x == g))
            })
            .cloned()
            .collect();
        let varying: Vec<String> = keys_in(recs.iter().map(|r| &r.args))
            .into_iter()
            .filter(|k| k != "d" && !NUMERICS.contains(&k.as_str()))
            .filter(|k| {
                let first = recs.first().and_then(|r| r.args.get(k));
                recs.iter().any(|r| r.args.get(k) != first)
            })
            .collect();
        // The innermost varied parameter across (the grid's nesting order), the others panels.
        let Some(across) = varying.last() else {
            continue;
        };
        if varying.iter().any(|k| k == "c") {
            continue;
        }
        let clean: String = g
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        out.extend(plot_maps_across(
            &recs,
            dir,
            &format!("{stem}_{clean}"),
            across,
        )?);
    }
    Ok(out)
}

/// The maps with the parameter `across` on the horizontal axis and d upwards.
fn plot_maps_across(
    records: &[RunRecord],
    dir: &Path,
    stem: &str,
    across: &str,
) -> std::io::Result<Vec<PathBuf>> {
    let (panel_keys, panels) = map_panels(records, across);
    let x_label = match short_and_unit(across) {
        (short, "") => short,
        (short, unit) => format!("{short} [{unit}]"),
    };
    // Title: the panel parameters that differ between panels (all of them if only one panel).
    let varying: Vec<String> = panel_keys
        .iter()
        .filter(|k| {
            let vals: Vec<Option<&String>> = panels
                .iter()
                .map(|p| p.0.iter().find(|(a, _)| a == *k).map(|(_, v)| v))
                .collect();
            vals.windows(2).any(|w| w[0] != w[1])
        })
        .map(|k| k.to_string())
        .collect();
    let sorted_unique = |vals: Vec<f64>| -> Vec<f64> {
        let mut v: Vec<f64> = vals.into_iter().filter(|x| x.is_finite()).collect();
        v.sort_by(|a, b| a.total_cmp(b));
        v.dedup();
        v
    };
    let grids: Vec<(Vec<f64>, Vec<f64>)> = panels
        .iter()
        .map(|(_, rs)| {
            (
                sorted_unique(rs.iter().filter_map(|r| r.param(across)).collect()),
                sorted_unique(rs.iter().filter_map(|r| r.param("d")).collect()),
            )
        })
        .collect();
    let max_nc = grids.iter().map(|g| g.0.len()).max().unwrap_or(1).max(1);
    let max_nd = grids.iter().map(|g| g.1.len()).max().unwrap_or(1).max(1);
    // The widest d tick label sets the left margin, so the turned axis name never meets it.
    let d_tick_w = grids
        .iter()
        .flat_map(|g| g.1.iter())
        .map(|d| text_width_px(&fmt_num(*d), CELL_PX))
        .fold(0.0, f64::max);
    let titles: Vec<String> = panels
        .iter()
        .map(|(key, _)| {
            let t: Vec<String> = key
                .iter()
                .filter(|(k, _)| {
                    if varying.is_empty() {
                        k == "clearance" || k == "dh"
                    } else {
                        varying.contains(k)
                    }
                })
                .map(|(k, v)| labelled(k, v))
                .collect();
            if t.is_empty() {
                "all runs".to_string()
            } else {
                t.join(", ")
            }
        })
        .collect();
    let cell_w = grids
        .iter()
        .flat_map(|g| g.0.iter())
        .map(|c| text_width_px(&fmt_num(*c), CELL_PX) + 12.0)
        .fold(92.0, f64::max);
    let cell_h = 46.0;
    let (ml, mt, mr, mb) = (d_tick_w + 40.0, 42.0, 18.0, 52.0);
    let widest_title = titles
        .iter()
        .map(|t| text_width_px(t, TITLE_PX))
        .fold(0.0, f64::max);
    let pw = (ml + cell_w * max_nc as f64 + mr)
        .max(300.0)
        .max(widest_title + 16.0)
        .max(text_width_px(&x_label, LABEL_PX) + ml + 16.0);
    let ph = (mt + cell_h * max_nd as f64 + mb).max(mt + text_width_px("d [N s/m]", LABEL_PX) + mb);
    let ncols = panels.len().clamp(1, 3);
    let nrows = panels.len().div_ceil(ncols).max(1);
    let legend_h = 64.0;
    let legend_w: f64 = 20.0 + LEGEND.iter().map(|(n, _)| legend_entry_w(n)).sum::<f64>();
    // The flags every run shares, as a footnote.
    let common: Vec<String> = keys_in(records.iter().map(|r| &r.args))
        .into_iter()
        .filter(|k| k != across && k != "d" && !varying.iter().any(|v| v == k))
        .filter(|k| !(varying.is_empty() && (k == "clearance" || k == "dh")))
        .filter_map(|k| {
            let first = records.first()?.args.get(&k)?;
            records
                .iter()
                .all(|r| r.args.get(&k) == Some(first))
                .then(|| labelled(&k, first))
        })
        .collect();
    let mut footnote = common.join(", ");
    if records.iter().any(|r| r.borderline == Some(true)) {
        if !footnote.is_empty() {
            footnote.push_str("; ");
        }
        footnote.push_str("* borderline: a deciding criterion within 10 % of its bound");
    }
    let footnote_w = text_width_px(&footnote, CELL_PX) + 20.0;
    let width = (pw * ncols as f64).max(legend_w).max(footnote_w).ceil() as u32;
    let height = (ph * nrows as f64 + legend_h).ceil() as u32;
    let mut c = Scene::new(width, height);
    for (pi, ((_, rs), (cs, ds))) in panels.iter().zip(&grids).enumerate() {
        let ox = pw * (pi % ncols) as f64;
        let oy = ph * (pi / ncols) as f64;
        c.panel((ox, oy, pw, ph));
        let title = &titles[pi];
        let (gx, gy) = (ox + ml, oy + mt);
        let (gw, gh) = (cell_w * cs.len() as f64, cell_h * ds.len() as f64);
        // Centred over the grid, but kept inside the panel when the grid is narrower than the title.
        let half_title = 0.5 * text_width_px(title, TITLE_PX);
        let tx = (gx + 0.5 * gw)
            .max(ox + half_title + 6.0)
            .min(ox + pw - half_title - 6.0);
        c.text(tx, oy + 20.0, title, TITLE_PX, Anchor::Middle);
        for r in rs {
            let (Some(cv), Some(dv)) = (r.param(across), r.param("d")) else {
                continue;
            };
            let (Some(ic), Some(id)) = (
                cs.iter().position(|x| *x == cv),
                ds.iter().position(|x| *x == dv),
            ) else {
                continue;
            };
            let x = gx + cell_w * ic as f64;
            let y = gy + gh - cell_h * (id + 1) as f64;
            let (fill, label) = cell_style(r);
            c.rect((x, y, cell_w, cell_h), Some(fill), Some(Rgb::WHITE));
            // "path 1 (f)": the marker goes on the second line (such runs show no onset speed),
            // so the label fits a narrow cell.
            let (class, marker) = label.split_once(" (").unwrap_or((&label, ""));
            c.text(x + 0.5 * cell_w, y + 15.0, class, CELL_PX, Anchor::Middle);
            if !marker.is_empty() {
                let marker = format!("({marker}");
                c.text(x + 0.5 * cell_w, y + 32.0, &marker, CELL_PX, Anchor::Middle);
            }
            if let Some(f) = r.onset_speed_hz.filter(|_| r.status == "completed") {
                c.text(
                    x + 0.5 * cell_w,
                    y + 32.0,
                    &format!("{f:.0} Hz"),
                    CELL_PX,
                    Anchor::Middle,
                );
            }
        }
        c.rect((gx, gy, gw, gh), None, Some(Rgb::BLACK));
        for (i, cv) in cs.iter().enumerate() {
            let x = gx + cell_w * (i as f64 + 0.5);
            c.text(x, gy + gh + 13.0, &fmt_num(*cv), CELL_PX, Anchor::Middle);
        }
        for (j, dv) in ds.iter().enumerate() {
            let y = gy + gh - cell_h * (j as f64 + 0.5);
            c.text(gx - 6.0, y, &fmt_num(*dv), CELL_PX, Anchor::End);
        }
        c.text(
            gx + 0.5 * gw,
            gy + gh + 33.0,
            &x_label,
            LABEL_PX,
            Anchor::Middle,
        );
        c.vtext(
            gx - 6.0 - d_tick_w - 16.0,
            gy + 0.5 * gh,
            "d [N s/m]",
            LABEL_PX,
        );
    }
    let ly = ph * nrows as f64 + 10.0;
    let mut x = 10.0;
    for (name, col) in LEGEND.iter() {
        c.rect((x, ly, 18.0, 18.0), Some(*col), Some(Rgb::GREY));
        c.text(x + 24.0, ly + 9.0, name, CELL_PX, Anchor::Start);
        x += legend_entry_w(name);
    }
    if !footnote.is_empty() {
        c.text(10.0, ly + 38.0, &footnote, CELL_PX, Anchor::Start);
    }
    c.save(dir, stem)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn failed_runs_keep_the_class_they_reached_after_onset() {
        let rec = |status: &str, class: Option<&str>, onset: Option<f64>| RunRecord {
            name: "r".into(),
            index: 0,
            args: BTreeMap::new(),
            status: status.into(),
            classification: class.map(String::from),
            borderline: None,
            onset_time_s: onset,
            onset_speed_hz: None,
            max_eps_c: None,
            max_eps_t: None,
            wall_time_s: None,
            settings: serde_json::Value::Null,
            dir: Default::default(),
        };
        assert_eq!(
            cell_style(&rec("failed", Some("path2b"), Some(1.1))).1,
            "path 2b (f)"
        );
        assert_eq!(cell_style(&rec("failed", Some("stable"), None)).1, "failed");
        // A borderline class is marked.
        let mut b = rec("completed", Some("path2a"), Some(2.0));
        b.borderline = Some(true);
        assert_eq!(cell_style(&b).1, "path 2a *");
        assert_eq!(
            cell_style(&rec("completed", Some("path2b"), Some(1.1))).1,
            "path 2b"
        );
        assert_eq!(
            cell_style(&rec("interrupted", Some("path1"), Some(1.1))).1,
            "path 1 (i)"
        );
        assert_eq!(
            cell_style(&rec("interrupted", Some("stable"), None)).1,
            "interrupted"
        );
    }

    #[test]
    fn runs_that_differ_only_in_numerics_share_a_panel() {
        let rec = |c: &str, contact: Option<&str>, clearance: &str| {
            let mut args: BTreeMap<String, String> =
                [("clearance", clearance), ("c", c), ("d", "50")]
                    .into_iter()
                    .map(|(k, v)| (k.to_string(), v.to_string()))
                    .collect();
            if let Some(side) = contact {
                args.insert("contact".into(), side.into());
            }
            RunRecord {
                name: format!("C{clearance}_c{c}"),
                index: 0,
                args,
                status: "completed".into(),
                classification: Some("stable".into()),
                borderline: None,
                onset_time_s: None,
                onset_speed_hz: None,
                max_eps_c: None,
                max_eps_t: None,
                wall_time_s: None,
                settings: serde_json::Value::Null,
                dir: Default::default(),
            }
        };
        let records = [
            rec("500", None, "30"),
            rec("1000", Some("rotor"), "30"),
            rec("500", Some("film"), "20"),
        ];
        let (keys, panels) = map_panels(&records, "c");
        assert!(!keys.iter().any(|k| k == "contact"));
        let sizes: Vec<usize> = panels.iter().map(|p| p.1.len()).collect();
        assert_eq!(sizes, [2, 1], "{panels:?}");
    }
}
