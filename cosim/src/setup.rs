//! From a system file to instantiated, initialized FMUs wired together.

use crate::algorithm::{AlgorithmConfig, CoSim, Scheme};
use crate::number::short;
use crate::slave::{Fmu, LoadedFmus, Slave};
use crate::step_control::StepControl;
use crate::step_plan::LongSteps;
use crate::subsystem::{Link, Subsystem};
use crate::system::{split_port, split_quantity, System, SystemError};
use fmi_core::description::ModelDescription;
use fmi_core::variables::{Causality, VarType};
use fmi_core::LogHandler;

/// More macro steps than this in one run are refused (10^9 steps of the fastest FMUs here take
/// days; the usual cause is a unit typo).
pub const MAX_MACRO_STEPS: f64 = 1e9;

/// More output rows than this are refused (10^8 rows of a run-up are ~60 GB of CSV).
pub const MAX_OUTPUT_ROWS: f64 = 1e8;

/// A ready co-simulation and the settings it was built with.
pub struct Built {
    pub cosim: CoSim,
    pub macro_step_s: f64,
    /// Longer macro steps in given windows (None: every step is `macro_step_s`).
    pub long_steps: Option<LongSteps>,
    pub stop_time_s: f64,
    pub output_interval_s: f64,
    /// The variables the system file asks to record, in column order.
    pub recorded: Vec<Recorded>,
    /// (instance, GUID of its FMU), in subsystem order: part of a run's identity.
    pub guids: Vec<(String, String)>,
}

/// A recorded variable: one column of the time series.
#[derive(Clone, Debug, PartialEq)]
pub struct Recorded {
    /// Index of its subsystem.
    pub subsystem: usize,
    /// Its value reference in that FMU.
    pub vr: u32,
    /// "instance.variable".
    pub name: String,
    /// Its unit as the FMU declares it ("" without one).
    pub unit: String,
}

/// A parameter value of a system file as the FMU receives it (Reals in the variable's SI unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamValue {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

/// Checks a `parameters.NAME = value` entry against the FMU's description and converts it (a string
/// "number unit" through the variable's declared display units); returns the value reference too.
pub fn parameter_value(
    sys: &System,
    md: &ModelDescription,
    inst: &str,
    name: &str,
    value: &toml::Spanned<toml::Value>,
) -> Result<(u32, ParamValue), SystemError> {
    let field = format!("fmu '{inst}' parameters.{name}");
    let var = md.variable(name).ok_or_else(|| {
        sys.error_at(
            value,
            &field,
            format!("'{}' has no variable '{name}'", md.model_name),
        )
    })?;
    if !matches!(var.causality, Causality::Parameter | Causality::Input) {
        return Err(sys.error_at(
            value,
            &field,
            format!("'{name}' is a {} and cannot be set", var.causality.as_str()),
        ));
    }
    let v = match (var.var_type, value.get_ref()) {
        (VarType::Boolean, toml::Value::Boolean(b)) => ParamValue::Boolean(*b),
        (VarType::Integer, toml::Value::Integer(i)) => ParamValue::Integer(
            i32::try_from(*i).map_err(|_| sys.error_at(value, &field, "integer out of range"))?,
        ),
        (VarType::Real, v) => {
            let si = match v {
                toml::Value::Float(x) => *x,
                toml::Value::Integer(i) => *i as f64,
                toml::Value::String(s) => {
                    let (num, unit) = split_quantity(s).ok_or_else(|| {
                        sys.error_at(value, &field, format!("'{s}' is not 'number unit'"))
                    })?;
                    if unit.is_empty() {
                        num
                    } else {
                        let (factor, offset) = md.to_unit(var, unit).ok_or_else(|| {
                            let mut units: Vec<String> = var.unit.iter().cloned().collect();
                            if let Some(u) =
                                md.units.iter().find(|u| Some(&u.name) == var.unit.as_ref())
                            {
                                units.extend(u.display_units.iter().map(|d| d.0.clone()));
                            }
                            sys.error_at(
                                value,
                                &field,
                                format!(
                                    "unit '{unit}' does not fit '{name}' (accepted: {})",
                                    units.join(", ")
                                ),
                            )
                        })?;
                        (num - offset) / factor
                    }
                }
                other => {
                    return Err(sys.error_at(
                        value,
                        &field,
                        format!("expected a number, found {other}"),
                    ))
                }
            };
            if !si.is_finite() {
                return Err(sys.error_at(value, &field, format!("value {si} is not finite")));
            }
            ParamValue::Real(si)
        }
        (t, other) => {
            return Err(sys.error_at(
                value,
                &field,
                format!("expected a {} value, found {other}", t.as_str()),
            ))
        }
    };
    Ok((var.vr, v))
}

