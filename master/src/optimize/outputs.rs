//! What an optimisation leaves in its folder: `evaluations.csv` (every candidate, the stage
//! that decided it, its worst values and why), `optimum.json` (the recommendation, its corners
//! and its verification), `recommended.toml` (a design file for `airring runup --design`),
//! `pareto.csv` (two objectives), the safe-set maps (`safe_set_*.svg/.png`) and `report.html`.

use super::evaluate::Stage;
use super::verify::Verification;
use super::{Candidate, Problem};
use crate::plot::chart::Heatmap;
use crate::plot::Role;
use crate::plot::{Chart, Figure as _, Rgb};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A value for tables and messages: 4 significant digits, "-" for a missing one.
pub fn fmt(x: f64) -> String {
    if !x.is_finite() {
        return "-".into();
    }
    let r = super::problem::significant(x, 4);
    format!("{r}")
}

pub fn write_all(
    p: &Problem,
    candidates: &[Candidate],
    best: Option<usize>,
    verification: Option<&Verification>,
    out: &Path,
) -> Result<Vec<PathBuf>, String> {
    let mut files = vec![];
    let csv = out.join("evaluations.csv");
    crate::output::write_whole(&csv, evaluations_csv(p, candidates).as_bytes())?;
    files.push(csv);
    let json = out.join("optimum.json");
    let optimum = optimum_json(p, candidates, best, verification);
    crate::output::write_whole(
        &json,
        serde_json::to_string_pretty(&optimum)
            .map_err(|e| e.to_string())?
            .as_bytes(),
    )?;
    files.push(json);
    if let Some(b) = best {
        let design = out.join("recommended.toml");
        crate::output::write_whole(&design, recommended_design(p, &candidates[b])?.as_bytes())?;
        files.push(design);
    }
    if p.objectives.len() == 2 {
        let path = out.join("pareto.csv");
        crate::output::write_whole(&path, pareto_csv(p, candidates).as_bytes())?;
        files.push(path);
    }
    let mut figures = vec![];
    for (stem, chart) in safe_set_maps(p, candidates, best) {
        match chart.save(out, &stem) {
            Ok(f) => figures.extend(f),
            Err(e) => eprintln!("warning: {stem}: {e}"),
        }
    }
    let page = out.join("report.html");
    crate::output::write_whole(
        &page,
        report_html(p, candidates, best, verification, &figures).as_bytes(),
    )?;
    files.extend(figures);
    files.push(page);
    Ok(files)
}

fn stage_name(s: Stage) -> &'static str {
    match s {
        Stage::Linear => "linear",
        Stage::Nonlinear => "nonlinear",
    }
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub fn evaluations_csv(p: &Problem, candidates: &[Candidate]) -> String {
    let mut s = String::from("index,");
    for v in &p.variables {
        s += &csv_field(&v.label());
        s.push(',');
    }
    s += "stage,feasible,min film [um],whirl [um],threshold [Hz],friction power [W],margin [1],";
    for o in &p.objectives {
        let _ = write!(
            s,
            "{} {},",
            if o.maximize { "max" } else { "min" },
            csv_field(&o.quantity.label(&p.variables))
        );
    }
    s += "run-ups,reason\n";
    for c in candidates {
        let _ = write!(s, "{},", c.index);
        for x in &c.x {
            let _ = write!(s, "{x},");
        }
        let runs = c.corners.iter().filter(|k| k.nonlinear.is_some()).count();
        let _ = write!(
            s,
            "{},{},{},{},{},{},{},",
            stage_name(c.stage),
            c.feasible,
            fmt(c.min_film_um),
            fmt(c.whirl_um),
            c.threshold_hz.map_or("-".into(), fmt),
            fmt(c.power_loss_w),
            fmt(c.margin)
        );
        for o in &c.objectives {
            let _ = write!(s, "{},", fmt(*o));
        }
        let _ = writeln!(s, "{runs},{}", csv_field(&c.reason));
    }
    s
}

