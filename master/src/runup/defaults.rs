//! A run-up's defaults and limits: the variables it records, its macro steps, the film mesh by
//! the bearing number, tolerances, and the bounds of its flags. Each default says why it is what it
//! is; docs/convergence.md holds the studies behind them.

use super::ContactSide;

/// Variables every run-up records (the analysis and the plots read them by these names).
pub const RECORDED: &[&str] = &[
    "rotor.omega",
    "rotor.dx_C",
    "rotor.dy_C",
    "rotor.dx_T",
    "rotor.dy_T",
    "rotor.vx_C",
    "rotor.vy_C",
    "rotor.vx_T",
    "rotor.vy_T",
    "rotor.x_JC",
    "rotor.y_JC",
    "rotor.x_JT",
    "rotor.y_JT",
    "rotor.x_RC",
    "rotor.y_RC",
    "rotor.x_RT",
    "rotor.y_RT",
    "film_C.Fx",
    "film_C.Fy",
    "film_T.Fx",
    "film_T.Fy",
    "film_C.eps",
    "film_T.eps",
    "film_C.h_min",
    "film_T.h_min",
    "film_C.p_max",
    "film_T.p_max",
    // Contact force magnitudes (reported by the films whichever side evaluates the contact).
    "film_C.F_contact",
    "film_T.F_contact",
    // Friction of the films (wall shear): torque on the journal and dissipated power.
    "film_C.friction_torque",
    "film_T.friction_torque",
    "film_C.power_loss",
    "film_T.power_loss",
];

/// Default macro step and polynomial orders (see docs/convergence.md for the study behind them).
/// 50 us with a second-order extrapolation of the rotor's inputs: against 20 us with first order
/// the same class in all 42 Section 4 cells and the three
/// Section 3 presets, onsets within 0.4 % of 10 us references, eccentricities within 1.8 %, the
/// Section 4 study in 0.48x of its wall time. `--macro-step 20 --extrapolation-order 1` remains
/// for cross-checks. 100 us was not adopted (weakly unstable whirls become visible up to 6.7 %
/// early with either order).
pub const DEFAULT_MACRO_STEP_US: f64 = 50.0;
/// Default macro step while the rotor is calm [us] (`crate::calm_steps`): where every mode of the
/// linearized rotor has a damping ratio of `calm_steps::CALM_DAMPING_RATIO` (0.02) or more,
/// before any instability. 100 us is the air films' own largest step (`h_max`), so they take one
/// sub-step per macro step there instead of two.
pub const DEFAULT_CALM_MACRO_STEP_US: f64 = 100.0;
/// The film mesh of a run-up without `--mesh`, for the largest bearing number `lambda` of the run
/// ([`RunupSettings::largest_bearing_number`]), and the films' tolerance with it: 10 x 2 graded
/// toward each lobe's trailing edge up to lambda = 10 (C >= 18.7 um at 2000 Hz) at
/// [`TWO_ACROSS_FILM_TOLERANCE`], 10 x 3 graded up to 20 (C >= 13.3 um), 20 x 4 uniform up to 40
/// (C >= 9.4 um), the paper's 20 x 6 above (and where lambda is not a number), these three at
/// [`DEFAULT_FILM_TOLERANCE`].
///
/// Across the half width: the pressure is nearly a parabola, which one biquadratic element
/// holds, except in an edge layer that narrows as lambda grows (docs/convergence.md, "Film mesh
/// across the width"): against 20 x 6, with [`DEFAULT_FILM_TOLERANCE`] path 1 in 0.60
/// and the Section 4 study in 0.56 of the time, the same class in all 42 cells, onsets within
/// 0.17 % and eccentricities within 0.91 % of the paper mesh. C10/dH20/c1500/d50 (lambda 35) is
/// 0.71 % off a reference at 10 us on a 40 x 12 mesh at 20 x 4, 1.03 % at 20 x 3.
///
/// Along the lobe, 16 elements instead of the paper's 20 where lambda <= 20 (docs/
/// convergence.md, "Film mesh along the lobe"): against 20 x 3 the same class in all 42 Section
/// 4 cells, onsets within 0.22 %, eccentricities within 1.6 %, and in the two cells whose slowly
/// growing whirls the films' errors can seed early, nine disturbance seeds each within 0.052 %;
/// path 1 0.032 % off and its eccentricities within 1 % of a 40 x 12 mesh; path 1 in ~0.8 of the
/// time.
///
/// Where lambda <= 20, 10 elements along the lobe graded by [`GRADED_MESH_GRADING`] toward its
/// trailing edge (docs/convergence.md, "A graded film mesh"): the error of a
/// uniform mesh sits in the trailing edge's last column, and 10 graded elements (147 nodes per
/// lobe) hold path 1's onset 0.021 % and its eccentricities 0.56 % from a 40 x 12 mesh, where
/// 16 uniform ones were 0.032 % and 0.99 % off (C15/dH45/c1000/d50: 0.23 % and 0.57 %, 16 x 3
/// 0.37 % and 1.63 %); path 1 in ~0.7 of the time.
///
/// Two elements across the half width where lambda <= 10 (docs/convergence.md,
/// "Two elements across the half width"): 105 nodes per lobe instead of 147 and a narrower band;
/// at 6e-4 / 60 Pa path 1's onset 0.067 % and its eccentricities 0.57 % from a 40 x 12 mesh,
/// paths 2a and 2b 0.24 % from their 10 us references, the Section 4 study the same class in all
/// 42 cells, onsets within 0.20 % and eccentricities within 1.29 % of 10 x 3; path 1 whole
/// process in 0.83 of the time.
pub fn film_mesh_for(lambda: f64) -> FilmMesh {
    let mesh = |along, across, grading, tolerance| FilmMesh {
        along,
        across,
        grading,
        tolerance,
    };
    if lambda <= TWO_ACROSS_MAX_BEARING_NUMBER {
        mesh(10, 2, GRADED_MESH_GRADING, TWO_ACROSS_FILM_TOLERANCE)
    } else if lambda <= 20.0 {
        mesh(10, 3, GRADED_MESH_GRADING, DEFAULT_FILM_TOLERANCE)
    } else if lambda <= 40.0 {
        mesh(20, 4, 1.0, DEFAULT_FILM_TOLERANCE)
    } else {
        mesh(20, 6, 1.0, DEFAULT_FILM_TOLERANCE)
    }
}

