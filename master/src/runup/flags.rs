//! The flags of `airring runup`, and the run-up settings they give. Sweeps check every point
//! of a study through the same parser and checks ([`check_argv`]), so `--list` refuses what a
//! run would refuse.

use crate::runup::RunupSettings;
use clap::Parser;
use std::path::PathBuf;

#[derive(clap::Args, Clone)]
pub struct RunupArgs {
    /// The rotor and its bearings (shared with `airring stability`).
    #[command(flatten)]
    pub bearing: crate::runup::DesignArgs,
    /// Final speed [Hz] (at most 20000)
    #[arg(long)]
    pub f_max: Option<f64>,
    /// Run-up duration to f_max [s].
    #[arg(long)]
    pub t_ramp: Option<f64>,
    /// Speed profile "T:F,T:F,..." (seconds:Hz, piecewise linear from T = 0, 2 to 16 points,
    /// constant after the last) in place of --f-max / --t-ramp, e.g. a run-up, a dwell and a
    /// run-down "0:0,1.5:2000,3:2000,4.5:0".
    #[arg(long)]
    pub profile: Option<String>,
    /// Simulated time [s] (default: t_ramp, or the profile's last time).
    #[arg(long)]
    pub stop: Option<f64>,
    /// Macro (communication) step [us], 1-1000 [default: 50; 20 with --extrapolation-order 1 is
    /// the previous default, for cross-checks]
    #[arg(long)]
    pub macro_step: Option<f64>,
    /// Macro step [us] before the rotor nears any instability, where the linear stability
    /// analysis finds every mode damped by 2 % or more (docs/convergence.md, "Calm macro
    /// steps"); a multiple of --macro-step, or "off" [default: 100]
    #[arg(long)]
    pub calm_macro_step: Option<String>,
    /// Extrapolation order of the rotor's inputs (0, 1, 2) [default: 2]
    #[arg(long)]
    pub extrapolation_order: Option<u8>,
    /// Interpolation order of the air films' inputs (0, 1, 2).
    #[arg(long)]
    pub interpolation_order: Option<u8>,
    /// Compressor-wheel imbalance "mass_g,radius_mm,phase_deg".
    #[arg(long)]
    pub imbalance_c: Option<String>,
    /// Turbine-wheel imbalance "mass_g,radius_mm,phase_deg".
    #[arg(long)]
    pub imbalance_t: Option<String>,
    /// Random disturbance force on each journal, x and y: standard deviation [mN] (the seed of
    /// self-excited whirl; 0 = off).
    #[arg(long)]
    pub disturbance: Option<f64>,
    /// Seed of the disturbance generator (other seeds: independent realisations).
    #[arg(long)]
    pub disturbance_seed: Option<u32>,
    /// Interval of the recorded time series [us]: a whole number of macro steps (rows are
    /// written at macro steps) [default: 50, or the most macro steps within 50 us]
    #[arg(long)]
    pub output_interval: Option<f64>,
    /// Jacobi instead of Gauss-Seidel.
    #[arg(long)]
    pub jacobi: bool,
    /// Step the two air films one after the other (one core) throughout. By default the run times
    /// both ways as it goes and keeps the faster (summary.json `group_stepping`).
    #[arg(long)]
    pub serial_films: bool,
    /// Macro-step control: "RTOL,ATOL_N" of the extrapolated bearing forces (a step whose
    /// extrapolated force misses the film's by more than ATOL + RTOL |F| is retried in halves,
    /// down to 1/64), or "off" for a fixed macro step [default: 0.3,3]
    #[arg(long)]
    pub step_control: Option<String>,
    /// Air-film time-integration tolerances "RTOL,ATOL_PA" [default: 1e-3,100, and 6e-4,60 with
    /// the 10x2 mesh a run-up chooses for the larger clearances; the FMU's own defaults are
    /// 1e-4,10]
    #[arg(long)]
    pub film_tolerance: Option<String>,
    /// Where the journal-ring contact is evaluated: "rotor" (implicitly inside the rotor's
    /// steps) or "film" (with the film force, extrapolated over each macro step) [default: rotor]
    #[arg(long)]
    pub contact: Option<String>,
    /// Folder with rotor.fmu and airfilm.fmu (default: next to the executable, then
    /// target/fmu).
    #[arg(long)]
    pub fmu_dir: Option<PathBuf>,
    /// Folder of linear analyses to reuse and add to when planning the calm macro steps: speeds
    /// already analysed there with the same parameters by this build are not analysed again (a
    /// sweep passes its own, which its --predict-first fills).
    #[arg(long)]
    pub linear_cache: Option<PathBuf>,
    /// End the run-up once the minimum film thickness of either bearing falls below this [um]
    /// (while the speed lies in --halt-speeds): the run is completed there, summary.json says
    /// where (`halted`). For searches that only need to know that a design fails.
    #[arg(long)]
    pub halt_film: Option<f64>,
    /// End the run-up once the whirl amplitude of either bearing exceeds this [um] (while the
    /// speed lies in --halt-speeds): the root mean square of the journal's motion relative to
    /// its ring over 40 ms windows every 20 ms, without its mean, drift and 1x part (the
    /// run-up analysis' measure). The run is completed there, summary.json says where.
    #[arg(long)]
    pub halt_whirl: Option<f64>,
    /// The speed range "LO:HI" [Hz] in which --halt-film and --halt-whirl watch [default: all
    /// speeds]
    #[arg(long)]
    pub halt_speeds: Option<String>,
}

