//! The checked-in modelDescriptions/*.xml are exactly what the variable tables generate, and the
//! tables keep their invariants (dense value references, start values, known units).

use fmi2::Model;
use integration_tests::workspace_root;

fn check(info: fmi2::ModelInfo) {
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