fn optimum_json(
    p: &Problem,
    candidates: &[Candidate],
    best: Option<usize>,
    verification: Option<&Verification>,
) -> serde_json::Value {
    let by_stage = |s: Stage| candidates.iter().filter(|c| c.stage == s).count();
    let requirement = serde_json::json!({
        "speed_range_hz": [p.speed_range_hz.0, p.speed_range_hz.1],
        "min_film_um": p.min_film_um,
        "max_whirl_um": p.max_whirl_um,
        "classes": p.classes,
        "tolerances": p.tolerances.iter().map(|(k, t)| (k.clone(), match t {
            super::problem::Tolerance::Absolute(a) => format!("+-{a}"),
            super::problem::Tolerance::Relative(r) => format!("+-{}%", r * 100.0),
        })).collect::<std::collections::BTreeMap<_, _>>(),
    });
    let objectives: Vec<serde_json::Value> = p
        .objectives
        .iter()
        .map(|o| {
            serde_json::json!({
                "quantity": o.quantity.key(&p.variables),
                "label": o.quantity.label(&p.variables),
                "sense": if o.maximize { "maximize" } else { "minimize" },
            })
        })
        .collect();
    let recommended = best.map(|b| {
        let c = &candidates[b];
        serde_json::json!({
            "index": c.index,
            "variables": p.variables.iter().zip(&c.x).map(|(v, x)| (v.key.clone(), serde_json::json!({
                "value": x, "unit": v.unit,
            }))).collect::<serde_json::Map<_, _>>(),
            "objectives": c.objectives,
            "min_film_um": c.min_film_um,
            "whirl_um": c.whirl_um,
            "threshold_hz": c.threshold_hz,
            "power_loss_w": c.power_loss_w,
            "margin": c.margin,
            "stage": c.stage,
            "reason": c.reason,
            "corners": c.corners,
        })
    });
    serde_json::json!({
        "name": p.name,
        "requirement": requirement,
        "objectives": objectives,
        "evaluations": candidates.len(),
        "feasible": candidates.iter().filter(|c| c.feasible).count(),
        "decided_by_linear_stage": by_stage(Stage::Linear),
        "decided_by_run_ups": by_stage(Stage::Nonlinear),
        "recommended": recommended,
        "verification": verification,
    })
}

/// A TOML value for a design-file entry's text: a number or boolean as such, else a string.
fn design_value(text: &str) -> toml::Value {
    if let Ok(i) = text.trim().parse::<i64>() {
        return toml::Value::Integer(i);
    }
    if let Ok(x) = text.trim().parse::<f64>() {
        return toml::Value::Float(x);
    }
    match text.trim() {
        "true" => toml::Value::Boolean(true),
        "false" => toml::Value::Boolean(false),
        t => toml::Value::String(t.to_string()),
    }
}

/// The recommended design as a design file: its bearing quantities (from the run-up settings of
/// its nominal corner) and the FMU parameters its base and variables set, each written once.
pub fn recommended_design(p: &Problem, best: &Candidate) -> Result<String, String> {
    let nominal = &best
        .corners
        .first()
        .ok_or("the recommended design has no nominal corner")?
        .args;
    let s = crate::sweep::linear::settings_for(nominal)?;
    // (table, key) -> value; later entries replace earlier ones, as FMU parameters apply after
    // the run-up's own quantities.
    let mut tables: std::collections::BTreeMap<&str, toml::Table> = Default::default();
    let mut put = |table: &'static str, key: &str, v: toml::Value| {
        tables.entry(table).or_default().insert(key.into(), v);
    };
    put(
        "bearing",
        "C",
        toml::Value::String(format!("{} um", s.clearance_um)),
    );
    put(
        "bearing",
        "dH",
        toml::Value::String(format!("{} um", s.dh_um)),
    );
    put(
        "bearing",
        "mount_c",
        toml::Value::String(format!("{} N/mm", s.c_n_per_mm)),
    );
    put(
        "bearing",
        "mount_d",
        toml::Value::String(format!("{} N.s/m", s.d_n_s_per_m)),
    );
    put(
        "bearing",
        "ring_mass",
        toml::Value::String(format!("{} g", s.m_r_g)),
    );
    for (key, text) in &s.fmu_parameters {
        let (prefix, name) = key.split_once('.').unwrap_or(("", key));
        let mount = |side: &str| -> Option<&'static str> {
            [("c_", "mount_c"), ("d_", "mount_d"), ("m_R_", "ring_mass")]
                .iter()
                .find(|(pre, _)| name == format!("{pre}{side}"))
                .map(|(_, k)| *k)
        };
        match prefix {
            "film" => put("bearing", name, design_value(text)),
            "film_C" => put("bearing.compressor", name, design_value(text)),
            "film_T" => put("bearing.turbine", name, design_value(text)),
            "rotor" => match (mount("C"), mount("T")) {
                (Some(k), _) => put("bearing.compressor", k, design_value(text)),
                (_, Some(k)) => put("bearing.turbine", k, design_value(text)),
                _ => put("rotor", name, design_value(text)),
            },
            _ => return Err(format!("{key}: no design-file place for this parameter")),
        }
    }
    let mut text = format!(
        "# The design `airring optimize` recommends for '{}' (candidate #{}): {}.\n\
         # Run it: airring runup --design recommended.toml\n",
        p.name,
        best.index,
        super::describe_x(p, &best.x)
    );
    if s.preset != "path1" {
        let _ = writeln!(
            text,
            "# Its rotor is the paper's; the base preset was '{}' (its bearing values are written \
             out below).",
            s.preset
        );
    }
    for (name, t) in tables {
        let _ = writeln!(text, "\n[{name}]");
        text += &toml::to_string(&t).map_err(|e| e.to_string())?;
    }
    Ok(text)
}

