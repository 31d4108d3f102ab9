//! Why each function this FMU does not provide returns fmi3Error (logged with the call).

use super::not_provided;
use crate::types::*;
use fmi_core::model::Model;

pub const MODEL_EXCHANGE: &str = "this FMU supports Co-Simulation only (no <ModelExchange>)";
pub const SCHEDULED_EXECUTION: &str =
    "this FMU supports Co-Simulation only (no <ScheduledExecution>)";
pub const EVENT_MODE: &str = "this FMU has no Event Mode (hasEventMode=\"false\")";
pub const CLOCKS: &str = "this FMU has no clocks";
pub const CONFIGURATION_MODE: &str =
    "this FMU has no structural parameters, hence no Configuration Mode";
pub const DIRECTIONAL_DERIVATIVES: &str =
    "directional derivatives are not provided (providesDirectionalDerivatives=\"false\")";
pub const ADJOINT_DERIVATIVES: &str =
    "adjoint derivatives are not provided (providesAdjointDerivatives=\"false\")";
pub const VARIABLE_DEPENDENCIES: &str = "per-element dependencies are not provided (providesPerElementDependencies=\"false\"); read <ModelStructure> in modelDescription.xml";

/// fmi3Get/Set of a type the variable table has no variables of.
pub fn no_variables<M: Model>(c: fmi3Instance, function: &str, type_name: &str) -> fmi3Status {
    not_provided::<M>(
        c,
        function,
        &format!("this FMU has no {type_name} variables"),
    )
}
