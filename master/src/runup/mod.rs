//! Run-up presets (paper Section 3) and the system file they generate. The generated file is
//! written into the run folder, so every run can be repeated with `airring run DIR/system.toml`.

use crate::fmu_params::{with_units, FmuParameter};
use toml::Value;

mod defaults;
mod design_args;
pub mod flags;
mod parse;
pub mod shaft_fmu;
pub use defaults::*;
pub use design_args::DesignArgs;
use parse::mesh_out_of_bounds;
pub use parse::*;

/// Everything an engineer varies in a run-up, in the units they think in (named in the fields).
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunupSettings {
    pub preset: String,
    pub c_n_per_mm: f64,
    pub d_n_s_per_m: f64,
    pub m_r_g: f64,
    pub clearance_um: f64,
    pub dh_um: f64,
    pub f_max_hz: f64,
    pub t_ramp_s: f64,
    /// A speed profile (time [s], speed [Hz]) in place of the linear run-up f_max / t_ramp:
    /// ramps, dwells, run-downs (`--profile`); empty: the run-up.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub speed_profile: Vec<(f64, f64)>,
    pub stop_time_s: f64,
    pub macro_step_us: f64,
    /// Macro step [us] while the rotor is calm (`crate::calm_steps`): an integer multiple of
    /// `macro_step_us`; None: every macro step is `macro_step_us` (`--calm-macro-step off`).
    pub calm_macro_step_us: Option<f64>,
    /// The windows of simulated time [s] the calm macro step is taken in, found by
    /// `crate::calm_steps::plan` before the run (empty until then, and where nothing is calm).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub calm_windows_s: Vec<(f64, f64)>,
    pub extrapolation_order: u8,
    pub interpolation_order: u8,
    pub n_elem_phi: u32,
    pub n_elem_z: u32,
    /// The films' `mesh_grading` (1: uniform; below 1 the elements along a lobe shrink toward
    /// its trailing edge); written into the system file only where it is not 1.
    #[serde(skip_serializing_if = "is_uniform")]
    pub mesh_grading: f64,
    /// Set where `airring runup` chose the film mesh itself (no `--mesh`): the largest bearing
    /// number of the run it was chosen for ([`film_mesh_for`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub film_mesh_bearing_number: Option<f64>,
    /// Imbalance per wheel: mass [g], radius [mm], phase [deg] (compressor, turbine).
    pub imbalance_c: (f64, f64, f64),
    pub imbalance_t: (f64, f64, f64),
    /// Random disturbance force on each journal (x and y), standard deviation [mN]: the seed
    /// of self-excited whirl (see docs/stability.md); 0 = off.
    pub disturbance_mn: f64,
    /// Seed of the disturbance generator.
    pub disturbance_seed: u32,
    pub output_interval_us: f64,
    pub jacobi: bool,
    /// Step the two air films one after the other instead of in two threads (for sweeps that
    /// run one run-up per core).
    pub serial_films: bool,
    /// Macro-step control by the coupling error of the extrapolated forces: [rtol, atol in N];
    /// None = fixed macro step. Carries a journal through impacts on its ring (docs/convergence.md).
    pub step_control: Option<[f64; 2]>,
    /// Air-film time-integration tolerances [rtol, atol in Pa]; None = the FMU's own defaults
    /// (1e-4, 10 Pa). Run-ups use DEFAULT_FILM_TOLERANCE (docs/convergence.md).
    pub film_tolerance: Option<[f64; 2]>,
    /// Where the journal-ring contact is evaluated: in the rotor (implicitly, inside its own
    /// steps) or in the air films (its force extrapolated with the film force over each macro
    /// step). See docs/convergence.md.
    pub contact: ContactSide,
    /// End the run-up once a film's minimum thickness falls below this [um] (`--halt-film`),
    /// while the speed lies in `halt_speeds_hz`; None: run to the stop time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub halt_film_um: Option<f64>,
    /// End the run-up once the whirl amplitude of either bearing exceeds this [um]
    /// (`--halt-whirl`), while the speed lies in `halt_speeds_hz`; None: run to the stop time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub halt_whirl_um: Option<f64>,
    /// The speed range [Hz] in which `halt_film_um` and `halt_whirl_um` are watched
    /// (`--halt-speeds`; default: all).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub halt_speeds_hz: Option<(f64, f64)>,
    /// The design file the run-up started from (`--design`); its entries are the first
    /// `fmu_parameters`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub design: Option<std::path::PathBuf>,
    /// Further FMU parameters (a design file's, then `--set` and study keys with a dot):
    /// (PREFIX.NAME, value text), e.g.
    /// ("film.eta", "1.9e-5 Pa.s"); applied after, and in place of, the parameters above
    /// (`crate::fmu_params`).
    pub fmu_parameters: Vec<(String, String)>,
    /// The design file's `[shaft]`: a flexible rotor. Run-ups (and the sweeps of run-ups) and
    /// orbits co-simulate it in the rotor FMU that carries it (`shaft_fmu`); a study's linear
    /// map refuses it.
    #[serde(skip)]
    pub shaft: Option<crate::design::shaft::ShaftSpec>,
    /// The rotor FMU of a flexible rotor (`shaft_fmu::rotor_fmu_with_shaft`), set by the command
    /// that runs it; the system file names it in place of FMU_DIR/rotor.fmu.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_fmu: Option<std::path::PathBuf>,
}