/// The feasible candidates no other feasible one beats in both objectives.
pub fn pareto_front(p: &Problem, candidates: &[Candidate]) -> Vec<usize> {
    let key = |c: &Candidate| -> Vec<f64> {
        p.objectives
            .iter()
            .zip(&c.objectives)
            .map(|(o, v)| super::evaluate::to_minimise(o, *v))
            .collect()
    };
    let ok: Vec<(usize, Vec<f64>)> = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.feasible && c.objectives.iter().all(|v| v.is_finite()))
        .map(|(i, c)| (i, key(c)))
        .collect();
    let mut front: Vec<usize> = ok
        .iter()
        .filter(|(_, a)| {
            !ok.iter().any(|(_, b)| {
                b.iter().zip(a).all(|(b, a)| b <= a) && b.iter().zip(a).any(|(b, a)| b < a)
            })
        })
        .map(|(i, _)| *i)
        .collect();
    front.sort_by(|a, b| key(&candidates[*a])[0].total_cmp(&key(&candidates[*b])[0]));
    front
}

fn pareto_csv(p: &Problem, candidates: &[Candidate]) -> String {
    let mut s = String::from("index,");
    for v in &p.variables {
        s += &csv_field(&v.label());
        s.push(',');
    }
    s += &p
        .objectives
        .iter()
        .map(|o| csv_field(&o.quantity.label(&p.variables)))
        .collect::<Vec<_>>()
        .join(",");
    s.push('\n');
    for i in pareto_front(p, candidates) {
        let c = &candidates[i];
        let _ = write!(s, "{},", c.index);
        for x in &c.x {
            let _ = write!(s, "{x},");
        }
        let _ = writeln!(
            s,
            "{}",
            c.objectives
                .iter()
                .map(|v| fmt(*v))
                .collect::<Vec<_>>()
                .join(",")
        );
    }
    s
}

const FEASIBLE: Rgb = Rgb(0, 140, 60);
const INFEASIBLE: Rgb = Rgb(200, 40, 40);
const OPTIMUM: Rgb = Rgb(20, 60, 200);

/// A "+" at `(x, y)` sized by the axes' spans.
fn cross(c: &mut Chart, (x, y): (f64, f64), color: Rgb, size: f64, name: &str) {
    let (dx, dy) = (size * (c.x.1 - c.x.0), size * (c.y.1 - c.y.0));
    c.line(
        [(x - dx, y), (x + dx, y)],
        color,
        2.0,
        false,
        Role::Series,
        name,
    );
    c.line(
        [(x, y - dy), (x, y + dy)],
        color,
        2.0,
        false,
        Role::Series,
        name,
    );
}

/// The surrogates' verdict on a design: safe or unsafe with a probability of feasibility beyond
/// `CERTAIN` either way, uncertain in between (the boundary of the safe set lies there).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Safe,
    Uncertain,
    Unsafe,
}

/// How sure the surrogates must be to call a design safe or unsafe.
pub const CERTAIN: f64 = 0.9;

