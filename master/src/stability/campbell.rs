//! Eigenvalues of the whole linearized system at one speed, with frequency-dependent films.
//!
//! The film impedance Z(nu) = K(nu) + i nu D(nu) is evaluated on a grid of whirl frequencies
//! (every `GRID_HZ`, lazily: only the grid cells the modes visit) and interpolated linearly in
//! between; this is the documented approximation (Z varies on the scale of the film's inverse
//! time constants, ~kHz, so a 50 Hz grid changes eigenvalues by far less than their own spread).
//! Each mode is then made self-consistent: starting from the modes with the static film
//! coefficients, the k-th mode (by frequency) of the system with the films taken at nu must have
//! Im(lambda) = nu: a scalar equation in nu per mode rank, solved by fixed-point then secant
//! steps to 1e-6 relative. A conjugate pair (nu < 0) sees the conjugate impedance,
//! so K(|nu|), D(|nu|) serve both whirl directions.

use super::equilibrium::SolvedBearing;
use super::structure::LinearRotor;
use fmu_rotor::FilmCoefficients;
use serde::Serialize;
use std::collections::HashMap;
use std::f64::consts::TAU;

/// Spacing of the frequency grid of the film coefficients [Hz].
pub const GRID_HZ: f64 = 50.0;
const MAX_ITERS: usize = 60;

/// Lazily filled table of one film's coefficients on the frequency grid.
pub struct ImpedanceTable<'a> {
    bearing: &'a SolvedBearing,
    table: HashMap<usize, FilmCoefficients>,
}

impl<'a> ImpedanceTable<'a> {
    pub fn new(bearing: &'a SolvedBearing) -> Self {
        ImpedanceTable {
            bearing,
            table: HashMap::new(),
        }
    }

    fn node(&mut self, i: usize) -> Result<FilmCoefficients, String> {
        if let Some(c) = self.table.get(&i) {
            return Ok(*c);
        }
        let (k, d) = self
            .bearing
            .lin
            .impedance(TAU * GRID_HZ * i as f64)
            .map_err(|e| e.to_string())?;
        let c = FilmCoefficients {
            k_n_m: k,
            d_n_s_m: d,
        };
        self.table.insert(i, c);
        Ok(c)
    }

    /// K and D at whirl frequency `nu_hz` (linear interpolation on the grid).
    pub fn at(&mut self, nu_hz: f64) -> Result<FilmCoefficients, String> {
        let x = nu_hz.abs() / GRID_HZ;
        let i = x.floor() as usize;
        let w = x - i as f64;
        let a = self.node(i)?;
        if w == 0.0 {
            return Ok(a);
        }
        let b = self.node(i + 1)?;
        let mut c = a;
        for r in 0..2 {
            for s in 0..2 {
                c.k_n_m[r][s] += w * (b.k_n_m[r][s] - a.k_n_m[r][s]);
                c.d_n_s_m[r][s] += w * (b.d_n_s_m[r][s] - a.d_n_s_m[r][s]);
            }
        }
        Ok(c)
    }

    /// Number of frequencies evaluated so far.
    pub fn evaluations(&self) -> usize {
        self.table.len()
    }
}

/// One self-consistent mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModeResult {
    pub freq_hz: f64,
    /// Re(lambda) [1/s]; > 0 is unstable.
    pub growth_per_s: f64,
    pub damping_ratio: f64,
    /// Logarithmic decrement 2 pi zeta / sqrt(1 - zeta^2) = -2 pi Re / Im.
    pub log_decrement: f64,
    pub whirl: String,
    /// Journal / ring orbit sizes and the node, from `ModeShape::describe`.
    pub description: String,
    /// Iterations of nu = Im(lambda).
    pub iterations: usize,
    /// nu = Im(lambda) / 2 pi was met to 1e-6 within the iteration limit; if not, the mode is the
    /// last iterate (its films taken at a frequency off its own), flagged in the printed table.
    pub converged: bool,
}

/// A non-oscillating (real) eigenvalue `re` [1/s] as a mode entry: frequency 0; a divergence
/// when `re` > 0.
pub fn real_mode(re: f64) -> ModeResult {
    ModeResult {
        freq_hz: 0.0,
        growth_per_s: re,
        damping_ratio: if re > 0.0 { -1.0 } else { 1.0 },
        // Undefined without oscillation: reported as 0 rather than a NaN.
        log_decrement: 0.0,
        whirl: "none".into(),
        description: if re > 0.0 {
            "non-oscillating: static divergence (a real eigenvalue > 0)".into()
        } else {
            "non-oscillating, overdamped".into()
        },
        iterations: 0,
        converged: true,
    }
}