/// `--halt-film` [um], `--halt-whirl` [um] and `--halt-speeds` [Hz].
type HaltFlags = (Option<f64>, Option<f64>, Option<(f64, f64)>);

/// `--halt-film`, `--halt-whirl` and `--halt-speeds`, checked.
fn halt(a: &RunupArgs) -> Result<HaltFlags, String> {
    for (flag, v) in [("--halt-film", a.halt_film), ("--halt-whirl", a.halt_whirl)] {
        if let Some(um) = v {
            if !(um.is_finite() && um > 0.0) {
                return Err(format!(
                    "{flag} = {} um must be a finite number > 0",
                    crate::runup::fmt_number(um)
                ));
            }
        }
    }
    let Some(text) = &a.halt_speeds else {
        return Ok((a.halt_film, a.halt_whirl, None));
    };
    if a.halt_film.is_none() && a.halt_whirl.is_none() {
        return Err(format!(
            "--halt-speeds '{text}' needs --halt-film or --halt-whirl (the limit it watches)"
        ));
    }
    let bad = || format!("--halt-speeds '{text}': expected LO:HI in Hz with 0 <= LO < HI");
    let (lo, hi) = text.split_once(':').ok_or_else(bad)?;
    let (lo, hi): (f64, f64) = (
        lo.trim().parse().map_err(|_| bad())?,
        hi.trim().parse().map_err(|_| bad())?,
    );
    if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi) {
        return Err(bad());
    }
    Ok((a.halt_film, a.halt_whirl, Some((lo, hi))))
}

/// "0:0,1.5:2000" -> [(0, 0), (1.5, 2000)]; the table's own checks follow in `validate`.
fn profile(text: &str) -> Result<Vec<(f64, f64)>, String> {
    text.split(',')
        .map(|pair| {
            let (t, f) = pair.split_once(':').ok_or_else(|| {
                format!("--profile '{text}': each point is TIME_S:SPEED_HZ, got '{pair}'")
            })?;
            let num = |x: &str| {
                x.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("--profile '{text}': '{x}' is not a number"))
            };
            Ok((num(t)?, num(f)?))
        })
        .collect()
}

fn triple(s: &str, flag: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--{flag} expects mass_g,radius_mm,phase_deg"))?;
    match v[..] {
        [m, r, p] if m >= 0.0 && r >= 0.0 => Ok((m, r, p)),
        _ => Err(format!(
            "--{flag} expects three numbers mass_g >= 0, radius_mm >= 0, phase_deg"
        )),
    }
}

