//! `target/fmu/fmi3/airfilm.fmu`: the air film exported as FMI 3.0 Co-Simulation. The physics and
//! the variable table are `fmu_airfilm`'s (built without its fmi2 `fmu` feature, so this library
//! exports the 75 fmi3* functions only).

use fmu_airfilm::shell::AirFilmFmu;

fmi3::export_fmu!(AirFilmFmu);