/// A run-up's own film mesh ([`film_mesh_for`]) and the films' tolerance with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmMesh {
    /// Elements along each lobe.
    pub along: u32,
    /// Elements across the half width.
    pub across: u32,
    /// The films' `mesh_grading` (1: uniform).
    pub grading: f64,
    /// The films' time-integration tolerance [rtol, atol in Pa].
    pub tolerance: [f64; 2],
}

/// Largest bearing number up to which a run-up's films take two elements across the half width
/// ([`film_mesh_for`]): C >= 18.7 um at 2000 Hz, the Section 3 presets and the C = 20 and 30 um
/// cells of Section 4.
pub const TWO_ACROSS_MAX_BEARING_NUMBER: f64 = 10.0;

/// The films' tolerance [rtol, atol in Pa] on the run-ups' 10 x 2 mesh ([`film_mesh_for`]). At
/// [`DEFAULT_FILM_TOLERANCE`] its accepted errors seeded C30/dH60/c1000/d500's slowly growing
/// whirl 5-7 % early in two of nine disturbance seeds (1e-4 / 10 Pa on the same mesh: within
/// 0.07 % of 10 x 3); at 6e-4 / 60 Pa all nine, and the nine of each of the two cells that coarse
/// films had seeded early before, are within 0.13 % of 10 x 3 (docs/convergence.md, "Two
/// elements across the half width").
pub const TWO_ACROSS_FILM_TOLERANCE: [f64; 2] = [6e-4, 60.0];

/// The grading of the run-ups' graded film mesh ([`film_mesh_for`]): each element along a lobe
/// 0.8 times the one before it, the last of ten 0.13 of the first.
pub const GRADED_MESH_GRADING: f64 = 0.8;