/// Which FMU evaluates the mixed-lubrication contact of a run-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactSide {
    Rotor,
    Film,
}

impl ContactSide {
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "rotor" => Ok(ContactSide::Rotor),
            "film" => Ok(ContactSide::Film),
            other => Err(format!("--contact '{other}': expected 'rotor' or 'film'")),
        }
    }
}

impl RunupSettings {
    /// The paper's Section 3 runs: path1 (c = 1000 N/mm), path2a (500 N/mm), path2b (100 N/mm, 150 g rings);
    /// all with d = 50 N s/m, C = 20 um, dH = 40 um, 0 -> 2000 Hz in 3 s, no imbalance.
    pub fn preset(name: &str) -> Result<Self, String> {
        let (c, m_r) = match name {
            "path1" => (1000.0, 50.0),
            "path2a" => (500.0, 50.0),
            "path2b" => (100.0, 150.0),
            other => return Err(format!("unknown preset '{other}' (path1, path2a, path2b)")),
        };
        Ok(RunupSettings {
            preset: name.into(),
            c_n_per_mm: c,
            d_n_s_per_m: 50.0,
            m_r_g: m_r,
            clearance_um: 20.0,
            dh_um: 40.0,
            f_max_hz: 2000.0,
            t_ramp_s: 3.0,
            speed_profile: Vec::new(),
            stop_time_s: 3.0,
            macro_step_us: DEFAULT_MACRO_STEP_US,
            calm_macro_step_us: Some(DEFAULT_CALM_MACRO_STEP_US),
            calm_windows_s: Vec::new(),
            extrapolation_order: DEFAULT_EXTRAPOLATION_ORDER,
            interpolation_order: DEFAULT_INTERPOLATION_ORDER,
            n_elem_phi: 20,
            n_elem_z: 6,
            mesh_grading: 1.0,
            film_mesh_bearing_number: None,
            imbalance_c: (0.0, 0.0, 0.0),
            imbalance_t: (0.0, 0.0, 0.0),
            disturbance_mn: DEFAULT_DISTURBANCE_MN,
            disturbance_seed: 1,
            output_interval_us: DEFAULT_OUTPUT_INTERVAL_US,
            jacobi: false,
            serial_films: false,
            step_control: Some(DEFAULT_STEP_CONTROL),
            film_tolerance: Some(DEFAULT_FILM_TOLERANCE),
            contact: DEFAULT_CONTACT,
            halt_film_um: None,
            halt_whirl_um: None,
            halt_speeds_hz: None,
            design: None,
            fmu_parameters: Vec::new(),
            shaft: None,
            rotor_fmu: None,
        })
    }

    /// The run's halt on its film thickness or whirl amplitude (`--halt-film`, `--halt-whirl`,
    /// `--halt-speeds`), if any.
    pub fn halt(&self) -> Option<crate::run::Halt> {
        (self.halt_film_um.is_some() || self.halt_whirl_um.is_some()).then(|| crate::run::Halt {
            min_film_m: self.halt_film_um.map(|um| um * 1e-6),
            max_whirl_m: self.halt_whirl_um.map(|um| um * 1e-6),
            speeds_hz: self.halt_speeds_hz.unwrap_or((0.0, f64::INFINITY)),
        })
    }

    pub fn validate(&self) -> Result<(), String> {
        // First: a bad profile also makes the default stop time (its last point) meaningless.
        if !self.speed_profile.is_empty() {
            fmu_rotor::params::SpeedTable::new(&self.speed_profile)
                .map_err(|e| format!("--profile: {e}"))?;
        }
        let positive = [
            ("c", self.c_n_per_mm, "N/mm", true),
            ("d", self.d_n_s_per_m, "N s/m", true),
            ("m-r", self.m_r_g, "g", false),
            ("clearance", self.clearance_um, "um", false),
            ("f-max", self.f_max_hz, "Hz", false),
            ("t-ramp", self.t_ramp_s, "s", false),
            ("stop", self.stop_time_s, "s", false),
            ("macro-step", self.macro_step_us, "us", false),
            ("output-interval", self.output_interval_us, "us", false),
            ("disturbance", self.disturbance_mn, "mN", true),
        ];
        for (name, v, unit, zero_ok) in positive {
            if !v.is_finite() || v < 0.0 || (!zero_ok && v == 0.0) {
                return Err(format!(
                    "--{name} = {} {unit} must be a finite number {}",
                    fmt_number(v),
                    if zero_ok { ">= 0" } else { "> 0" }
                ));
            }
        }
        if !(MIN_MACRO_STEP_US..=MAX_MACRO_STEP_US).contains(&self.macro_step_us) {
            return Err(format!(
                "--macro-step = {} us must lie between {MIN_MACRO_STEP_US} us and \
                 {MAX_MACRO_STEP_US} us",
                fmt_number(self.macro_step_us)
            ));
        }
        check_dh_um(self.dh_um)?;
        check_clearance_um(self.clearance_um)?;
        // Before the calm plan, whose analysis grows with the stop time (1e6 s: seconds of
        // silence, 1e9 s: an hour) and which the system file's own limit would refuse after it.
        let steps = self.stop_time_s * 1e6 / self.macro_step_us;
        if steps > cosim::setup::MAX_MACRO_STEPS {
            return Err(format!(
                "--stop = {} s takes {steps:.1e} macro steps of {} us (at most {:e})",
                fmt_number(self.stop_time_s),
                fmt_number(self.macro_step_us),
                cosim::setup::MAX_MACRO_STEPS
            ));
        }
        let top_speed_hz = self.speed_profile.iter().map(|p| p.1).fold(0.0, f64::max);
        for (name, f_hz) in [("f-max", self.f_max_hz), ("profile", top_speed_hz)] {
            if f_hz > MAX_SPEED_HZ {
                return Err(format!(
                    "--{name}: {} Hz is above {MAX_SPEED_HZ} Hz, the highest speed a run-up \
                     takes (10 times the paper's 2000 Hz)",
                    fmt_number(f_hz)
                ));
            }
        }

        if let Some(calm) = self.calm_macro_step_us {
            self.calm_factor().ok_or_else(|| {
                format!(
                    "--calm-macro-step = {calm} us must be a multiple (2x or more) of the macro \
                     step ({} us), or \"off\"",
                    self.macro_step_us
                )
            })?;
        }
        for (name, order) in [
            ("extrapolation-order", self.extrapolation_order),
            ("interpolation-order", self.interpolation_order),
        ] {
            if order > 2 {
                return Err(format!("--{name} = {order} must be 0, 1 or 2"));
            }
        }
        if let Some(why) = mesh_out_of_bounds(self.n_elem_phi as u64, self.n_elem_z as u64) {
            return Err(format!(
                "mesh {}x{} is {why}",
                self.n_elem_phi, self.n_elem_z
            ));
        }
        self.checked_fmu_parameters()?;
        Ok(())
    }

