//! What a model implements. Nothing here knows about C pointers: the glue in `instance.rs` and the
//! export macro translate FMI calls into these methods.

use crate::variables::{ModelInfo, VarType};

/// Highest input derivative order the layer accepts through fmi2SetRealInputDerivatives.
pub const MAX_INPUT_DERIVATIVE_ORDER: usize = 3;

/// Current values of all variables, indexed by value reference per type.
#[derive(Clone, Debug, PartialEq)]
pub struct Store {
    pub reals: Vec<f64>,
    pub integers: Vec<i32>,
    pub booleans: Vec<bool>,
}

impl Store {
    /// Start values from the table (calculated variables start at 0 until the model writes them).
    pub fn from_info(info: &ModelInfo) -> Store {
        let mut s = Store {
            reals: vec![0.0; info.count(VarType::Real)],
            integers: vec![0; info.count(VarType::Integer)],
            booleans: vec![false; info.count(VarType::Boolean)],
        };
        for v in &info.variables {
            let x = v.start.unwrap_or(0.0);
            match v.var_type {
                VarType::Real => s.reals[v.vr as usize] = x,
                VarType::Integer => s.integers[v.vr as usize] = x as i32,
                VarType::Boolean => s.booleans[v.vr as usize] = x != 0.0,
            }
        }
        s
    }

    pub fn real(&self, vr: u32) -> f64 {
        self.reals[vr as usize]
    }
    pub fn integer(&self, vr: u32) -> i32 {
        self.integers[vr as usize]
    }
    pub fn boolean(&self, vr: u32) -> bool {
        self.booleans[vr as usize]
    }
}

/// The inputs inside a communication step: the Taylor polynomial the master set at the
/// communication point `t0` (values by fmi2SetReal, derivatives by fmi2SetRealInputDerivatives).
#[derive(Clone, Debug, PartialEq)]
pub struct Inputs {
    pub t0: f64,
    /// Real values at `t0`, indexed by value reference (all Real variables; only inputs are read).
    pub values: Vec<f64>,
    /// `derivatives[vr][k-1]` is the k-th time derivative at `t0`.
    pub derivatives: Vec<[f64; MAX_INPUT_DERIVATIVE_ORDER]>,
}

/// Value at `t0 + dt` of the Taylor polynomial with value `u0` and derivatives `d` at `t0`.
///
/// The one place this sum is written: an FMI 3.0 master that answers intermediate updates with it
/// (`fmi3::importer`) gives a model bit for bit the inputs an FMI 2.0 master gives through
/// fmi2SetRealInputDerivatives.
#[inline]
pub fn taylor_at(u0: f64, d: &[f64; MAX_INPUT_DERIVATIVE_ORDER], dt: f64) -> f64 {
    // Horner form of u0 + d1 dt + d2 dt^2/2 + d3 dt^3/6.
    u0 + dt * (d[0] + dt * (d[1] / 2.0 + dt * d[2] / 6.0))
}

/// Where a model reads its Real inputs inside a communication step.
///
/// FMI 2.0 gives a Taylor polynomial per input at the step's start ([`Inputs`]); an FMI 3.0 instance
/// with intermediate update asks the master for the values at the model's internal times.
pub trait StepInputs {
    /// Value of Real input `vr` at time `t` in [t0, t0 + h].
    fn real_at(&self, vr: u32, t: f64) -> f64;

    /// The input's Taylor polynomial over the whole step, (value, derivatives) at the step's start,
    /// when the inputs come as one (FMI 2.0, or FMI 3.0 holding them); `None` when they come at
    /// internal times (FMI 3.0 intermediate update). For models that integrate inputs exactly.
    fn polynomial(&self, _vr: u32) -> Option<(f64, [f64; MAX_INPUT_DERIVATIVE_ORDER])> {
        None
    }
}

/// Inputs a master gives at the model's internal times, inside a step (FMI 3.0 intermediate
/// update). `held` are the values the master set before the step.
pub trait IntermediateInputs {
    fn real_at(&self, held: &Inputs, vr: u32, t: f64) -> f64;
}

/// A step's inputs when a master answers at internal times: no polynomial over the step.
pub(crate) struct AskedInputs<'a> {
    pub held: &'a Inputs,
    pub master: &'a dyn IntermediateInputs,
}

impl StepInputs for AskedInputs<'_> {
    fn real_at(&self, vr: u32, t: f64) -> f64 {
        self.master.real_at(self.held, vr, t)
    }
}

impl StepInputs for Inputs {
    fn real_at(&self, vr: u32, t: f64) -> f64 {
        Inputs::real_at(self, vr, t)
    }

