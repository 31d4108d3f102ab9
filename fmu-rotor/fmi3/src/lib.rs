//! `target/fmu/fmi3/rotor.fmu`: the rotor exported as FMI 3.0 Co-Simulation. The physics and the
//! variable table are `fmu_rotor`'s (built without its fmi2 `fmu` feature, so this library
//! exports the 75 fmi3* functions only).

use fmu_rotor::shell::RotorFmu;

fmi3::export_fmu!(RotorFmu);