    /// Base macro steps per calm macro step: Some(n >= 2) when `calm_macro_step_us` is n times
    /// `macro_step_us` (within rounding), None when it is off or not such a multiple.
    pub fn calm_factor(&self) -> Option<u64> {
        let calm = self.calm_macro_step_us?;
        let n = (calm / self.macro_step_us).round();
        let fits = calm.is_finite()
            && n >= 2.0
            && n <= cosim::step_plan::MAX_FACTOR as f64
            && (calm - n * self.macro_step_us).abs() <= 1e-9 * calm;
        fits.then_some(n as u64)
    }

    /// `validate`, and what only a co-simulated run-up needs: with the contact in the rotor, both
    /// films share one bore and contact law (the rotor FMU has one contact geometry for both
    /// bearings). The linear analysis takes each film's own and needs only `validate`.
    pub fn validate_runup(&self) -> Result<(), String> {
        self.validate()?;
        self.check_shaft()?;
        // Rows are written at macro points only: an interval that is not a whole number of
        // macro steps would space them unevenly (50 us at a 20 us step: 60, 40, 60, ... us).
        let per_row = (self.output_interval_us / self.macro_step_us).round();
        if per_row < 1.0
            || (self.output_interval_us - per_row * self.macro_step_us).abs()
                > 1e-9 * self.output_interval_us
        {
            return Err(format!(
                "--output-interval = {} us must be a whole number of macro steps ({} us): the \
                 time series is written at macro steps only",
                fmt_number(self.output_interval_us),
                fmt_number(self.macro_step_us)
            ));
        }
        if self.stop_time_s * 1e6 < self.macro_step_us {
            return Err(format!(
                "--stop = {} s is shorter than one macro step ({} us)",
                self.stop_time_s, self.macro_step_us
            ));
        }
        // The FMUs' own checks of the parameters they will get, so that a study's `--list`
        // refuses what the FMUs would refuse at the start of each run.
        self.validate_fmu_parameters()?;
        self.check_contact_geometry()
    }

    /// A design's `[shaft]` as the rotor FMU will take it: the flexible rotor built with this
    /// run-up's rotor parameters (its imbalances at nodes, the reduction within its error bound).
    pub fn check_shaft(&self) -> Result<(), String> {
        self.shaft_reduction().map(|_| ())
    }

    /// The reduction the rotor FMU will make of the design's shaft (none without a shaft).
    pub fn shaft_reduction(&self) -> Result<Option<fmu_rotor::flexible::ReductionReport>, String> {
        let Some(shaft) = &self.shaft else {
            return Ok(None);
        };
        let params = self.rotor_params()?;
        fmu_rotor::flexible::FlexRotor::new(params, shaft_fmu::spec_of(shaft))
            .map(|f| Some(f.reduction))
            .map_err(|e| {
                let at = self
                    .design
                    .as_ref()
                    .map_or(String::new(), |p| format!("{}: ", p.display()));
                format!("{at}[shaft]: {}", with_units("rotor", e.to_string()))
            })
    }

    /// The air films' and the rotor's own checks of the parameters they will get; a refusal of
    /// a value the design file set names the file and its entry.
    pub fn validate_fmu_parameters(&self) -> Result<(), String> {
        let [c, t] = self.film_params()?;
        for (inst, p) in [("film_C", c), ("film_T", t)] {
            p.validate()
                .map_err(|e| self.blame_design(with_units(inst, format!("{inst}: {e}"))))?;
        }
        self.rotor_params()?
            .validate()
            .map_err(|e| self.blame_design(with_units("rotor", format!("rotor: {e}"))))
    }