/// The highest rotor speed a run-up takes [Hz]: ten times the paper's top speed. Far above it the
/// model has no meaning, and the calm-step planning would analyse a speed every 50 Hz up to it.
pub const MAX_SPEED_HZ: f64 = 20_000.0;

/// Smallest macro step a run-up takes [us]: 3 million macro steps for the 3 s run-up (the
/// shipped 50 us take 60 000), far below any step whose coupling error matters; a mistyped
/// 0.001 (1 ns) would have run for days without a word.
pub const MIN_MACRO_STEP_US: f64 = 1.0;
/// Largest macro step [us]: two revolutions at the paper's top speed (2000 Hz). The input
/// polynomials could not follow the imbalance forcing over such a step.
pub const MAX_MACRO_STEP_US: f64 = 1000.0;

/// Default interval of the recorded time series [us].
pub const DEFAULT_OUTPUT_INTERVAL_US: f64 = 50.0;
/// Largest internal step of the rotor FMU in a run-up [us] (its own default is 100 us). The
/// rotor's error control cannot see a whirl of nanometres against an equilibrium of micrometres
/// (atol 10 nm, rtol 1e-4), so its step grows to the macro step; at a 100 us macro step BDF2
/// damps the slowly growing whirl enough to delay path 2a's onset by 2.1 % (1.8287 -> 1.8677 s),
/// with this cap by 0.1 %. At a 20 us macro step it changes nothing: the rotor never steps past
/// a macro step (docs/convergence.md).
pub const ROTOR_MAX_STEP_US: f64 = 20.0;
/// Default air-film tolerances of a run-up [rtol, atol in Pa]: 10x looser than the FMU's own
/// defaults (Section 3 onsets within 1e-5, eccentricities within 0.2 %, 1.5x faster). 3e-3 /
/// 300 Pa sufficed on the paper's 20 x 6 mesh; with the coarser meshes of
/// [`film_mesh_for`] the film's accepted errors at 3e-3 seeded a slowly growing whirl early
/// (C30/dH60/c1500/d500 at 20 x 3: onsets 3-6 % early in 3 of 9 disturbance seeds), at 1e-3 all
/// nine onsets are within 0.1 % of the paper mesh's (docs/convergence.md, "Film mesh across
/// the width"). 1e-2 / 1000 Pa moved a ring-riding whirl's eccentricity by 3.5 %.
pub const DEFAULT_FILM_TOLERANCE: [f64; 2] = [1e-3, 100.0];
/// Default side of the contact evaluation: the rotor (implicit). Where no journal touches its ring
/// (the Section 3 run-ups) both sides compute the same thing, the contact force being zero (path 1
/// and 2b: the same onsets to the last digit); where one does, the rotor side needs no macro-step
/// refinement for the contact and let no journal cross the contact limit in the Section 4 study
/// (docs/convergence.md).
pub const DEFAULT_CONTACT: ContactSide = ContactSide::Rotor;
/// Default macro-step control: [rtol, atol in N] of the extrapolated bearing forces. 0.3, 3
/// rather than 0.1, 1: where journals ride on their rings the control refines less (C15/
/// dH0/d50: macro sub-steps 1.15 M -> 0.51 M), with the same class in all 42 cells of the
/// Section 4 study, onsets within 0.1 %, eccentricities within 0.92 %, the C30 fall within 0.44 um
/// of a 0.3125 us reference (0.42 um at 0.1, 1); path 1 and 2a never refine (docs/convergence.md).
pub const DEFAULT_STEP_CONTROL: [f64; 2] = [0.3, 3.0];
/// Second order: the coupling's damping error shrinks like h^(order + 1), which matters for weak
/// whirls. Path 2b's onset against a 10 us reference: +0.15 % at 50 us with order 2, -4.8 % at
/// 100 us with order 1 (docs/convergence.md).
pub const DEFAULT_EXTRAPOLATION_ORDER: u8 = 2;
pub const DEFAULT_INTERPOLATION_ORDER: u8 = 1;
/// Default journal disturbance [mN] (see docs/stability.md, "The whirl seed").
pub const DEFAULT_DISTURBANCE_MN: f64 = 0.001;