    fn polynomial(&self, vr: u32) -> Option<(f64, [f64; MAX_INPUT_DERIVATIVE_ORDER])> {
        Some((self.values[vr as usize], self.derivatives[vr as usize]))
    }
}

impl Inputs {
    /// Value of Real input `vr` at time `t` from the Taylor polynomial about `t0`.
    pub fn real_at(&self, vr: u32, t: f64) -> f64 {
        let vr = vr as usize;
        taylor_at(self.values[vr], &self.derivatives[vr], t - self.t0)
    }
    /// First time derivative of Real input `vr` at time `t`.
    pub fn real_rate_at(&self, vr: u32, t: f64) -> f64 {
        let vr = vr as usize;
        let dt = t - self.t0;
        let d = &self.derivatives[vr];
        d[0] + dt * (d[1] + dt * d[2] / 2.0)
    }
}

/// Where a model sends its log messages (the instance's logger, with category filtering).
pub trait Log {
    /// Debug message in a model category (e.g. "logSolverStatistics"); shown only when enabled.
    fn debug(&mut self, category: &str, message: &str);
    /// A warning (always shown).
    fn warning(&mut self, message: &str);
    /// Whether a debug message in `category` would be shown now. A model that builds a message
    /// at every step asks first: formatting the rotor's statistics took ~0.2 s of path 1's 55 000
    /// steps with logging off (its time in the FMU 1.47 -> 1.29 s). Without an answer, yes.
    fn enabled(&self, category: &str) -> bool {
        let _ = category;
        true
    }
}

/// Result of a model's step.
#[derive(Clone, Debug, PartialEq)]
pub enum StepOutcome {
    Ok,
    /// The step could not be completed; the model reached `reached_time` and keeps that state.
    /// The instance reports Discard and its last successful time = `reached_time`
    /// (fmi2LastSuccessfulTime; FMI 3.0's fmi3DoStep returns it).
    Discard {
        reason: String,
        reached_time: f64,
    },
    /// Unrecoverable: the instance goes to the error state.
    Error(String),
}

/// A model behind an FMU. The layer owns a `Store` with all variable values; the model is built from
/// the parameter values when initialization mode is left (or earlier, when outputs are read in
/// initialization mode) and then advanced by `do_step`.
pub trait Model: Clone + Send + Sized + 'static {
    /// The model's interface (built once per instance; keep it cheap).
    fn info() -> ModelInfo;

    /// Builds the model from the parameter values in `store` (validate them here: a bad parameter
    /// returns a clear message, the instance reports fmi2Error). Inputs in `store` hold their values
    /// at the start time. `resources` is the FMU's unpacked resources folder, where the importer
    /// gave one (a model may read data files there).
    fn new(
        store: &Store,
        start_time: f64,
        resources: Option<&std::path::Path>,
        log: &mut dyn Log,
    ) -> Result<Self, String>;

    /// Refuses a start time the model cannot take at the call that gives it (fmi2SetupExperiment,
    /// fmi3EnterInitializationMode) instead of when initialization ends, which is too late for a
    /// master to tell which of its calls was wrong. The layer has checked that it is finite; the
    /// default takes any.
    fn check_start_time(_start_time_s: f64) -> Result<(), String> {
        Ok(())
    }

    /// Refuses a tolerance of fmi2SetupExperiment (fmi3EnterInitializationMode) that the model's
    /// error control cannot reach, at that call, naming the tolerance: otherwise the model fails
    /// its first step with a message about its solver, not about the master's setting. The layer
    /// has checked that it lies in (0, 1); the default takes any.
    fn check_tolerance(_tolerance: f64) -> Result<(), String> {
        Ok(())
    }

    /// Advances from `t` to `t + h` with inputs following `inputs`. Never panics on bad data:
    /// returns `Discard` or `Error` with a reason.
    fn do_step(
        &mut self,
        t: f64,
        h: f64,
        inputs: &dyn StepInputs,
        log: &mut dyn Log,
    ) -> StepOutcome;

    /// Writes all outputs (and other calculated variables) into `store`.
    fn write_outputs(&self, store: &mut Store);

    /// `order`-th time derivative of Real output `vr` at the current time, if the model provides it.
    fn output_derivative(&self, vr: u32, order: i32) -> Option<f64>;

    /// Serialized model state; with `deserialize` it must continue bit-identically.
    fn serialize(&self) -> Vec<u8>;
    fn deserialize(bytes: &[u8]) -> Result<Self, String>;
}