    /// An FMU's refusal of a parameter, with the design file and its entry in front where the
    /// design file set it (`crate::design::blame`).
    fn blame_design(&self, error: String) -> String {
        match &self.design {
            Some(path) => crate::design::blame(path, &self.fmu_parameters, error),
            None => error,
        }
    }

    /// The extra FMU parameters, checked against the FMUs' variable tables. The rotor's
    /// contact geometry (`bearing_*`) is refused: a run-up derives it from the air films.
    pub fn checked_fmu_parameters(&self) -> Result<Vec<FmuParameter>, String> {
        self.fmu_parameters
            .iter()
            .map(|(k, v)| {
                let p = FmuParameter::parse(k, v)?;
                if p.target == crate::fmu_params::Target::Rotor && p.name.starts_with("bearing_") {
                    let film_name = p.name.trim_start_matches("bearing_");
                    return Err(format!(
                        "{k}: a run-up derives the rotor's contact geometry from the air films; \
                         set film.{film_name} (both bearings) or film_C.{film_name} / \
                         film_T.{film_name} instead{}",
                        match film_name {
                            "C" => " (or --clearance)",
                            "dH" => " (or --dh)",
                            _ => "",
                        }
                    ));
                }
                Ok(p)
            })
            .collect()
    }

    /// The two air films' parameters [C, T] as the run-up's system file gives them (the run-up's
    /// own, then `--set` ones), mapped by the film FMU's own `params_from`.
    pub fn film_params(&self) -> Result<[fmu_airfilm::BearingParams; 2], String> {
        let film = |inst: &str| -> Result<fmu_airfilm::BearingParams, String> {
            let store = crate::fmu_params::store_for(inst, &self.instance_parameters(inst))?;
            Ok(fmu_airfilm::shell::params_from(&store))
        };
        Ok([film("film_C")?, film("film_T")?])
    }

    /// The largest bearing number Lambda = 6 eta Omega r^2 / (p_a C^2) of either film at the
    /// run's highest speed, as the rotor FMU gets it (`f_max`, or its speed table's highest
    /// point; a `--set rotor.f_max` included). The stop time does not enter: a run-up stopped
    /// early uses the film mesh of the whole run-up.
    pub fn largest_bearing_number(&self) -> Result<f64, String> {
        let rotor = self.rotor_params()?;
        let f_max_hz = if rotor.speed_table.is_empty() {
            rotor.f_max_hz
        } else {
            rotor.speed_table.iter().map(|p| p.1).fold(0.0, f64::max)
        };
        let omega_rad_s = 2.0 * std::f64::consts::PI * f_max_hz;
        let films = self.film_params()?;
        Ok(films
            .iter()
            .map(|f| f.bearing_number(omega_rad_s))
            .fold(0.0, f64::max))
    }

    /// The run-up's own film mesh where the user gave none: [`film_mesh_for`] the largest
    /// bearing number, and the tolerance that goes with that mesh unless `tolerance_given`
    /// (`--film-tolerance`). A `--set` of a film's `n_elem_phi`, `n_elem_z` or `mesh_grading` is a
    /// mesh given too, and leaves the settings' mesh as it is (the paper's 20 x 6 without
    /// `--mesh`): a grading alone would otherwise have graded, or made uniform, the chosen mesh,
    /// and `mesh_grading=1` on the chosen 10 elements is coarser than any run-up mesh.
    pub fn choose_film_mesh(&mut self, tolerance_given: bool) -> Result<(), String> {
        let mesh_set = self.fmu_parameters.iter().any(|(k, _)| {
            k.starts_with("film")
                && [".n_elem_phi", ".n_elem_z", ".mesh_grading"]
                    .iter()
                    .any(|name| k.ends_with(name))
        });
        if mesh_set {
            return Ok(());
        }
        let lambda = self.largest_bearing_number()?;
        let mesh = film_mesh_for(lambda);
        (self.n_elem_phi, self.n_elem_z, self.mesh_grading) =
            (mesh.along, mesh.across, mesh.grading);
        if !tolerance_given {
            self.film_tolerance = Some(mesh.tolerance);
        }
        self.film_mesh_bearing_number = Some(lambda);
        Ok(())
    }

    /// The rotor's parameters as the run-up's system file gives them, mapped by the rotor FMU's
    /// own `params_from`.
    pub fn rotor_params(&self) -> Result<fmu_rotor::RotorParams, String> {
        let store = crate::fmu_params::store_for("rotor", &self.instance_parameters("rotor"))?;
        Ok(fmu_rotor::shell::params_from(&store))
    }

    /// See `validate_runup`.
    fn check_contact_geometry(&self) -> Result<(), String> {
        if self.contact != ContactSide::Rotor {
            return Ok(());
        }
        let [c, t] = self.film_params()?;
        if c.bore != t.bore || c.contact != t.contact {
            return Err(format!(
                "film_C and film_T differ in their bore or contact law ({}): the rotor's contact \
                 (--contact rotor, the default) has one geometry for both bearings; run with \
                 --contact film to give each bearing its own",
                bore_differences(&c, &t).join(", ")
            ));
        }
        Ok(())
    }