/// The constraint surrogates' verdicts at `points` (own units), fitted to every candidate as the
/// search fits them; `None` where they cannot be fitted (fewer than two candidates).
pub fn surrogate_verdicts(
    p: &Problem,
    candidates: &[Candidate],
    points: &[Vec<f64>],
) -> Option<Vec<Verdict>> {
    let variables: Vec<design_search::Variable> =
        p.variables.iter().map(|v| v.bounds.clone()).collect();
    let evals: Vec<design_search::Evaluation> =
        candidates.iter().map(|c| super::as_search(p, c)).collect();
    let pred =
        design_search::safe_set(&variables, &evals, super::constraint_count(p), points).ok()?;
    Some(
        pred.iter()
            .map(|q| {
                if q.p_feasible >= CERTAIN {
                    Verdict::Safe
                } else if q.p_feasible <= 1.0 - CERTAIN {
                    Verdict::Unsafe
                } else {
                    Verdict::Uncertain
                }
            })
            .collect(),
    )
}

/// The safe set in 2-D slices through the recommended design: every evaluated candidate by its
/// two variables (green feasible, red not), the recommendation in blue, the background shaded by
/// the search's constraint surrogates (safe, unsafe, or uncertain where the boundary lies: an
/// estimate between the evaluated points, not an evaluation). One variable: the worst film
/// thickness against it, with the limit.
pub fn safe_set_maps(
    p: &Problem,
    candidates: &[Candidate],
    best: Option<usize>,
) -> Vec<(String, Chart)> {
    let mut out = vec![];
    if candidates.is_empty() {
        return out;
    }
    if p.dim() == 1 {
        let v = &p.variables[0];
        let pts: Vec<(f64, f64, bool)> = candidates
            .iter()
            .filter(|c| c.min_film_um.is_finite())
            .map(|c| (c.x[0], c.min_film_um, c.feasible))
            .collect();
        let ys = pts.iter().map(|p| p.1).chain([p.min_film_um]);
        let y = (
            ys.clone().fold(f64::INFINITY, f64::min).min(0.0),
            ys.fold(f64::NEG_INFINITY, f64::max),
        );
        let mut c = Chart::new(
            900,
            560,
            &format!("{}: worst film thickness over the corners", p.name),
            &v.label(),
            "minimum film thickness [um]",
            (v.bounds.lo, v.bounds.hi),
            y,
        );
        c.line(
            [(v.bounds.lo, p.min_film_um), (v.bounds.hi, p.min_film_um)],
            Rgb(0, 0, 0),
            1.0,
            true,
            Role::Reference,
            "limit",
        );
        for (x, h, ok) in pts {
            cross(
                &mut c,
                (x, h),
                if ok { FEASIBLE } else { INFEASIBLE },
                0.01,
                "evaluation",
            );
        }
        if let Some(b) = best {
            let bc = &candidates[b];
            cross(
                &mut c,
                (bc.x[0], bc.min_film_um),
                OPTIMUM,
                0.025,
                "recommended",
            );
        }
        c.legend(&[
            ("feasible", FEASIBLE),
            ("infeasible", INFEASIBLE),
            ("recommended", OPTIMUM),
        ]);
        out.push(("safe_set".to_string(), c));
        return out;
    }
    let pairs: Vec<(usize, usize)> = (1..p.dim()).map(|j| (0, j)).take(4).collect();
    for (i, j) in pairs {
        let (vi, vj) = (&p.variables[i], &p.variables[j]);
        let mut c = Chart::new(
            900,
            640,
            &format!(
                "{}: safe set, {} against {}",
                p.name,
                vi.label(),
                vj.label()
            ),
            &vi.label(),
            &vj.label(),
            (vi.bounds.lo, vi.bounds.hi),
            (vj.bounds.lo, vj.bounds.hi),
        );
        // Background: what the search's constraint surrogates make of the slice (the other
        // variables at the recommendation's values), or, where they cannot be fitted, the
        // nearest evaluated candidate's verdict.
        let (cols, rows) = (90usize, 64usize);
        let through = best.map_or_else(|| candidates[0].x.clone(), |b| candidates[b].x.clone());
        let mut points = Vec::with_capacity(cols * rows);
        // Cells evenly spaced on the chart's (linear) axes, top row first.
        for r in 0..rows {
            let y = c.y.1 - (c.y.1 - c.y.0) * (r as f64 + 0.5) / rows as f64;
            for col in 0..cols {
                let x = c.x.0 + (c.x.1 - c.x.0) * (col as f64 + 0.5) / cols as f64;
                let mut at = through.clone();
                at[i] = x.max(1e-300);
                at[j] = y.max(1e-300);
                points.push(at);
            }
        }
        let verdicts = surrogate_verdicts(p, candidates, &points).unwrap_or_else(|| {
            let known: Vec<(f64, f64, bool)> = candidates
                .iter()
                .map(|k| (vi.bounds.unit(k.x[i]), vj.bounds.unit(k.x[j]), k.feasible))
                .collect();
            points
                .iter()
                .map(|x| {
                    let (ux, uy) = (vi.bounds.unit(x[i]), vj.bounds.unit(x[j]));
                    let ok = known
                        .iter()
                        .min_by(|a, b| {
                            let da = (a.0 - ux).powi(2) + (a.1 - uy).powi(2);
                            let db = (b.0 - ux).powi(2) + (b.1 - uy).powi(2);
                            da.total_cmp(&db)
                        })
                        .is_some_and(|k| k.2);
                    if ok {
                        Verdict::Safe
                    } else {
                        Verdict::Unsafe
                    }
                })
                .collect()
        });
        let rgb: Vec<u8> = verdicts
            .iter()
            .flat_map(|v| match v {
                Verdict::Safe => [225, 243, 228],
                Verdict::Unsafe => [248, 226, 226],
                Verdict::Uncertain => [250, 244, 214],
            })
            .collect();
        c.heatmap = Some(Heatmap { cols, rows, rgb });
        for k in candidates {
            let color = if k.feasible { FEASIBLE } else { INFEASIBLE };
            cross(&mut c, (k.x[i], k.x[j]), color, 0.01, "evaluation");
        }
        if let Some(b) = best {
            let bc = &candidates[b];
            cross(&mut c, (bc.x[i], bc.x[j]), OPTIMUM, 0.025, "recommended");
        }
        c.legend(&[
            ("feasible", FEASIBLE),
            ("infeasible", INFEASIBLE),
            ("recommended", OPTIMUM),
            ("surrogate: safe", Rgb(225, 243, 228)),
            ("surrogate: uncertain", Rgb(250, 244, 214)),
            ("surrogate: unsafe", Rgb(248, 226, 226)),
        ]);
        out.push((format!("safe_set_{}_{}", slug(&vi.key), slug(&vj.key)), c));
    }
    out
}