pub fn settings(a: &RunupArgs) -> Result<RunupSettings, String> {
    let mut s = a.bearing.settings()?;
    s.f_max_hz = a.f_max.unwrap_or(s.f_max_hz);
    s.t_ramp_s = a.t_ramp.unwrap_or(s.t_ramp_s);
    if let Some(p) = &a.profile {
        if a.f_max.is_some() || a.t_ramp.is_some() {
            return Err("--profile replaces --f-max and --t-ramp: give one or the other".into());
        }
        s.speed_profile = profile(p)?;
    }
    let profile_end = s.speed_profile.last().map(|p| p.0);
    s.stop_time_s = a.stop.or(profile_end).unwrap_or(s.t_ramp_s);
    s.macro_step_us = a.macro_step.unwrap_or(s.macro_step_us);
    if let Some(c) = &a.calm_macro_step {
        s.calm_macro_step_us = match c.trim() {
            "off" => None,
            t => Some(t.parse::<f64>().map_err(|_| {
                format!("--calm-macro-step '{c}': expected a number of microseconds or \"off\"")
            })?),
        };
    } else if a.macro_step.is_some() {
        // A macro step of the user's own (a cross-check): every step at it unless calm steps
        // are asked for as well.
        s.calm_macro_step_us = None;
    }
    s.extrapolation_order = a.extrapolation_order.unwrap_or(s.extrapolation_order);
    s.interpolation_order = a.interpolation_order.unwrap_or(s.interpolation_order);
    s.output_interval_us = match a.output_interval {
        Some(v) => v,
        // The default interval where it is a whole number of macro steps, else the largest such
        // number of steps within it (at least one): rows are written at macro steps only.
        None => {
            let steps = (s.output_interval_us / s.macro_step_us + 1e-9)
                .floor()
                .max(1.0);
            if s.macro_step_us.is_finite() && s.macro_step_us > 0.0 {
                steps * s.macro_step_us
            } else {
                s.output_interval_us
            }
        }
    };
    s.disturbance_mn = a.disturbance.unwrap_or(s.disturbance_mn);
    s.disturbance_seed = a.disturbance_seed.unwrap_or(s.disturbance_seed);
    s.jacobi = a.jacobi;
    s.serial_films = a.serial_films;
    if let Some(ft) = &a.film_tolerance {
        s.film_tolerance = Some(crate::runup::parse_film_tolerance(ft)?);
    }
    if let Some(sc) = &a.step_control {
        s.step_control = crate::runup::parse_step_control(sc)?;
    }
    if let Some(c) = &a.contact {
        s.contact = crate::runup::ContactSide::parse(c)?;
    }
    if let Some(i) = &a.imbalance_c {
        s.imbalance_c = triple(i, "imbalance-c")?;
    }
    if let Some(i) = &a.imbalance_t {
        s.imbalance_t = triple(i, "imbalance-t")?;
    }
    (s.halt_film_um, s.halt_whirl_um, s.halt_speeds_hz) = halt(a)?;
    // Checked first, so that a parameter that does not map is reported with its flag; every
    // mesh the run-up chooses passes the same checks.
    s.validate()?;
    // The rotor's speed as its FMU gets it: a `--set rotor.f_max` or `rotor.t_ramp` replaces the
    // flags' values in the FMU, and the settings (the run-up's first line, summary.json, the
    // default stop time) say what runs.
    if s.speed_profile.is_empty() {
        let rotor = s.rotor_params()?;
        if (rotor.f_max_hz, rotor.t_ramp_s) != (s.f_max_hz, s.t_ramp_s) {
            (s.f_max_hz, s.t_ramp_s) = (rotor.f_max_hz, rotor.t_ramp_s);
            if a.stop.is_none() {
                s.stop_time_s = s.t_ramp_s;
            }
            s.validate()?;
        }
    }
    if a.bearing.mesh.is_none() {
        s.choose_film_mesh(a.film_tolerance.is_some())?;
    }
    Ok(s)
}

/// `airring runup` with only the run-up flags: what a study point may set.
#[derive(Parser)]
#[command(name = "runup", allow_negative_numbers = true)]
struct RunupFlagsOnly {
    #[command(flatten)]
    args: RunupArgs,
}

