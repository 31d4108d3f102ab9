//! The co-simulated rotor in its films as a [`Flow`] over the full state: the rotor's lateral
//! state and both films' free pressures (scaled p / p_a at every node not held at ambient
//! pressure: ~1 600 per film on the paper mesh). A flow restores the base with the rotor
//! restarted at the given lateral state and each film restarted with the given pressures, so
//! the period map includes the films' memory; the reduced shooting ([`RotorFilmFlow`] alone)
//! keeps the base's pressures and relaxes them afterwards. Too large for a monodromy matrix: it
//! is shot by Newton-Krylov (`krylov.rs`).
//!
//! The boundary nodes (p = p_a) are left out: the film never changes them, so a perturbation
//! of one would stay for ever (a spurious Floquet multiplier 1 per node).

use super::cosim_flow::RotorFilmFlow;
use super::shooting::Flow;

/// Typical magnitude of a scaled film pressure (p / p_a) in the shooting's scaled unknowns:
/// finite-difference steps (`fd_rel` times this) must stand well above the films' solver
/// tolerance (atol 10 Pa = 1e-4 p_a), and the periodicity tolerance is relative to it.
pub const PRESSURE_SCALE: f64 = 1.0;

pub struct FullStateFlow<'a> {
    pub inner: &'a mut RotorFilmFlow,
    /// The base's pressure fields (C, T): the fixed nodes keep these values.
    base_pressures: [Vec<f64>; 2],
    /// Indices of the free pressure nodes per film (C, T).
    free: [Vec<usize>; 2],
}

impl<'a> FullStateFlow<'a> {
    pub fn new(inner: &'a mut RotorFilmFlow) -> Result<Self, String> {
        let base_pressures = inner.base_pressures()?;
        let fixed = inner.fixed_pressure_nodes()?;
        let free = fixed.map(|f| (0..f.len()).filter(|i| !f[*i]).collect::<Vec<usize>>());
        Ok(FullStateFlow {
            inner,
            base_pressures,
            free,
        })
    }

    /// Lateral state, then the free pressures of film C and of film T.
    fn pack(&self, lateral: Vec<f64>, p: &[Vec<f64>; 2]) -> Vec<f64> {
        let mut x = lateral;
        for b in 0..2 {
            x.extend(self.free[b].iter().map(|&i| p[b][i]));
        }
        x
    }

    /// The full state at the base point.
    pub fn base_state(&self) -> Result<Vec<f64>, String> {
        Ok(self.pack(self.inner.base_lateral_state()?, &self.base_pressures))
    }

    /// Both films' whole pressure fields from a full state.
    fn unpack(&self, x: &[f64]) -> [Vec<f64>; 2] {
        let mut p = self.base_pressures.clone();
        let mut k = self.inner.n_lateral();
        for b in 0..2 {
            for &i in &self.free[b] {
                p[b][i] = x[k];
                k += 1;
            }
        }
        p
    }
}

impl Flow for FullStateFlow<'_> {
    fn dim(&self) -> usize {
        self.inner.n_lateral() + self.free[0].len() + self.free[1].len()
    }

    fn scale(&self) -> Vec<f64> {
        let mut s = self.inner.scale();
        s.resize(self.dim(), PRESSURE_SCALE);
        s
    }

    fn flow(&mut self, x0: &[f64], at_s: &[f64]) -> Result<Vec<Vec<f64>>, String> {
        if x0.len() != self.dim() {
            return Err(format!(
                "a full state has {} values, not {}",
                self.dim(),
                x0.len()
            ));
        }
        let p = self.unpack(x0);
        self.inner
            .start_with(&x0[..self.inner.n_lateral()], Some([&p[0], &p[1]]))?;
        let free = self.free.clone();
        self.inner.states_at(at_s, &|f: &RotorFilmFlow| {
            let p = f.pressures_now()?;
            let mut x = f.lateral_state()?;
            for b in 0..2 {
                x.extend(free[b].iter().map(|&i| p[b][i]));
            }
            Ok(x)
        })
    }

    fn measures(&mut self, x0: &[f64], period_s: f64) -> Result<Vec<(String, f64)>, String> {
        let p = self.unpack(x0);
        let m = self.inner.orbit_measures_with(
            &x0[..self.inner.n_lateral()],
            Some([&p[0], &p[1]]),
            period_s,
        )?;
        Ok(super::cosim_flow::measures_list(&m))
    }
}