fn set_parameter(
    sys: &System,
    fmu: &Fmu,
    inst: &str,
    sub: &Slave,
    name: &str,
    value: &toml::Spanned<toml::Value>,
) -> Result<(), SystemError> {
    let (vr, v) = parameter_value(sys, fmu.description(), inst, name, value)?;
    match v {
        ParamValue::Real(x) => sub.set_real(&[vr], &[x]),
        ParamValue::Integer(i) => sub.set_integer(&[vr], &[i]),
        ParamValue::Boolean(b) => sub.set_boolean(&[vr], &[b]),
    }
    .map_err(|e| {
        sys.error_at(
            value,
            &format!("fmu '{inst}' parameters.{name}"),
            format!("the FMU refused the value ({e}; see its log above)"),
        )
    })
}

/// Err unless the system file's output interval (if it gives one) is a whole number of macro
/// steps. The library writes a row at each macro point where an output is due, so any interval
/// runs; an application that promises evenly spaced rows (airring's `run`, as its `runup`) checks
/// this first: 70 us at a 50 us step gave rows 50 and 100 us apart.
pub fn check_output_interval_whole(sys: &System) -> Result<(), SystemError> {
    // The grid's own errors first: a macro step longer than the run (a bare `macro_step = 50`
    // is 50 s) was reported as an output interval that is not a whole number of it.
    let (macro_step_s, _, interval_s) = time_grid(sys)?;
    let Some(v) = &sys.file.output.interval else {
        return Ok(());
    };
    let per_row = (interval_s / macro_step_s).round();
    if per_row < 1.0 || (interval_s - per_row * macro_step_s).abs() > 1e-9 * interval_s {
        return Err(sys.error_at(
            v,
            "output.interval",
            format!(
                "{} s is not a whole number of macro steps ({} s): rows are written at macro \
                 steps only",
                short(interval_s),
                short(macro_step_s)
            ),
        ));
    }
    Ok(())
}

/// Loads, instantiates, parameterizes, connects and initializes everything in the system file.
/// The system's time grid [s]: macro step, stop time, output interval (ten macro steps where it
/// gives none), checked to be one a run can cover.
fn time_grid(sys: &System) -> Result<(f64, f64, f64), SystemError> {
    let f = &sys.file;
    let alg = &f.algorithm;
    let macro_step_s = sys.seconds(&alg.macro_step, "algorithm.macro_step")?;
    let stop_time_s = sys.seconds(&alg.stop_time, "algorithm.stop_time")?;
    let output_interval_s = match &f.output.interval {
        Some(v) => sys.seconds(v, "output.interval")?,
        None => macro_step_s * 10.0,
    };
    // The time grid must be something a run can cover: at least one macro step, and not more
    // steps or output rows than any run could store (a typo such as "1e-300 s" would otherwise
    // write gigabytes of identical rows, or hang).
    if macro_step_s > stop_time_s {
        return Err(sys.error_at(
            &alg.macro_step,
            "algorithm.macro_step",
            format!(
                "{} s is longer than the stop time {} s",
                short(macro_step_s),
                short(stop_time_s)
            ),
        ));
    }
    if stop_time_s / macro_step_s > MAX_MACRO_STEPS {
        return Err(sys.error_at(
            &alg.macro_step,
            "algorithm.macro_step",
            format!(
                "{} s gives {:.3e} macro steps to {} s (at most {MAX_MACRO_STEPS:e})",
                short(macro_step_s),
                stop_time_s / macro_step_s,
                short(stop_time_s)
            ),
        ));
    }
    if stop_time_s / output_interval_s > MAX_OUTPUT_ROWS {
        let field = "output.interval";
        let msg = format!(
            "{} s gives {:.3e} output rows to {} s (at most {MAX_OUTPUT_ROWS:e})",
            short(output_interval_s),
            stop_time_s / output_interval_s,
            short(stop_time_s)
        );
        return Err(match &f.output.interval {
            Some(v) => sys.error_at(v, field, msg),
            None => SystemError(format!("{}: {field}: {msg}", sys.path.display())),
        });
    }
    Ok((macro_step_s, stop_time_s, output_interval_s))
}

