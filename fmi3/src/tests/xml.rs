//! The FMI 3.0 description parses, has unique value references and matches the FMI 2.0 one.

use super::lag::Lag;
use crate::value_refs::{to_fmi3, TIME_VR};
use fmi_core::model::Model;
use std::collections::HashSet;

#[test]
fn description_is_well_formed_and_matches_fmi2() {
    let info = Lag::info();
    let text = crate::xml::model_description(&info);
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "fmiModelDescription");
    assert_eq!(root.attribute("fmiVersion"), Some("3.0"));
    assert_eq!(
        root.attribute("instantiationToken"),
        Some(info.guid().as_str())
    );
    assert!(info.guid().starts_with('{') && info.guid().ends_with('}'));

    let child = |name: &str| {
        root.children()
            .find(|n| n.has_tag_name(name))
            .unwrap_or_else(|| panic!("no <{name}>"))
    };
    let cs = child("CoSimulation");
    for (attr, value) in [
        ("modelIdentifier", "lag"),
        ("canHandleVariableCommunicationStepSize", "true"),
        ("canGetAndSetFMUState", "true"),
        ("canSerializeFMUState", "true"),
        ("providesIntermediateUpdate", "true"),
        ("canReturnEarlyAfterIntermediateUpdate", "false"),
        ("mightReturnEarlyFromDoStep", "true"),
        ("hasEventMode", "false"),
        ("maxOutputDerivativeOrder", "1"),
    ] {
        assert_eq!(cs.attribute(attr), Some(value), "{attr}");
    }
    assert!(root.children().all(|n| !n.has_tag_name("ModelExchange")));

    let vars: Vec<_> = child("ModelVariables")
        .children()
        .filter(|n| n.is_element())
        .collect();
    let vrs: Vec<u32> = vars
        .iter()
        .map(|v| v.attribute("valueReference").unwrap().parse().unwrap())
        .collect();
    assert_eq!(
        vrs.iter().collect::<HashSet<_>>().len(),
        vrs.len(),
        "unique value references"
    );
    let independent: Vec<_> = vars
        .iter()
        .filter(|v| v.attribute("causality") == Some("independent"))
        .collect();
    assert_eq!(independent.len(), 1);
    assert_eq!(
        independent[0].attribute("valueReference"),
        Some(TIME_VR.to_string().as_str())
    );
    assert_eq!(independent[0].attribute("start"), None);

    // Same variables as the FMI 2.0 description, attribute by attribute.
    let text2 = fmi2::xml::model_description(&info);
    let doc2 = roxmltree::Document::parse(&text2).unwrap();
    let svs: Vec<_> = doc2
        .descendants()
        .filter(|n| n.has_tag_name("ScalarVariable"))
        .collect();
    assert_eq!(svs.len() + 1, vars.len());
    for (sv, v3) in svs.iter().zip(&vars[1..]) {
        let typed = sv.children().find(|n| n.is_element()).unwrap();
        let fmi2_type = typed.tag_name().name();
        let fmi3_type = match fmi2_type {
            "Real" => "Float64",
            "Integer" => "Int32",
            _ => fmi2_type,
        };
        assert_eq!(v3.tag_name().name(), fmi3_type);
        for a in ["name", "causality", "variability", "initial", "description"] {
            assert_eq!(
                sv.attribute(a),
                v3.attribute(a),
                "{a} of {:?}",
                sv.attribute("name")
            );
        }
        for a in ["min", "max", "start"] {
            assert_eq!(
                typed.attribute(a),
                v3.attribute(a),
                "{a} of {:?}",
                sv.attribute("name")
            );
        }
        // Unit and display unit come through the declared type (TypeDefinitions).
        let declared = v3.attribute("declaredType").map(|t| {
            let ty = child("TypeDefinitions")
                .children()
                .find(|n| n.attribute("name") == Some(t))
                .unwrap_or_else(|| panic!("type {t} undefined"));
            (ty.attribute("unit"), ty.attribute("displayUnit"))
        });
        assert_eq!(
            declared.unwrap_or((None, None)),
            (typed.attribute("unit"), typed.attribute("displayUnit")),
            "units of {:?}",
            sv.attribute("name")
        );
        let var = info.by_name(sv.attribute("name").unwrap()).unwrap();
        let vr3: u32 = v3.attribute("valueReference").unwrap().parse().unwrap();
        assert_eq!(vr3, to_fmi3(var.var_type, var.vr));
    }

    // Every unit used is defined, `s` included (the unit of time).
    let units: HashSet<&str> = child("UnitDefinitions")
        .children()
        .filter_map(|u| u.attribute("name"))
        .collect();
    for t in child("TypeDefinitions")
        .children()
        .filter(|n| n.is_element())
    {
        let u = t.attribute("unit").unwrap();
        assert!(units.contains(u), "unit {u} undefined");
    }

    // Outputs in ModelStructure: every output, no direct dependencies; InitialUnknowns exist.
    let ms = child("ModelStructure");
    let outputs: Vec<u32> = ms
        .children()
        .filter(|n| n.has_tag_name("Output"))
        .map(|n| {
            assert_eq!(n.attribute("dependencies"), Some(""));
            n.attribute("valueReference").unwrap().parse().unwrap()
        })
        .collect();
    let expected: Vec<u32> = vars
        .iter()
        .filter(|v| v.attribute("causality") == Some("output"))
        .map(|v| v.attribute("valueReference").unwrap().parse().unwrap())
        .collect();
    assert_eq!(outputs, expected);
    let initial = ms
        .children()
        .filter(|n| n.has_tag_name("InitialUnknown"))
        .count();
    assert_eq!(initial, expected.len());
    // Element order of the schema: Output before InitialUnknown.
    let tags: Vec<&str> = ms
        .children()
        .filter(|n| n.is_element())
        .map(|n| n.tag_name().name())
        .collect();
    assert!(tags
        .windows(2)
        .all(|w| !(w[0] == "InitialUnknown" && w[1] == "Output")));
}