    /// The rotor's parameters of this run-up as (name, TOML literal), before `fmu_parameters`.
    fn rotor_parameters(&self) -> Vec<(String, Value)> {
        let (mc, rc, pc) = self.imbalance_c;
        let (mt, rt, pt) = self.imbalance_t;
        let (c, d, m) = (self.c_n_per_mm, self.d_n_s_per_m, self.m_r_g);
        let q = |x: f64, unit: &str| Value::String(format!("{x} {unit}"));
        let mut v: Vec<(&str, Value)> = vec![
            ("c_C", q(c, "N/mm")),
            ("c_T", q(c, "N/mm")),
            ("d_C", Value::Float(d)),
            ("d_T", Value::Float(d)),
            ("m_R_C", q(m, "g")),
            ("m_R_T", q(m, "g")),
            ("f_max", Value::Float(self.f_max_hz)),
            ("t_ramp", Value::Float(self.t_ramp_s)),
            ("m_imb_C", q(mc, "g")),
            ("r_imb_C", q(rc, "mm")),
            ("phase_imb_C", q(pc, "deg")),
            ("m_imb_T", q(mt, "g")),
            ("r_imb_T", q(rt, "mm")),
            ("phase_imb_T", q(pt, "deg")),
            ("disturbance_force", q(self.disturbance_mn, "mN")),
            (
                "disturbance_seed",
                Value::Integer(i64::from(self.disturbance_seed)),
            ),
            ("h_max", q(ROTOR_MAX_STEP_US, "us")),
        ];
        if !self.speed_profile.is_empty() {
            v.push((
                "speed_table_points",
                Value::Integer(self.speed_profile.len() as i64),
            ));
        }
        let mut v: Vec<(String, Value)> = v.into_iter().map(|(k, x)| (k.to_string(), x)).collect();
        for (k, (t, f)) in self.speed_profile.iter().enumerate() {
            v.push((format!("speed_table_t_{:02}", k + 1), Value::Float(*t)));
            v.push((format!("speed_table_f_{:02}", k + 1), Value::Float(*f)));
        }
        if self.contact == ContactSide::Rotor {
            // The rotor evaluates the contact on the films' own bore and contact law, derived
            // from the films' final parameters (including `--set film.C=...`), so the two cannot
            // disagree. One bore serves both bearings in the rotor FMU: `validate` refuses films
            // whose bores differ.
            v.push(("contact".into(), Value::Boolean(true)));
            if let Ok([film_c, _]) = self.film_params() {
                v.extend(
                    rotor_contact_parameters(&film_c.bore, &film_c.contact)
                        .into_iter()
                        .map(|(k, x)| (k.to_string(), x)),
                );
            }
        }
        v
    }

    /// "0 -> 2000 Hz in 3 s" or the profile's points.
    pub fn describe_speed(&self) -> String {
        if self.speed_profile.is_empty() {
            return format!(
                "0 -> {} Hz in {} s",
                fmt_number(self.f_max_hz),
                fmt_number(self.t_ramp_s)
            );
        }
        let pts: Vec<String> = self
            .speed_profile
            .iter()
            .map(|(t, f)| format!("{} Hz at {} s", fmt_number(*f), fmt_number(*t)))
            .collect();
        format!("speed profile {}", pts.join(", "))
    }

    /// An air film's parameters of this run-up as (name, TOML value), before `fmu_parameters`.
    fn film_parameters(&self) -> Vec<(String, Value)> {
        let mut v: Vec<(&str, Value)> = vec![
            ("C", Value::String(format!("{} um", self.clearance_um))),
            ("dH", Value::String(format!("{} um", self.dh_um))),
            ("n_elem_phi", Value::Integer(i64::from(self.n_elem_phi))),
            ("n_elem_z", Value::Integer(i64::from(self.n_elem_z))),
        ];
        if !is_uniform(&self.mesh_grading) {
            v.push(("mesh_grading", Value::Float(self.mesh_grading)));
        }
        if let Some([rtol, atol]) = self.film_tolerance {
            v.push(("rtol", Value::Float(rtol)));
            v.push(("atol", Value::String(format!("{atol} Pa"))));
        }
        if self.contact == ContactSide::Rotor {
            v.push(("contact_in_force", Value::Boolean(false)));
        }
        v.into_iter().map(|(k, x)| (k.to_string(), x)).collect()
    }

    /// The parameters of instance `inst` ("rotor", "film_C", "film_T") as (name, TOML value):
    /// the run-up's own, each `fmu_parameters` entry for it replacing or adding one. Entries that
    /// fail their check are left out here; `validate` reports them.
    pub fn instance_parameters(&self, inst: &str) -> Vec<(String, Value)> {
        let mut v = if inst == "rotor" {
            self.rotor_parameters()
        } else {
            self.film_parameters()
        };
        for p in self.checked_fmu_parameters().unwrap_or_default() {
            if !p.applies_to(inst) {
                continue;
            }
            let value = p.toml_value();
            match v.iter_mut().find(|(k, _)| *k == p.name) {
                Some(e) => e.1 = value,
                None => v.push((p.name.clone(), value)),
            }
        }
        v
    }