fn slug(k: &str) -> String {
    k.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

fn esc(s: &str) -> String {
    crate::plot::svg::xml_escape(s)
}

fn report_html(
    p: &Problem,
    candidates: &[Candidate],
    best: Option<usize>,
    verification: Option<&Verification>,
    figures: &[PathBuf],
) -> String {
    let mut h = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>airring optimize: {n}</title>\
         <style>body{{font-family:sans-serif;max-width:1100px;margin:2em auto}}table{{border-collapse:collapse}}\
         td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}th{{background:#f2f2f2}}\
         .ok{{color:#08602c}}.bad{{color:#b01c1c}}</style></head><body>\n<h1>{n}: which design to build</h1>\n",
        n = esc(&p.name)
    );
    let req = format!(
        "film thickness at least {} um{}{} over {:.0}-{:.0} Hz, at every corner of the tolerance \
         box ({})",
        p.min_film_um,
        p.max_whirl_um.map_or(String::new(), |w| format!(
            ", whirl amplitude at most {w} um"
        )),
        if p.classes.is_empty() {
            String::new()
        } else {
            format!(", class in {{{}}}", p.classes.join(", "))
        },
        p.speed_range_hz.0,
        p.speed_range_hz.1,
        if p.tolerances.is_empty() {
            "none".to_string()
        } else {
            p.tolerances
                .iter()
                .map(|(k, t)| match t {
                    super::problem::Tolerance::Absolute(a) => format!("{k} +-{a}"),
                    super::problem::Tolerance::Relative(r) => format!("{k} +-{}%", r * 100.0),
                })
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    let _ = writeln!(h, "<p><b>Requirement:</b> {}</p>", esc(&req));
    match best {
        None => {
            let _ = writeln!(
                h,
                "<h2 class=\"bad\">No design meets the requirement</h2><p>None of the {} \
                 candidates met it at all its corners. evaluations.csv gives each one's reason.</p>",
                candidates.len()
            );
            if let Some(i) = super::closest_of(candidates) {
                let c = &candidates[i];
                let _ = writeln!(
                    h,
                    "<p>Nearest to meeting it: candidate #{} ({}), margin {}: {}.</p>",
                    c.index,
                    esc(&super::describe_x(p, &c.x)),
                    fmt(c.margin),
                    esc(&c.reason)
                );
            }
        }
        Some(b) => {
            let c = &candidates[b];
            let _ = writeln!(
                h,
                "<h2>Recommended: {}</h2>\n<p>Candidate #{}; {}. Objective{}: {}. Design file: \
                 <a href=\"recommended.toml\">recommended.toml</a>.</p>",
                esc(&super::describe_x(p, &c.x)),
                c.index,
                esc(&c.reason),
                if p.objectives.len() > 1 { "s" } else { "" },
                esc(&p
                    .objectives
                    .iter()
                    .zip(&c.objectives)
                    .map(|(o, v)| format!(
                        "{} {} = {}",
                        if o.maximize { "max" } else { "min" },
                        o.quantity.label(&p.variables),
                        fmt(*v)
                    ))
                    .collect::<Vec<_>>()
                    .join("; "))
            );
            match verification {
                Some(v) => {
                    let verdict = match (v.verified, v.resolved) {
                        (true, true) => ("ok", "Verified: every corner meets the requirement on the fine mesh, with margins larger than the discretization error."),
                        (true, false) => ("bad", "Met on the fine mesh, but a margin is within the discretization error: the verdict rests on the mesh."),
                        _ => ("bad", "Not verified: a corner fails on the fine mesh (see below)."),
                    };
                    let _ = writeln!(
                        h,
                        "<p class=\"{}\"><b>{}</b></p><p>Worst over the corners on the {} mesh \
                         (run-up and run-down, {} s each way): film {} um (margin {} um, mesh \
                         error {} um), whirl {} um{} (mesh error {} um).</p>",
                        verdict.0,
                        verdict.1,
                        esc(&v.mesh),
                        v.t_ramp_s,
                        fmt(v.min_film_um),
                        fmt(v.film_margin_um),
                        fmt(v.film_error_um),
                        fmt(v.whirl_um),
                        v.whirl_margin_um
                            .map_or(String::new(), |m| format!(" (margin {} um)", fmt(m))),
                        fmt(v.whirl_error_um),
                    );
                    h += "<h3>Verification runs</h3>\n<table><tr><th>corner</th><th>class</th>\
                          <th>film [um]</th><th>film, search mesh [um]</th><th>whirl [um]</th>\
                          <th>whirl, search mesh [um]</th><th>onset [Hz]</th><th>verdict</th></tr>\n";
                    for k in &v.corners {
                        let _ = writeln!(
                            h,
                            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
                             <td>{}</td><td class=\"{}\">{}</td></tr>",
                            esc(&k.label),
                            esc(k.fine.class.as_deref().unwrap_or("-")),
                            fmt(k.fine.min_film_um),
                            fmt(k.coarse.min_film_um),
                            fmt(k.fine.whirl_um),
                            fmt(k.coarse.whirl_um),
                            k.fine.onset_hz.map_or("-".into(), fmt),
                            if k.ok { "ok" } else { "bad" },
                            esc(&k.reason)
                        );
                    }
                    h += "</table>\n";
                }
                None => {
                    h += "<p>Not verified (--no-verify, or the search was interrupted).</p>\n";
                }
            }
            h += "<h3>Its tolerance corners in the search</h3>\n<table><tr><th>corner</th>\
                  <th>stage</th><th>class</th><th>film [um]</th><th>whirl [um]</th>\
                  <th>linear threshold [Hz]</th><th>verdict</th></tr>\n";
            for k in &c.corners {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
                     <td class=\"{}\">{}</td></tr>",
                    esc(&k.label),
                    stage_name(k.stage),
                    esc(k.class.as_deref().unwrap_or("-")),
                    fmt(k.min_film_um),
                    fmt(k.whirl_um),
                    k.linear.threshold_hz.map_or("none".into(), fmt),
                    if k.ok { "ok" } else { "bad" },
                    esc(&k.reason)
                );
            }
            h += "</table>\n";
        }
    }
    let linear = candidates
        .iter()
        .filter(|c| c.stage == Stage::Linear)
        .count();
    let _ = writeln!(
        h,
        "<h2>The search</h2><p>{} candidates ({} feasible): {} decided by the linear stage, {} by \
         run-ups and run-downs. Every candidate: <a href=\"evaluations.csv\">evaluations.csv</a>; \
         the run-ups: <a href=\"nonlinear/report.html\">nonlinear/</a>.</p>",
        candidates.len(),
        candidates.iter().filter(|c| c.feasible).count(),
        linear,
        candidates.len() - linear
    );
    for f in figures
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "svg"))
    {
        let name = f
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let _ = writeln!(
            h,
            "<p><img src=\"{}\" alt=\"{}\" style=\"max-width:100%\"></p>",
            esc(&name),
            esc(&name)
        );
    }
    h += "</body></html>\n";
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::evaluate::{summarize, Corner};

    fn problem(two: bool) -> Problem {
        let objective = if two {
            "[[objective]]\nmaximize = \"clearance\"\n[[objective]]\nminimize = \"c\"\n"
        } else {
            "[objective]\nmaximize = \"clearance\"\n"
        };
        Problem::parse(
            &format!(
                "[variables]\nclearance = [10, 30]\nc = [200, 2000]\n[requirement]\n\
                 min_film_um = 2.0\n{objective}"
            ),
            Path::new("t.toml"),
        )
        .unwrap()
    }

    fn candidate(p: &Problem, i: usize, x: [f64; 2], film: f64) -> Candidate {
        let corner = Corner {
            label: "nominal".into(),
            args: [
                ("preset".to_string(), "path1".to_string()),
                ("clearance".to_string(), x[0].to_string()),
                ("c".to_string(), x[1].to_string()),
            ]
            .into(),
            linear: Default::default(),
            nonlinear: None,
            stage: Stage::Linear,
            min_film_um: film,
            whirl_um: 0.0,
            class: Some("stable".into()),
            ok: film >= 2.0,
            reason: "r".into(),
        };
        summarize(p, i, x.to_vec(), vec![corner])
    }

    #[test]
    fn the_pareto_front_keeps_the_feasible_points_nothing_beats_in_both() {
        let p = problem(true);
        // Maximise clearance, minimise c.
        let cs = vec![
            candidate(&p, 0, [20.0, 1000.0], 3.0),
            candidate(&p, 1, [25.0, 1500.0], 3.0),
            candidate(&p, 2, [18.0, 1200.0], 3.0), // beaten by #0 in both
            candidate(&p, 3, [29.0, 300.0], 1.0),  // best in both, infeasible
            candidate(&p, 4, [15.0, 400.0], 3.0),
        ];
        assert_eq!(pareto_front(&p, &cs), vec![1, 0, 4]);
        let csv = pareto_csv(&p, &cs);
        assert_eq!(csv.lines().count(), 4, "{csv}");
    }

    #[test]
    fn the_recommended_design_file_gives_the_same_run_up_settings() {
        let p = problem(false);
        let c = candidate(&p, 0, [17.5, 812.0], 3.0);
        let text = recommended_design(&p, &c).unwrap();
        let dir = std::env::temp_dir().join(format!("airring-rec-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("recommended.toml");
        std::fs::write(&file, &text).unwrap();
        let direct = crate::sweep::linear::settings_for(&c.corners[0].args).unwrap();
        let via_file = crate::sweep::linear::settings_for(
            &[("design".to_string(), file.display().to_string())].into(),
        )
        .unwrap();
        let (a, b) = (
            crate::stability::params_of(&direct).unwrap(),
            crate::stability::params_of(&via_file).unwrap(),
        );
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "{text}");
        assert!(text.contains("C = \"17.5 um\""), "{text}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn maps_and_tables_cover_every_candidate() {
        let p = problem(false);
        let cs = vec![
            candidate(&p, 0, [20.0, 1000.0], 3.0),
            candidate(&p, 1, [12.0, 300.0], 1.0),
        ];
        let csv = evaluations_csv(&p, &cs);
        assert_eq!(csv.lines().count(), 3);
        assert!(csv.lines().nth(2).unwrap().contains(",false,1,"), "{csv}");
        let maps = safe_set_maps(&p, &cs, Some(0));
        assert_eq!(maps.len(), 1);
        let svg = crate::plot::Figure::to_svg(&maps[0].1).unwrap();
        assert!(svg.contains("recommended"));
        let html = report_html(&p, &cs, Some(0), None, &[]);
        assert!(
            html.contains("Recommended: C = 20 um, c = 1000 N/mm"),
            "{html}"
        );
    }
}
