use std::path::PathBuf;

use super::*;
use runup_analysis::synth::{add_whirl, base, hopf_amp, C_M};
use runup_analysis::{classify, Bearing};

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("airring-plot-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn count(doc: &roxmltree::Document, tag: &str, class: &str) -> usize {
    doc.descendants()
        .filter(|n| n.has_tag_name(tag) && n.attribute("class") == Some(class))
        .count()
}

#[test]
fn lobe_contours_close_at_c_on_trailing_edges_and_open_to_c_plus_dh() {
    let g = Bore::paper();
    let lobes = g.closure_contours_m(50);
    assert_eq!(lobes.len(), 3);
    for (k, l) in lobes.iter().enumerate() {
        let lead = l[0];
        let trail = *l.last().unwrap();
        assert!(
            (trail.0.hypot(trail.1) - g.c_m).abs() < 1e-15,
            "trailing edge radius"
        );
        assert!(
            (lead.0.hypot(lead.1) - (g.c_m + g.dh_m)).abs() < 1e-15,
            "leading edge radius"
        );
        // The trailing edge of lobe k sits at theta = 2 pi k / 3 + phi_t + alpha = 2 pi k / 3 + pi.
        let theta = std::f64::consts::TAU * k as f64 / 3.0 + std::f64::consts::PI;
        let expect = (g.c_m * theta.cos(), g.c_m * theta.sin());
        assert!((trail.0 - expect.0).abs() < 1e-15 && (trail.1 - expect.1).abs() < 1e-15);
        // The radius falls monotonically from leading to trailing edge (a converging wedge).
        assert!(l
            .windows(2)
            .all(|w| w[1].0.hypot(w[1].1) < w[0].0.hypot(w[0].1)));
    }
}

#[test]
fn runup_figures_are_written_well_formed_with_their_series() {
    let mut s = base(5e-5, 3.0);
    add_whirl(
        &mut s,
        Bearing::T,
        1.15,
        hopf_amp(1.15, 0.8 * C_M, 0.15),
        |_| 345.0,
    );
    add_whirl(
        &mut s,
        Bearing::C,
        1.35,
        hopf_amp(1.35, 0.7 * C_M, 0.15),
        |_| 420.0,
    );
    let cl = classify(&s);
    assert!(cl.onset_time_s.is_some());
    // AIRRING_PLOT_DIR=/some/dir keeps the figures for a look.
    let keep = std::env::var_os("AIRRING_PLOT_DIR").map(PathBuf::from);
    let dir = keep.clone().unwrap_or_else(|| temp_dir("runup"));
    std::fs::create_dir_all(&dir).unwrap();
    let files = plot_runup(&s, &cl, &[Bore::paper(), Bore::paper()], &dir).unwrap();
    let stems = [
        "eps",
        "y_journal",
        "waterfall_C",
        "orbit_C",
        "waterfall_T",
        "orbit_T",
    ];
    assert_eq!(files.len(), 2 * stems.len());
    for stem in stems {
        let svg_path = dir.join(format!("{stem}.svg"));
        let text = std::fs::read_to_string(&svg_path).unwrap();
        assert!(text.len() < 2_000_000, "{stem}.svg is {} bytes", text.len());
        let doc = roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{stem}.svg: {e}"));
        assert_eq!(doc.root_element().tag_name().name(), "svg");
        let series = count(&doc, "polyline", "series");
        let expected = match stem {
            "eps" | "y_journal" => 2,
            _ => 1,
        };
        assert_eq!(series, expected, "{stem}.svg series");
        match stem {
            "eps" | "y_journal" => {
                assert_eq!(count(&doc, "polyline", "marker"), 1, "{stem}: onset marker")
            }
            s if s.starts_with("orbit") => {
                assert_eq!(count(&doc, "polyline", "lobe"), 3, "{stem}: lobes")
            }
            _ => assert_eq!(
                doc.descendants()
                    .filter(|n| n.has_tag_name("image"))
                    .count(),
                1,
                "{stem}: colour map"
            ),
        }
        let png = std::fs::read(dir.join(format!("{stem}.png"))).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{stem}.png signature");
        let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
        let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
        let root = doc.root_element();
        assert_eq!(root.attribute("width"), Some(w.to_string().as_str()));
        assert_eq!(root.attribute("height"), Some(h.to_string().as_str()));
        let bad = layout::problems(&text);
        assert!(bad.is_empty(), "{stem}.svg: {bad:#?}");
        // Title, axis names and tick labels at least: the check saw the text.
        assert!(layout::text_boxes(&text).unwrap().len() >= 8, "{stem}.svg");
    }
    if keep.is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn stable_run_has_no_onset_marker() {
    let s = base(1e-4, 1.0);
    let cl = classify(&s);
    let dir = temp_dir("stable");
    plot_runup(&s, &cl, &[Bore::paper(), Bore::paper()], &dir).unwrap();
    let text = std::fs::read_to_string(dir.join("eps.svg")).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert_eq!(count(&doc, "polyline", "marker"), 0);
    assert_eq!(count(&doc, "polyline", "series"), 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every index runs once, on one of two threads, and the results come back in index order.
#[test]
fn on_two_threads_returns_every_result_in_index_order() {
    let threads = std::sync::Mutex::new(std::collections::HashSet::new());
    let r = super::on_two_threads(40, |k| {
        threads.lock().unwrap().insert(std::thread::current().id());
        std::thread::sleep(std::time::Duration::from_millis(1));
        k * k
    });
    assert_eq!(r, (0..40).map(|k| k * k).collect::<Vec<_>>());
    assert!(threads.lock().unwrap().len() <= 2);
    assert!(super::on_two_threads(0, |k| k).is_empty());
}

/// A job's panic reaches the caller, with its own message from either thread.
#[test]
fn on_two_threads_passes_a_panic_on() {
    let r = std::panic::catch_unwind(|| super::on_two_threads(5, |k| assert_ne!(k, 3)));
    assert!(r.is_err());
    let caller = std::thread::current().id();
    let r = std::panic::catch_unwind(|| {
        super::on_two_threads(40, |k| {
            std::thread::sleep(std::time::Duration::from_millis(1));
            if std::thread::current().id() != caller {
                panic!("figure {k} failed on the helper thread");
            }
        })
    });
    let panic = r.expect_err("the helper took an index and panicked");
    let message = panic
        .downcast_ref::<String>()
        .map(String::as_str)
        .unwrap_or("(not a message)");
    assert!(message.contains("on the helper thread"), "{message}");
}