    /// The system file for this run-up; `fmu_dir` holds rotor.fmu and airfilm.fmu. Written by
    /// the TOML serializer: any folder name or `--set` text comes out as a valid TOML string.
    pub fn system_toml(&self, fmu_dir: &str) -> String {
        let fmu = |name: &str, file: &str| FmuEntry {
            name: name.to_string(),
            path: match (&self.rotor_fmu, name) {
                (Some(p), "rotor") => p.display().to_string(),
                _ => format!("{fmu_dir}/{file}"),
            },
            parameters: self.instance_parameters(name).into_iter().collect(),
        };
        let mut connection = vec![];
        let mut connect = |from: String, to: String| connection.push(Connection { from, to });
        for side in ["C", "T"] {
            for v in ["dx", "dy", "vx", "vy"] {
                connect(format!("rotor.{v}_{side}"), format!("film_{side}.{v}"));
            }
            connect("rotor.omega".into(), format!("film_{side}.omega"));
            for axis in ["x", "y"] {
                connect(
                    format!("film_{side}.F{axis}"),
                    format!("rotor.F_{side}_{axis}"),
                );
            }
        }
        let file = SystemFile {
            fmu: vec![
                fmu("rotor", "rotor.fmu"),
                fmu("film_C", "airfilm.fmu"),
                fmu("film_T", "airfilm.fmu"),
            ],
            connection,
            algorithm: Algorithm {
                kind: if self.jacobi {
                    "jacobi"
                } else {
                    "gauss-seidel"
                },
                parallel: !self.serial_films,
                order: ["rotor", "film_C", "film_T"],
                macro_step: format!("{} us", self.macro_step_us),
                stop_time: format!("{} s", self.stop_time_s),
                extrapolation_order: self.extrapolation_order,
                interpolation_order: self.interpolation_order,
                step_control: self
                    .step_control
                    .map(|[rtol, atol]| StepControl { rtol, atol }),
                long_steps: self
                    .calm_factor()
                    .filter(|_| !self.calm_windows_s.is_empty())
                    .map(|factor| LongSteps {
                        factor,
                        windows: self.calm_windows_s.iter().map(|&(a, b)| [a, b]).collect(),
                    }),
            },
            output: Output {
                interval: format!("{} us", self.output_interval_us),
                variables: RECORDED,
            },
        };
        format!(
            "# Run-up '{}' generated by airring (units are SI unless a string names them).\n{}",
            self.preset.replace(['\n', '\r'], " "),
            toml::to_string(&file).expect("a system file is plain data")
        )
    }
}

/// The generated system file, as the TOML serializer writes it (the layout `cosim::system` reads).
#[derive(serde::Serialize)]
struct SystemFile {
    fmu: Vec<FmuEntry>,
    connection: Vec<Connection>,
    algorithm: Algorithm,
    output: Output,
}

#[derive(serde::Serialize)]
struct FmuEntry {
    name: String,
    path: String,
    parameters: toml::Table,
}

#[derive(serde::Serialize)]
struct Connection {
    from: String,
    to: String,
}

#[derive(serde::Serialize)]
struct Algorithm {
    kind: &'static str,
    parallel: bool,
    order: [&'static str; 3],
    macro_step: String,
    stop_time: String,
    extrapolation_order: u8,
    interpolation_order: u8,
    #[serde(skip_serializing_if = "Option::is_none")]
    step_control: Option<StepControl>,
    #[serde(skip_serializing_if = "Option::is_none")]
    long_steps: Option<LongSteps>,
}

#[derive(serde::Serialize)]
struct LongSteps {
    factor: u64,
    windows: Vec<[f64; 2]>,
}

#[derive(serde::Serialize)]
struct StepControl {
    rtol: f64,
    atol: f64,
}

#[derive(serde::Serialize)]
struct Output {
    interval: String,
    variables: &'static [&'static str],
}

/// The bearings as the run-up's FMUs get them, in the units engineers read: "c = 1000 N/mm,
/// d = 50 N s/m, m_R = 50 g, C = 20 um, dH = 40 um", with "C/T" pairs where the bearings differ.
pub fn describe_bearings(s: &RunupSettings) -> Result<String, String> {
    let (rotor, films) = (s.rotor_params()?, s.film_params()?);
    let pair = |c: f64, t: f64| {
        // Rounded to 12 significant digits for reading (unit conversions leave residues in the
        // last digits: 1e30 N/m read 9.999999999999999e26 N/mm).
        let r = |x: f64| {
            if x == 0.0 || !x.is_finite() {
                return x;
            }
            // By an exact power of ten on the side where it is one (1e18, not 1e-18).
            let d = x.abs().log10().ceil() as i32 - 12;
            if d >= 0 {
                (x / 10f64.powi(d)).round() * 10f64.powi(d)
            } else {
                (x * 10f64.powi(-d)).round() / 10f64.powi(-d)
            }
        };
        // Very large or small values with an exponent ("1e30", not thirty-one digits).
        if r(c) == r(t) {
            fmt_number(r(c))
        } else {
            format!("{}/{}", fmt_number(r(c)), fmt_number(r(t)))
        }
    };
    Ok(format!(
        "c = {} N/mm, d = {} N s/m, m_R = {} g, C = {} um, dH = {} um",
        pair(rotor.c_c_n_m / 1e3, rotor.c_t_n_m / 1e3),
        pair(rotor.d_c_n_s_m, rotor.d_t_n_s_m),
        pair(rotor.m_r_c_kg * 1e3, rotor.m_r_t_kg * 1e3),
        pair(films[0].bore.c_m * 1e6, films[1].bore.c_m * 1e6),
        pair(films[0].bore.dh_m * 1e6, films[1].bore.dh_m * 1e6),
    ))
}

