//! The crate graph keeps the layers apart (ARCHITECTURE.md): the generic co-simulation library
//! knows no physics and no application, the rotor does not link the air film, and the shared
//! bearing description depends on neither physics crate. Read from the Cargo.toml files, with
//! path dependencies followed transitively (normal and build dependencies; dev-dependencies may
//! cross layers for tests).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Workspace crate name -> (folder, [(dependency name, path if a path dependency)]).
type Graph = BTreeMap<String, (PathBuf, Vec<(String, Option<PathBuf>)>)>;

fn manifest(dir: &Path) -> toml::Table {
    let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
    text.parse().unwrap()
}

fn graph() -> Graph {
    let root = integration_tests::workspace_root();
    let ws = manifest(&root);
    let members = ws["workspace"]["members"].as_array().unwrap();
    let mut g = Graph::new();
    for m in members {
        let dir = root.join(m.as_str().unwrap());
        let t = manifest(&dir);
        let name = t["package"]["name"].as_str().unwrap().to_string();
        let mut deps = vec![];
        for section in ["dependencies", "build-dependencies"] {
            if let Some(d) = t.get(section).and_then(|d| d.as_table()) {
                for (dep, spec) in d {
                    let path = spec
                        .get("path")
                        .and_then(|p| p.as_str())
                        .map(|p| dir.join(p).canonicalize().unwrap());
                    deps.push((dep.clone(), path));
                }
            }
        }
        g.insert(name, (dir.canonicalize().unwrap(), deps));
    }
    g
}

/// Every crate `name` links, directly or through workspace crates (by name).
fn closure(g: &Graph, name: &str) -> BTreeSet<String> {
    let by_dir: BTreeMap<&PathBuf, &String> = g.iter().map(|(n, (d, _))| (d, n)).collect();
    let mut seen = BTreeSet::new();
    let mut todo = vec![name.to_string()];
    while let Some(n) = todo.pop() {
        for (dep, path) in &g[&n].1 {
            let dep_name = path
                .as_ref()
                .and_then(|p| by_dir.get(p))
                .map(|s| s.to_string())
                .unwrap_or_else(|| dep.clone());
            if seen.insert(dep_name.clone()) && g.contains_key(&dep_name) {
                todo.push(dep_name);
            }
        }
    }
    seen
}

#[test]
fn the_cosim_library_links_no_physics_and_no_application_crates() {
    let g = graph();
    let links = closure(&g, "cosim");
    assert!(links.contains("fmi2"), "{links:?}");
    for forbidden in [
        "fmu-airfilm",
        "fmu-rotor",
        "bearing",
        "master",
        "clap",
        "parquet",
        "plotters",
        "rustfft",
    ] {
        assert!(
            !links.contains(forbidden),
            "cosim links {forbidden}: {links:?}"
        );
    }
}

/// The FMI 3.0 layer is glue over the FMI core's model layer, a sibling of the FMI 2.0 glue, not
/// built on it; it knows no model. Each twin links its own model crate only; the physics crates
/// do not know FMI 3.0 exists. The co-simulation library links it for its importer (it drives
/// FMUs of either version).
#[test]
fn the_fmi3_layer_links_no_model_and_each_twin_only_its_own() {
    let g = graph();
    let fmi3 = closure(&g, "fmi3");
    assert!(fmi3.contains("fmi-core"), "{fmi3:?}");
    for forbidden in [
        "fmi2",
        "fmu-airfilm",
        "fmu-rotor",
        "bearing",
        "cosim",
        "master",
    ] {
        assert!(!fmi3.contains(forbidden), "fmi3 links {forbidden}");
    }
    let film3 = closure(&g, "fmu-airfilm-fmi3");
    let rotor3 = closure(&g, "fmu-rotor-fmi3");
    assert!(
        film3.contains("fmu-airfilm") && !film3.contains("fmu-rotor"),
        "{film3:?}"
    );
    assert!(
        rotor3.contains("fmu-rotor") && !rotor3.contains("fmu-airfilm"),
        "{rotor3:?}"
    );
    for model in ["fmu-airfilm", "fmu-rotor"] {
        assert!(!closure(&g, model).contains("fmi3"), "{model} links fmi3");
    }
    assert!(closure(&g, "cosim").contains("fmi3"));
}

#[test]
fn the_rotor_does_not_link_the_air_film_and_both_share_the_bearing_crate() {
    let g = graph();
    let rotor = closure(&g, "fmu-rotor");
    let film = closure(&g, "fmu-airfilm");
    assert!(!rotor.contains("fmu-airfilm"), "{rotor:?}");
    assert!(!film.contains("fmu-rotor"), "{film:?}");
    assert!(rotor.contains("bearing") && film.contains("bearing"));
    let bearing = closure(&g, "bearing");
    for forbidden in ["fmu-airfilm", "fmu-rotor", "fmi2", "cosim", "master"] {
        assert!(!bearing.contains(forbidden), "bearing links {forbidden}");
    }
}