fn result_of<R: LinearRotor>(m: &R::Mode, iterations: usize, converged: bool) -> ModeResult {
    let (re, im) = R::eigenvalue(m);
    ModeResult {
        freq_hz: R::freq_hz(m),
        growth_per_s: re,
        damping_ratio: R::damping_ratio(m),
        log_decrement: -TAU * re / im,
        whirl: if R::forward(m) {
            "forward".into()
        } else {
            "backward".into()
        },
        description: R::describe(m),
        iterations,
        converged,
    }
}

fn modes_with<R: LinearRotor>(
    rotor: &R,
    omega_rad_s: f64,
    tables: &mut [ImpedanceTable; 2],
    nu_hz: f64,
) -> Result<Vec<R::Mode>, String> {
    let films = [tables[0].at(nu_hz)?, tables[1].at(nu_hz)?];
    rotor.modes(omega_rad_s, &films)
}

/// All oscillating modes at `omega_rad_s`, each with film coefficients at its own frequency,
/// sorted by frequency; and the real eigenvalues [1/s] with the static film coefficients (exact
/// where it matters: a real eigenvalue crosses 0, a divergence, at nu = 0).
pub fn system_modes<R: LinearRotor>(
    rotor: &R,
    omega_rad_s: f64,
    bearings: &[SolvedBearing; 2],
) -> Result<(Vec<ModeResult>, Vec<f64>), String> {
    let mut tables = [
        ImpedanceTable::new(&bearings[0]),
        ImpedanceTable::new(&bearings[1]),
    ];
    let start = modes_with(rotor, omega_rad_s, &mut tables, 0.0)?;
    let films0 = [tables[0].at(0.0)?, tables[1].at(0.0)?];
    let real = rotor.real_eigenvalues(omega_rad_s, &films0)?;
    let mut out = Vec::with_capacity(start.len());
    let cap = rotor.mode_cap_hz();
    for (rank, m0) in start.iter().enumerate() {
        if cap.is_some_and(|c| R::freq_hz(m0) > c) {
            break;
        }
        // Mode `rank` (by frequency) of A(nu) defines g(nu) = Im(lambda_rank(nu)) / 2 pi - nu; its
        // root is the self-consistent mode. Fixed-point steps, then secant steps (ranks keep two
        // starting modes from converging onto the same eigenvalue).
        // None: at this nu the matrix has fewer oscillatory modes than `rank + 1` (heavy ring
        // damping makes a mode overdamped: a pair of negative real eigenvalues, which `modes`
        // does not list); such a mode has no whirl frequency and decays, so it is left out.
        let f_of = |tables: &mut [ImpedanceTable; 2], nu: f64| -> Result<Option<R::Mode>, String> {
            let ms = modes_with(rotor, omega_rad_s, tables, nu)?;
            Ok(ms.get(rank).cloned())
        };
        let mut nu = R::freq_hz(m0);
        let Some(mut current) = f_of(&mut tables, nu)? else {
            continue;
        };
        let mut g = R::freq_hz(&current) - nu;
        let mut prev: Option<(f64, f64)> = None;
        let mut iterations = 1;
        let mut lost = false;
        while g.abs() > 1e-6 * nu.abs() + 1e-6 && iterations < MAX_ITERS {
            let next = match prev {
                Some((nu0, g0)) if g != g0 && iterations > 2 => nu - g * (nu - nu0) / (g - g0),
                _ => nu + g,
            };
            prev = Some((nu, g));
            nu = next.max(0.0);
            match f_of(&mut tables, nu)? {
                Some(m) => current = m,
                None => {
                    lost = true;
                    break;
                }
            }
            g = R::freq_hz(&current) - nu;
            iterations += 1;
        }
        if !lost {
            let converged = g.abs() <= 1e-6 * nu.abs() + 1e-6;
            out.push(result_of::<R>(&current, iterations, converged));
        }
    }
    out.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
    // A real eigenvalue at round-off distance from 0 is neutral, not a divergence.
    let scale = out
        .iter()
        .map(|m| (TAU * m.freq_hz).hypot(m.growth_per_s))
        .chain(real.iter().map(|r| r.abs()))
        .fold(0.0, f64::max);
    let real = real
        .into_iter()
        .map(|r| if r.abs() <= 1e-9 * scale { 0.0 } else { r })
        .collect();
    Ok((out, real))
}