/// The bore and contact-law quantities in which two films differ, "C 20 um / 22 um" (C's value
/// first), in the units of a design file.
fn bore_differences(c: &fmu_airfilm::BearingParams, t: &fmu_airfilm::BearingParams) -> Vec<String> {
    let (bc, bt) = (&c.bore, &t.bore);
    let quantities = [
        ("r", bc.r_m * 1e3, bt.r_m * 1e3, "mm"),
        ("b", bc.b_m * 1e3, bt.b_m * 1e3, "mm"),
        ("C", bc.c_m * 1e6, bt.c_m * 1e6, "um"),
        ("dH", bc.dh_m * 1e6, bt.dh_m * 1e6, "um"),
        (
            "phi_t",
            bc.phi_t_rad.to_degrees(),
            bt.phi_t_rad.to_degrees(),
            "deg",
        ),
        (
            "alpha",
            bc.alpha_rad.to_degrees(),
            bt.alpha_rad.to_degrees(),
            "deg",
        ),
        ("n_lobes", bc.n_lobes as f64, bt.n_lobes as f64, ""),
        ("h_con_rel", c.contact.h_con_rel, t.contact.h_con_rel, ""),
        (
            "c_con",
            c.contact.c_con_n_per_m3,
            t.contact.c_con_n_per_m3,
            "N/m^3",
        ),
    ];
    let mut differ: Vec<String> = quantities
        .iter()
        .filter(|(_, a, b, _)| a != b)
        .map(|(name, a, b, unit)| {
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" {unit}")
            };
            format!("{name} {}{unit} / {}{unit}", fmt_number(*a), fmt_number(*b))
        })
        .collect();
    if bc.plain_bore != bt.plain_bore {
        differ.push(format!("plain_bore {} / {}", bc.plain_bore, bt.plain_bore));
    }
    differ
}

/// The films' mesh as their FMUs get it, "film mesh 10 x 2 graded by 0.8 toward the trailing edge
/// per lobe", why where the run-up chose it, "(for the largest bearing number 8.8; the paper's is
/// 20 x 6)", and the films' time integration tolerance as their FMUs get it too, ", film
/// tolerance 6e-4 / 60 Pa".
pub fn describe_film_mesh(s: &RunupSettings) -> Result<String, String> {
    let films = s.film_params()?;
    let mesh = |f: &fmu_airfilm::BearingParams| {
        let graded = match f.mesh_grading {
            g if g == 1.0 || f.bore.plain_bore => String::new(),
            g => format!(" graded by {g} toward the trailing edge"),
        };
        format!("{} x {}{graded}", f.n_elem_phi, f.n_elem_z)
    };
    let (c, t) = (mesh(&films[0]), mesh(&films[1]));
    let mut text = if c == t {
        format!("film mesh {c} per lobe")
    } else {
        format!("film mesh {c} (C) / {t} (T) per lobe")
    };
    if let Some(lambda) = s.film_mesh_bearing_number {
        text += &format!(" (for the largest bearing number {lambda:.1}; the paper's is 20 x 6)");
    }
    let tol = |f: &fmu_airfilm::BearingParams| format!("{:e} / {} Pa", f.rtol, f.atol_pa);
    let (c, t) = (tol(&films[0]), tol(&films[1]));
    text += &if c == t {
        format!(", film tolerance {c}")
    } else {
        format!(", film tolerance {c} (C) / {t} (T)")
    };
    Ok(text)
}

/// The rotor's contact-geometry parameters (`bearing_*`, in SI, exact) for a film's bore and
/// contact law.
fn rotor_contact_parameters(
    bore: &bearing::Bore,
    law: &bearing::ContactLaw,
) -> Vec<(&'static str, Value)> {
    vec![
        ("bearing_r", Value::Float(bore.r_m)),
        ("bearing_b", Value::Float(bore.b_m)),
        ("bearing_C", Value::Float(bore.c_m)),
        ("bearing_dH", Value::Float(bore.dh_m)),
        ("bearing_phi_t", Value::Float(bore.phi_t_rad)),
        ("bearing_alpha", Value::Float(bore.alpha_rad)),
        ("bearing_n_lobes", Value::Integer(bore.n_lobes as i64)),
        ("bearing_plain_bore", Value::Boolean(bore.plain_bore)),
        ("bearing_h_con_rel", Value::Float(law.h_con_rel)),
        ("bearing_c_con", Value::Float(law.c_con_n_per_m3)),
    ]
}