pub fn build(sys: &System, log: LogHandler) -> Result<Built, SystemError> {
    let f = &sys.file;
    let alg = &f.algorithm;
    let (macro_step_s, stop_time_s, output_interval_s) = time_grid(sys)?;
    let long_steps = match &alg.long_steps {
        None => None,
        Some(e) => {
            let l = e.get_ref();
            let windows = l.windows.iter().map(|w| (w[0], w[1])).collect();
            Some(
                LongSteps::new(l.factor, windows)
                    .map_err(|msg| sys.error_at(e, "algorithm.long_steps", msg))?,
            )
        }
    };
    let scheme = match alg.kind.get_ref().as_str() {
        "gauss-seidel" => Scheme::GaussSeidel,
        "jacobi" => Scheme::Jacobi,
        other => {
            return Err(sys.error_at(
                &alg.kind,
                "algorithm.kind",
                format!("'{other}' is neither 'gauss-seidel' nor 'jacobi'"),
            ))
        }
    };
    for (o, name) in [
        (&alg.extrapolation_order, "algorithm.extrapolation_order"),
        (&alg.interpolation_order, "algorithm.interpolation_order"),
    ] {
        if *o.get_ref() > 2 {
            return Err(sys.error_at(o, name, "polynomial order must be 0, 1 or 2"));
        }
    }

    let mut loaded = LoadedFmus::default();
    let mut fmus = Vec::new();
    let mut subs: Vec<Subsystem> = Vec::new();
    for e in &f.fmu {
        let name = e.name.get_ref().clone();
        if subs.iter().any(|s| s.name == name) {
            return Err(sys.error_at(
                &e.name,
                "fmu.name",
                format!("instance name '{name}' is used twice"),
            ));
        }
        let path = sys.resolve(e.path.get_ref());
        let fmu = loaded
            .get(&path)
            .map_err(|err| sys.error_at(&e.path, "fmu.path", err))?;
        let slave = fmu
            .instantiate(&name, false, log.clone())
            .map_err(|err| sys.error_at(&e.name, "fmu", err))?;
        slave
            .setup_experiment(None, 0.0, Some(stop_time_s))
            .map_err(|err| sys.error_at(&e.name, "fmu", err))?;
        slave
            .enter_initialization_mode()
            .map_err(|err| sys.error_at(&e.name, "fmu", err))?;
        for (pname, value) in &e.parameters {
            set_parameter(sys, &fmu, &name, &slave, pname, value)?;
        }
        subs.push(Subsystem::new(name, slave, fmu.description()));
        fmus.push(fmu);
    }

    let names: Vec<String> = subs.iter().map(|s| s.name.clone()).collect();
    let find = |port: &toml::Spanned<String>,
                field: &str,
                want: Causality|
     -> Result<(usize, u32), SystemError> {
        let (inst, var) = split_port(port.get_ref())
            .ok_or_else(|| sys.error_at(port, field, "expected 'instance.variable'"))?;
        let i = names
            .iter()
            .position(|s| s == inst)
            .ok_or_else(|| sys.error_at(port, field, format!("no FMU instance '{inst}'")))?;
        let v = fmus[i].description().variable(var).ok_or_else(|| {
            sys.error_at(port, field, format!("'{inst}' has no variable '{var}'"))
        })?;
        if v.causality != want || v.var_type != VarType::Real {
            return Err(sys.error_at(
                port,
                field,
                format!("'{inst}.{var}' is not a Real {}", want.as_str()),
            ));
        }
        Ok((i, v.vr))
    };
    let mut links: Vec<(usize, Link)> = Vec::new();
    for c in &f.connection {
        let (si, svr) = find(&c.from, "connection.from", Causality::Output)?;
        let (di, dvr) = find(&c.to, "connection.to", Causality::Input)?;
        if links.iter().any(|(d, l)| *d == di && l.to_vr == dvr) {
            return Err(sys.error_at(&c.to, "connection.to", "this input is already connected"));
        }
        let from_slot = subs[si].coupling_slot(svr);
        links.push((
            di,
            Link {
                to_vr: dvr,
                from: si,
                from_slot,
            },
        ));
    }
    for (di, l) in links {
        subs[di].inputs.push(l);
    }

    let order: Vec<usize> = match &alg.order {
        None => (0..subs.len()).collect(),
        Some(o) => {
            let mut idx = Vec::new();
            for name in o.get_ref() {
                let i = subs.iter().position(|s| &s.name == name).ok_or_else(|| {
                    sys.error_at(o, "algorithm.order", format!("no FMU instance '{name}'"))
                })?;
                if idx.contains(&i) {
                    return Err(sys.error_at(
                        o,
                        "algorithm.order",
                        format!("'{name}' appears twice"),
                    ));
                }
                idx.push(i);
            }
            if idx.len() != subs.len() {
                return Err(sys.error_at(
                    o,
                    "algorithm.order",
                    "must list every FMU instance once",
                ));
            }
            idx
        }
    };

    let mut recorded = Vec::new();
    for v in &f.output.variables {
        let (inst, var) = split_port(v.get_ref())
            .ok_or_else(|| sys.error_at(v, "output.variables", "expected 'instance.variable'"))?;
        let i = subs.iter().position(|s| s.name == inst).ok_or_else(|| {
            sys.error_at(v, "output.variables", format!("no FMU instance '{inst}'"))
        })?;
        let sv = fmus[i].description().variable(var).ok_or_else(|| {
            sys.error_at(
                v,
                "output.variables",
                format!("'{inst}' has no variable '{var}'"),
            )
        })?;
        if sv.var_type != VarType::Real {
            return Err(sys.error_at(v, "output.variables", format!("'{inst}.{var}' is not Real")));
        }
        recorded.push(Recorded {
            subsystem: i,
            vr: sv.vr,
            name: v.get_ref().clone(),
            unit: sv.unit.clone().unwrap_or_default(),
        });
    }

    let control = match &alg.step_control {
        None => None,
        Some(sc) => {
            let c = sc.get_ref();
            let control = StepControl::new(c.rtol, c.atol)
                .map_err(|e| sys.error_at(sc, "algorithm.step_control", e))?;
            if !alg.rollback {
                return Err(sys.error_at(
                    sc,
                    "algorithm.step_control",
                    "needs rollback = true (a rejected step is rolled back)",
                ));
            }
            Some(control)
        }
    };
    let config = AlgorithmConfig {
        scheme,
        extrapolation_order: *alg.extrapolation_order.get_ref() as usize,
        interpolation_order: *alg.interpolation_order.get_ref() as usize,
        rollback: alg.rollback,
        parallel: alg.parallel,
        control,
        parallel_tuning: Default::default(),
    };
    let guids = subs
        .iter()
        .zip(&fmus)
        .map(|(s, f)| (s.name.clone(), f.description().guid.clone()))
        .collect();
    let cosim = CoSim::initialize(subs, order, config, fmus).map_err(|e| {
        SystemError(format!(
            "{}: initialization failed: {e}",
            sys.path.display()
        ))
    })?;
    Ok(Built {
        cosim,
        macro_step_s,
        long_steps,
        stop_time_s,
        output_interval_s,
        recorded,
        guids,
    })
}
