//! The checked-in modelDescriptions/*.xml are exactly what the variable tables generate, and the
//! tables keep their invariants (dense value references, start values, known units).

use fmi_core::model::Model;
use integration_tests::workspace_root;

fn check(info: fmi_core::variables::ModelInfo) {
    info.check().unwrap();
    let path = workspace_root()
        .join("modelDescriptions")
        .join(format!("{}.xml", info.model_identifier));
    let on_disk =
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        on_disk == fmi2::xml::model_description(&info),
        "{} differs from the generated one: run `cargo xtask descriptions`",
        path.display()
    );
}

#[test]
fn airfilm_description_is_generated() {
    check(fmu_airfilm::shell::AirFilmFmu::info());
}

#[test]
fn rotor_description_is_generated() {
    check(fmu_rotor::shell::RotorFmu::info());
}

#[test]
fn interface_names_fixed_by_the_spec_exist() {
    let film = fmu_airfilm::shell::AirFilmFmu::info();
    for name in [
        "dx",
        "dy",
        "vx",
        "vy",
        "omega",
        "Fx",
        "Fy",
        "r",
        "b",
        "C",
        "dH",
        "phi_t",
        "alpha",
        "eta",
        "p_a",
        "n_lobes",
        "n_elem_phi",
        "n_elem_z",
        "mesh_grading",
        "h_con_rel",
        "c_con",
    ] {
        assert!(film.by_name(name).is_some(), "airfilm lacks {name}");
    }
    let rotor = fmu_rotor::shell::RotorFmu::info();
    for name in [
        "F_C_x", "F_C_y", "F_T_x", "F_T_y", "dx_C", "dy_C", "vx_C", "vy_C", "dx_T", "dy_T", "vx_T",
        "vy_T", "omega", "m", "J_t", "J_p", "z_cm", "z_JC", "z_JT", "m_R_C", "m_R_T", "c_C", "d_C",
        "c_T", "d_T", "g", "f_max", "t_ramp",
    ] {
        assert!(rotor.by_name(name).is_some(), "rotor lacks {name}");
    }
}

/// Every output declares that it depends directly on no input (`dependencies=""`), so a master
/// that checks sees no algebraic loop between the rotor and its films (before: no declaration,
/// which FMI reads as "depends on every input"). fmu_airfilm_abi.rs and fmi_layer.rs check the
/// behaviour behind it: an input set in step mode changes no output before the next step.
#[test]
fn outputs_declare_no_direct_dependency_on_inputs() {
    for info in [
        fmu_airfilm::shell::AirFilmFmu::info(),
        fmu_rotor::shell::RotorFmu::info(),
    ] {
        let xml = fmi2::xml::model_description(&info);
        let outputs = xml
            .split("<Outputs>")
            .nth(1)
            .and_then(|s| s.split("</Outputs>").next())
            .expect("an Outputs element");
        let unknowns: Vec<&str> = outputs.lines().filter(|l| l.contains("<Unknown")).collect();
        let n_outputs = info
            .variables
            .iter()
            .filter(|v| v.causality == fmi_core::variables::Causality::Output)
            .count();
        assert_eq!(unknowns.len(), n_outputs);
        for u in unknowns {
            assert!(
                u.contains(r#"dependencies="""#),
                "{}: {u}",
                info.model_identifier
            );
        }
    }
}