fn is_uniform(g: &f64) -> bool {
    *g == 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_up_flags_parse_or_explain() {
        assert_eq!(parse_step_control("off"), Ok(None));
        assert_eq!(parse_step_control("0.1, 1"), Ok(Some([0.1, 1.0])));
        for bad in ["0.1", "x,1", "-0.1,1", "0,0", "nan,1"] {
            let e = parse_step_control(bad).unwrap_err();
            assert!(e.starts_with("--step-control"), "{bad}: {e}");
        }
        assert_eq!(parse_film_tolerance("1e-3,100"), Ok([1e-3, 100.0]));
        for bad in ["1e-3", "1,10", "1e-3,0", "1e-3,inf"] {
            let e = parse_film_tolerance(bad).unwrap_err();
            assert!(e.starts_with("--film-tolerance"), "{bad}: {e}");
        }
        // The generated system file carries both settings.
        let mut s = RunupSettings::preset("path1").unwrap();
        s.film_tolerance = Some([1e-3, 100.0]);
        let text = s.system_toml("fmus");
        let doc: toml::Table = text.parse().unwrap();
        let film = &doc["fmu"][1]["parameters"];
        assert_eq!(film["rtol"], toml::Value::Float(0.001), "{text}");
        assert_eq!(film["atol"], toml::Value::String("100 Pa".into()), "{text}");
        let control = &doc["algorithm"]["step_control"];
        assert_eq!(
            (control["rtol"].as_float(), control["atol"].as_float()),
            (Some(DEFAULT_STEP_CONTROL[0]), Some(DEFAULT_STEP_CONTROL[1])),
            "{text}"
        );
        s.step_control = None;
        assert!(!s.system_toml("fmus").contains("step_control"));
    }

    #[test]
    fn contact_side_sets_both_fmus_consistently() {
        assert_eq!(ContactSide::parse("rotor"), Ok(ContactSide::Rotor));
        assert_eq!(ContactSide::parse("film"), Ok(ContactSide::Film));
        assert!(ContactSide::parse("ring")
            .unwrap_err()
            .starts_with("--contact"));
        let mut s = RunupSettings::preset("path1").unwrap();
        s.clearance_um = 15.0;
        s.dh_um = 0.0;
        s.contact = ContactSide::Rotor;
        let text = s.system_toml("fmus");
        // The rotor gets the films' whole bore and contact law, bit for bit; both films leave
        // the contact out of their force.
        let doc: toml::Table = text.parse().unwrap();
        let rotor = &doc["fmu"][0]["parameters"];
        assert_eq!(rotor["contact"], toml::Value::Boolean(true), "{text}");
        assert_eq!(rotor["bearing_C"], toml::Value::Float(15e-6), "{text}");
        let store = |inst: &str| crate::fmu_params::store_for(inst, &s.instance_parameters(inst));
        let rotor = fmu_rotor::shell::params_from(&store("rotor").unwrap());
        let film = fmu_airfilm::shell::params_from(&store("film_C").unwrap());
        let [c, t] = rotor.contact.expect("contact in the rotor");
        assert_eq!(c, t);
        assert_eq!(c.bore, film.bore);
        assert_eq!(c.law, film.contact);
        assert_eq!(film.bore.c_m, 15e-6);
        assert_eq!(film.bore.dh_m, 0.0);
        assert_eq!(
            text.matches("contact_in_force = false").count(),
            2,
            "{text}"
        );
        let sys = cosim::system::System::parse(std::path::Path::new("s.toml"), text).unwrap();
        assert_eq!(sys.file.fmu.len(), 3);
        s.contact = ContactSide::Film;
        let text = s.system_toml("fmus");
        assert!(
            !text.contains("contact =") && !text.contains("contact_in_force"),
            "{text}"
        );
    }

    #[test]
    fn fmu_parameters_replace_or_extend_the_generated_ones() {
        let mut s = RunupSettings::preset("path1").unwrap();
        s.fmu_parameters = vec![
            ("rotor.c_C".into(), "1500 N/mm".into()),
            ("film.eta".into(), "2e-5".into()),
            ("film_T.C".into(), "25 um".into()),
        ];
        s.validate().unwrap();
        let sys: toml::Table = s.system_toml("fmus").parse().unwrap();
        let fmus = sys["fmu"].as_array().unwrap();
        let params = |i: usize| fmus[i]["parameters"].as_table().unwrap().clone();
        assert_eq!(fmus[0]["name"].as_str(), Some("rotor"));
        assert_eq!(params(0)["c_C"].as_str(), Some("1500 N/mm"));
        assert_eq!(params(0)["c_T"].as_str(), Some("1000 N/mm"));
        assert_eq!(params(1)["eta"].as_float(), Some(2e-5));
        assert_eq!(params(2)["eta"].as_float(), Some(2e-5));
        assert_eq!(params(1)["C"].as_str(), Some("20 um"));
        assert_eq!(params(2)["C"].as_str(), Some("25 um"));
        s.fmu_parameters = vec![("film.C".into(), "5 furlongs".into())];
        assert!(s.validate().unwrap_err().contains("furlongs"));
    }

    /// The header line reads like the flags: no thirty-one digits for 1e30 N/mm (a conversion
    /// residue made it 9.999999999999999e29 too), no residues in ordinary values.
    #[test]
    fn bearings_are_described_as_written() {
        let mut s = RunupSettings::preset("path1").unwrap();
        let d = describe_bearings(&s).unwrap();
        assert!(
            d.starts_with("c = 1000 N/mm, d = 50 N s/m, m_R = 50 g, C = 20 um, dH = 40 um"),
            "{d}"
        );
        s.c_n_per_mm = 1e30;
        let d = describe_bearings(&s).unwrap();
        assert!(d.starts_with("c = 1e30 N/mm,"), "{d}");
        s.c_n_per_mm = 1234.5678;
        let d = describe_bearings(&s).unwrap();
        assert!(d.starts_with("c = 1234.5678 N/mm,"), "{d}");
    }
}