#[test]
fn the_application_sits_on_the_library_and_the_physics() {
    let g = graph();
    let app = closure(&g, "master");
    for needed in ["cosim", "bearing", "fmu-airfilm", "fmu-rotor"] {
        assert!(app.contains(needed), "master does not link {needed}");
    }
    // The check itself can fail: a graph with an edge cosim -> fmu-rotor is caught.
    let mut bad = g.clone();
    let rotor_dir = bad["fmu-rotor"].0.clone();
    bad.get_mut("cosim")
        .unwrap()
        .1
        .push(("fmu-rotor".into(), Some(rotor_dir)));
    assert!(closure(&bad, "cosim").contains("bearing"));
}

/// The application's libraries each do one job: the periodic-orbit numerics know no rotor and
/// no FMI, the run-up analysis knows the bearing description only, the figures draw what the
/// analysis gives and know no FMU; none of them links the application.
#[test]
fn the_applications_libraries_know_only_what_their_job_needs() {
    let g = graph();
    let orbits = closure(&g, "periodic-orbits");
    for forbidden in [
        "bearing",
        "fmi2",
        "fmi3",
        "cosim",
        "fmu-rotor",
        "fmu-airfilm",
        "master",
    ] {
        assert!(
            !orbits.contains(forbidden),
            "periodic-orbits links {forbidden}"
        );
    }
    let analysis = closure(&g, "runup-analysis");
    assert!(analysis.contains("bearing"), "{analysis:?}");
    for forbidden in [
        "fmi2",
        "cosim",
        "fmu-rotor",
        "fmu-airfilm",
        "figures",
        "master",
        "plotters",
    ] {
        assert!(
            !analysis.contains(forbidden),
            "runup-analysis links {forbidden}"
        );
    }
    let figures = closure(&g, "figures");
    assert!(figures.contains("runup-analysis"), "{figures:?}");
    for forbidden in ["fmu-rotor", "fmu-airfilm", "master", "periodic-orbits"] {
        assert!(!figures.contains(forbidden), "figures links {forbidden}");
    }
    let app = closure(&g, "master");
    for needed in ["periodic-orbits", "runup-analysis", "figures"] {
        assert!(app.contains(needed), "master does not link {needed}");
    }
}

/// The FMI core is below both standards' layers and knows neither: both link it, it links no
/// workspace crate; the co-simulation library drives slaves through it.
#[test]
fn the_fmi_core_knows_no_standard_and_both_layers_share_it() {
    let g = graph();
    let core = closure(&g, "fmi-core");
    for other in g.keys() {
        assert!(!core.contains(other), "fmi-core links {other}");
    }
    for layer in ["fmi2", "fmi3", "cosim"] {
        assert!(
            closure(&g, layer).contains("fmi-core"),
            "{layer} does not link fmi-core"
        );
    }
}

/// The flexible-rotor crate is physics below the rotor FMU: it knows no FMI, no air film, no
/// co-simulation and not the application; the rotor and the application link it.
#[test]
fn the_shaft_crate_knows_no_fmi_and_no_air_film() {
    let g = graph();
    let shaft = closure(&g, "shaft");
    for forbidden in [
        "fmi-core",
        "fmi2",
        "fmi3",
        "cosim",
        "fmu-rotor",
        "fmu-airfilm",
        "master",
    ] {
        assert!(!shaft.contains(forbidden), "shaft links {forbidden}");
    }
    for user in ["fmu-rotor", "master"] {
        assert!(
            closure(&g, user).contains("shaft"),
            "{user} does not link shaft"
        );
    }
}

/// The design search knows no AirRing crate: it chooses points in a design space; what a point
/// means (an FMU parameter, a run-up) is the application's.
#[test]
fn the_design_search_knows_no_airring_crate() {
    let g = graph();
    let search = closure(&g, "design-search");
    for other in g.keys().filter(|k| *k != "design-search") {
        assert!(!search.contains(other), "design-search links {other}");
    }
}

/// The models implement the FMI core's model layer; each standard's glue is linked only to export
/// it (the FMI 2.0 glue behind the model crate's `fmu` feature, the FMI 3.0 glue by the twin), so
/// the master and the tests link the physics without either standard's C symbols.
#[test]
fn the_models_implement_the_core_and_link_a_standard_only_to_export() {
    let root = integration_tests::workspace_root();
    for model in ["fmu-airfilm", "fmu-rotor", "tests/oscillator"] {
        let t = manifest(&root.join(model));
        let deps = t["dependencies"].as_table().unwrap();
        assert!(
            deps.contains_key("fmi-core"),
            "{model} does not link fmi-core"
        );
        assert!(!deps.contains_key("fmi3"), "{model} links fmi3");
        let fmi2 = &deps["fmi2"];
        assert_eq!(
            fmi2.get("optional").and_then(|o| o.as_bool()),
            Some(true),
            "{model}: fmi2 must be optional (feature fmu)"
        );
        let fmu = t["features"]["fmu"].as_array().unwrap();
        assert!(
            fmu.iter().any(|f| f.as_str() == Some("dep:fmi2")),
            "{model}: {fmu:?}"
        );
    }
}