/// Checks an `airring runup` argument list (first element "runup", no --out) as the command
/// would: every flag parsed and every value through the run-up's own checks.
pub fn check_argv(argv: &[String]) -> Result<RunupSettings, String> {
    let flags = RunupFlagsOnly::try_parse_from(argv).map_err(|e| {
        // clap's message without its usage block: the first line says what is wrong.
        e.to_string()
            .lines()
            .next()
            .unwrap_or("invalid flags")
            .trim_start_matches("error: ")
            .to_string()
    })?;
    let s = settings(&flags.args)?;
    s.validate_runup()?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `airring runup FLAGS` through the run-up's own checks.
    fn checked(flags: &[&str]) -> Result<RunupSettings, String> {
        let argv: Vec<String> = std::iter::once("runup")
            .chain(flags.iter().copied())
            .map(String::from)
            .collect();
        check_argv(&argv)
    }

    fn settings_of(flags: &[&str]) -> RunupSettings {
        checked(flags).unwrap()
    }

    fn refusal(flags: &[&str]) -> String {
        checked(flags).unwrap_err()
    }

    /// Lambda = 6 eta Omega r^2 / (p_a C^2) with the paper's r = 15 mm, eta = 20.936e-6 Pa s and
    /// p_a = 101325 Pa, written out here apart from the film's own formula.
    fn lambda(c_um: f64, f_hz: f64) -> f64 {
        let (eta, r, p_a) = (20.936e-6, 15e-3, 101_325.0);
        6.0 * eta * 2.0 * std::f64::consts::PI * f_hz * r * r / (p_a * (c_um * 1e-6).powi(2))
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs()
    }

    /// Without --mesh a run-up takes the film mesh for its largest bearing number, at its
    /// highest speed (not at the stop time), from either film's clearance however it was set;
    /// --mesh, or a film's n_elem_phi / n_elem_z through --set, is the user's mesh and stays.
    #[test]
    fn run_up_chooses_the_film_mesh_by_the_largest_bearing_number() {
        use crate::runup::{film_mesh_for, DEFAULT_FILM_TOLERANCE, TWO_ACROSS_FILM_TOLERANCE};
        let g = crate::runup::GRADED_MESH_GRADING;
        let rule = |lambda| {
            let m = film_mesh_for(lambda);
            (m.along, m.across, m.grading, m.tolerance)
        };
        let (two, one) = (TWO_ACROSS_FILM_TOLERANCE, DEFAULT_FILM_TOLERANCE);
        assert_eq!(rule(8.8), (10, 2, g, two));
        assert_eq!(rule(10.0), (10, 2, g, two));
        assert_eq!(rule(10.01), (10, 3, g, one));
        assert_eq!(rule(20.0), (10, 3, g, one));
        assert_eq!(rule(20.01), (20, 4, 1.0, one));
        assert_eq!(rule(40.0), (20, 4, 1.0, one));
        assert_eq!(rule(40.01), (20, 6, 1.0, one));
        assert_eq!(rule(f64::NAN), (20, 6, 1.0, one));
        assert!(
            two[0] < one[0] && two[1] < one[1],
            "the coarser mesh integrates tighter"
        );

        // (flags, (along, across, grading), largest bearing number)
        type Case<'a> = (&'a [&'a str], (u32, u32, f64), f64);
        let cases: [Case; 8] = [
            (&[], (10, 2, g), lambda(20.0, 2000.0)),
            (&["--stop", "0.1"], (10, 2, g), lambda(20.0, 2000.0)),
            (&["--clearance", "15"], (10, 3, g), lambda(15.0, 2000.0)),
            (&["--clearance", "10"], (20, 4, 1.0), lambda(10.0, 2000.0)),
            (&["--clearance", "5"], (20, 6, 1.0), lambda(5.0, 2000.0)),
            // The smaller clearance of the two films decides (C 20 / 10 um).
            (
                &["--set", "film_T.C=10 um", "--contact", "film"],
                (20, 4, 1.0),
                lambda(10.0, 2000.0),
            ),
            // A profile's highest speed, not its last: 3000 Hz at 1 s.
            (
                &["--profile", "0:0,1:3000,2:0", "--clearance", "13"],
                (20, 4, 1.0),
                lambda(13.0, 3000.0),
            ),
            // The rotor's speed as its FMU gets it, a --set included.
            (
                &["--set", "rotor.f_max=5000 Hz"],
                (20, 4, 1.0),
                lambda(20.0, 5000.0),
            ),
        ];
        for (flags, mesh, expected_lambda) in cases {
            let s = settings_of(flags);
            assert_eq!(
                (s.n_elem_phi, s.n_elem_z, s.mesh_grading),
                mesh,
                "{flags:?}"
            );
            // The mesh's own tolerance: tighter on 10 x 2.
            let tolerance = if mesh.1 == 2 { two } else { one };
            assert_eq!(s.film_tolerance, Some(tolerance), "{flags:?}");
            let got = s.film_mesh_bearing_number.unwrap();
            assert!(
                close(got, expected_lambda),
                "{flags:?}: {got} against {expected_lambda}"
            );
            // The films get that mesh.
            for f in s.film_params().unwrap() {
                assert_eq!(
                    (f.n_elem_phi, f.n_elem_z, f.mesh_grading),
                    (mesh.0 as usize, mesh.1 as usize, mesh.2),
                    "{flags:?}"
                );
            }
        }

        // A tolerance given is kept with the chosen mesh; a mesh given keeps the default one.
        let s = settings_of(&["--film-tolerance", "2e-3,200"]);
        assert_eq!((s.n_elem_z, s.film_tolerance), (2, Some([2e-3, 200.0])));
        let s = settings_of(&["--mesh", "10x2", "--set", "film.mesh_grading=0.8"]);
        assert_eq!(s.film_tolerance, Some(one));

        // --mesh is a uniform mesh; a grading comes with --set film.mesh_grading.
        let s = settings_of(&["--mesh", "20x6", "--clearance", "10"]);
        assert_eq!((s.n_elem_phi, s.n_elem_z, s.mesh_grading), (20, 6, 1.0));
        assert_eq!(s.film_mesh_bearing_number, None);
        let s = settings_of(&["--mesh", "16x3"]);
        for f in s.film_params().unwrap() {
            assert_eq!((f.n_elem_phi, f.n_elem_z, f.mesh_grading), (16, 3, 1.0));
        }
        let s = settings_of(&["--mesh", "12x3", "--set", "film.mesh_grading=0.7"]);
        for f in s.film_params().unwrap() {
            assert_eq!((f.n_elem_phi, f.n_elem_z, f.mesh_grading), (12, 3, 0.7));
        }
        let e = refusal(&["--set", "film.mesh_grading=0.3"]);
        assert!(e.contains("mesh_grading"), "{e}");
        // A grading alone is a mesh given: it grades the paper's 20 x 6, not the chosen 10 x 2.
        for g in ["1", "0.9"] {
            let s = settings_of(&["--set", &format!("film.mesh_grading={g}")]);
            assert_eq!(s.film_mesh_bearing_number, None);
            for f in s.film_params().unwrap() {
                let want: f64 = g.parse().unwrap();
                assert_eq!((f.n_elem_phi, f.n_elem_z, f.mesh_grading), (20, 6, want));
            }
        }
        // A grading that crowds the lobe's last columns is refused with the least it takes.
        let e = refusal(&["--mesh", "40x3", "--set", "film.mesh_grading=0.7"]);
        assert!(
            e.contains("mesh_grading") && e.contains("at least 0.838"),
            "{e}"
        );
        let s = settings_of(&["--set", "film.n_elem_z=5"]);
        assert_eq!(s.film_mesh_bearing_number, None);
        for f in s.film_params().unwrap() {
            assert_eq!((f.n_elem_phi, f.n_elem_z), (20, 5));
        }
        // A bad film parameter is reported with its flag, not as a mesh problem.
        let e = refusal(&["--set", "film.eta=-1"]);
        assert!(e.contains("eta"), "{e}");
    }

    /// The run-up's first line names the films' mesh and tolerance as their FMUs get them.
    #[test]
    fn the_first_line_states_the_films_mesh_and_tolerance() {
        let line = crate::runup::describe_film_mesh(&settings_of(&[])).unwrap();
        assert!(
            line.starts_with(
                "film mesh 10 x 2 graded by 0.8 toward the trailing edge per lobe (for the \
                 largest bearing number 8.8"
            ) && line.ends_with(", film tolerance 6e-4 / 60 Pa"),
            "{line}"
        );
        let s = settings_of(&["--mesh", "20x6", "--set", "film_T.rtol=1e-4"]);
        let line = crate::runup::describe_film_mesh(&s).unwrap();
        assert_eq!(
            line,
            "film mesh 20 x 6 per lobe, film tolerance 1e-3 / 100 Pa (C) / 1e-4 / 100 Pa (T)"
        );
    }

    /// With the contact in the rotor both films must share one bore; the refusal names each
    /// quantity that differs, with both values in a design file's units, and only those.
    #[test]
    fn a_refused_pair_of_bores_names_what_differs() {
        let e = refusal(&["--set", "film_T.C=22 um"]);
        assert!(e.contains("(C 20 um / 22 um)"), "{e}");
        let e = refusal(&["--set", "film_T.r=16 mm", "--set", "film_C.c_con=2e16"]);
        assert!(
            e.contains("(r 15 mm / 16 mm, c_con 2e16 N/m^3 / 1e16 N/m^3)"),
            "{e}"
        );
        assert!(e.contains("--contact film"), "{e}");
        assert!(checked(&["--set", "film_T.C=22 um", "--contact", "film"]).is_ok());
    }

    /// A `--set` of the rotor's speed is what the run-up reports and runs to.
    #[test]
    fn the_rotor_speed_set_through_set_is_the_run_ups_own() {
        let s = settings_of(&["--set", "rotor.t_ramp=0.5", "--set", "rotor.f_max=500 Hz"]);
        assert_eq!((s.f_max_hz, s.t_ramp_s, s.stop_time_s), (500.0, 0.5, 0.5));
        assert!(
            s.describe_speed().starts_with("0 -> 500 Hz in 0.5 s"),
            "{}",
            s.describe_speed()
        );
        let s = settings_of(&["--set", "rotor.t_ramp=0.5", "--stop", "0.1"]);
        assert_eq!((s.f_max_hz, s.t_ramp_s, s.stop_time_s), (2000.0, 0.5, 0.1));
        // Without such a --set the flags' values stand.
        let s = settings_of(&["--f-max", "1500", "--t-ramp", "2"]);
        assert_eq!((s.f_max_hz, s.t_ramp_s, s.stop_time_s), (1500.0, 2.0, 2.0));
    }

    /// Rows are written at macro steps only: the default interval follows the macro step, and an
    /// interval of the user's that is not a whole number of macro steps is refused.
    #[test]
    fn the_output_interval_is_a_whole_number_of_macro_steps() {
        for (step, interval) in [
            ("50", 50.0),
            ("20", 40.0),
            ("33", 33.0),
            ("100", 100.0),
            ("10", 50.0),
        ] {
            let s = settings_of(&["--macro-step", step]);
            assert_eq!(s.output_interval_us, interval, "--macro-step {step}");
        }
        for (step, interval) in [("50", "73"), ("50", "1"), ("20", "50")] {
            let e = refusal(&["--macro-step", step, "--output-interval", interval]);
            assert!(
                e.starts_with(&format!("--output-interval = {interval} us must be a whole number of macro steps ({step} us)")),
                "{e}"
            );
        }
        let s = settings_of(&["--macro-step", "20", "--output-interval", "100"]);
        assert_eq!(s.output_interval_us, 100.0);
    }

    /// Values no run-up can mean are refused with the flag, the value and the bound.
    #[test]
    fn impossible_speeds_meshes_and_infinities_are_refused_by_name() {
        let e = refusal(&["--f-max", "1e9"]);
        assert!(e.starts_with("--f-max: 1e9 Hz is above 20000 Hz"), "{e}");
        let e = refusal(&["--profile", "0:0,1:30000"]);
        assert!(
            e.starts_with("--profile: 30000 Hz is above 20000 Hz"),
            "{e}"
        );
        let e = refusal(&["--set", "rotor.f_max=25000 Hz"]);
        assert!(e.starts_with("--f-max: 25000 Hz is above 20000 Hz"), "{e}");
        assert!(checked(&["--f-max", "20000"]).is_ok());
        let e = refusal(&["--clearance", "inf"]);
        assert_eq!(e, "--clearance = inf um must be a finite number > 0");
        let e = refusal(&["--dh", "inf"]);
        assert_eq!(e, "--dh = inf um must be a finite number >= 0");
        let e = refusal(&["--dh", "1e6"]);
        assert_eq!(e, "--dh = 1000000 um must lie between 0 um and 10000 um");
        let e = refusal(&["--clearance", "1e-6"]);
        assert_eq!(
            e,
            "--clearance = 1e-6 um must lie between 0.01 um and 10000 um"
        );
        let e = refusal(&["--stop", "1e9"]);
        assert_eq!(
            e,
            "--stop = 1e9 s takes 2.0e13 macro steps of 50 us (at most 1e9)"
        );
        let e = refusal(&["--macro-step", "0.001"]);
        assert_eq!(
            e,
            "--macro-step = 0.001 us must lie between 1 us and 1000 us"
        );
        let e = refusal(&["--macro-step", "2000"]);
        assert!(e.starts_with("--macro-step = 2000 us must lie"), "{e}");
        assert!(checked(&["--macro-step", "1"]).is_ok());
        let e = refusal(&["--interpolation-order", "3"]);
        assert_eq!(e, "--interpolation-order = 3 must be 0, 1 or 2");
        let e = refusal(&["--mesh", "3x2"]);
        assert!(e.contains("at least 4x2 elements per lobe"), "{e}");
        assert!(checked(&["--mesh", "4x2"]).is_ok());
        for (mesh, why) in [
            ("0x0", "too coarse"),
            ("2x200", "too coarse"),
            ("4x600", "too fine"),
        ] {
            let e = refusal(&["--mesh", mesh]);
            assert!(
                e.starts_with(&format!("--mesh '{mesh}': mesh {why}")),
                "{e}"
            );
        }
        // The linear prediction's mesh flag by the same rule (0x0 failed every point, exit 0).
        let e = crate::runup::parse_mesh("0x0", "--linear-mesh").unwrap_err();
        assert!(e.starts_with("--linear-mesh '0x0': mesh too coarse"), "{e}");
    }

    /// The design file of docs/design.md, as printed there, runs as a run-up with the default
    /// flags (it once held a second bore, which only `--contact film` takes).
    #[test]
    fn the_design_example_in_the_docs_runs_with_the_default_flags() {
        let doc = include_str!("../../../docs/design.md");
        let start = doc
            .find("```toml\n")
            .expect("a TOML block in docs/design.md")
            + 8;
        let end = start + doc[start..].find("```").unwrap();
        let path =
            std::env::temp_dir().join(format!("airring-design-doc-{}.toml", std::process::id()));
        std::fs::write(&path, &doc[start..end]).unwrap();
        let s = checked(&["--design", path.to_str().unwrap()]);
        let _ = std::fs::remove_file(&path);
        let s = s.unwrap();
        // A value the FMU refuses: the file, its entry, and the value in the FMU's units.
        std::fs::write(&path, "[bearing]\nmount_c = \"-5 N/mm\"\n").unwrap();
        let e = refusal(&["--design", path.to_str().unwrap()]);
        let _ = std::fs::remove_file(&path);
        assert_eq!(
            e,
            format!(
                "{}: [bearing] mount_c: rotor: invalid parameter c_C = -5000 N/m (-5 N/mm): \
                 must be >= 0",
                path.display()
            )
        );
        assert!(s
            .fmu_parameters
            .iter()
            .any(|(k, v)| k == "rotor.d_T" && v.contains("80")));
    }
}
