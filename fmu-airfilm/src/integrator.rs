//! Transient film solver: variable-step BDF1/BDF2 with local error control and modified Newton.
//!
//! Time discretization: dP/dt at t_{n+1} = c0 P_{n+1} - hist, with
//!   BDF1: c0 = 1/h,                       hist = c0 P_n,
//!   BDF2: c0 = (1+2w)/((1+w) h), w = h/h_prev, hist = c0 P_n + w^2/((1+w) h) (P_n - P_{n-1}).
//! The first step is BDF1 from a constant predictor, the second BDF1 with a linear predictor,
//! then BDF2 with a quadratic predictor. The local error is estimated from corrector minus
//! predictor (Milne's device, variable-step constants) in a weighted RMS norm
//! (rtol |P| + atol/p_a). Each lobe is an independent block: its Newton iteration, Jacobian
//! (analytic) and banded LUs are its own. A block keeps two factorized matrices, for the two
//! sub-step sizes a master's macro step makes the step control alternate between; a sub-step
//! reuses the one whose coefficient c0 is nearest its own until Newton converges slowly, c0
//! differs by more than ~50 %, or the matrix is 40 steps old (`factor_slots`). The factors,
//! their c0, age and use are part of the serialized state, so clones and restored states continue
//! bit-identically.

use crate::error::FilmError;
use crate::factor_slots::{self, SlotInfo, SLOTS_PER_LOBE};
use crate::forces::{self, FilmOutputs};
use crate::geometry::{min_gap_m, GapField, Geometry};
use crate::linsolve::BandLu;
use crate::mesh::Mesh;
use crate::params::BearingParams;
use crate::reynolds::{self, Coeffs};
use crate::{contact, JournalState};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Newton tolerance on the weighted update norm (the local error tolerance is 1).
const NEWTON_TOL: f64 = 0.05;
const MAX_NEWTON_ITERS: usize = 7;
/// A reused matrix is given up as soon as its contraction rate predicts convergence only after
/// this many iterations: a fresh one costs about 7 iterations' work (assembly and factorization,
/// fmu-airfilm/BENCHMARKS.md) and converges in one or two. Path 1 used to spend a fifth of its
/// film iterations in solves that ran into `MAX_NEWTON_ITERS` with a stale matrix and then
/// refactorized anyway.
const MAX_PREDICTED_ITERS: f64 = 5.0;
/// A reused matrix whose solve took this many iterations or more is refactorized at its next
/// use: the gap has moved on since it was assembled (in a large whirl within a fraction of the
/// whirl period, long before `MAX_LU_AGE`), and the next solve would be slower still.
const SLOW_SOLVE_ITERS: usize = 4;
const MAX_LU_AGE: u32 = 40;
/// Sums of squares over the nodes (weighted norms) run in this many independent chains of
/// additions, which vectorize: one chain waits for each addition before the next (~4 cycles per
/// node, 1 599 nodes per norm). A sum in lanes rounds differently from one in node order.
const SUM_LANES: usize = 8;
/// Smallest sub-step before a Newton failure is reported.
const H_MIN_S: f64 = 1e-13;

/// Vacuum floor of the scaled pressure P = p / p_a (1e-3: 100 Pa at the paper's p_a). The
/// continuous isothermal Reynolds equation keeps p > 0, but the Galerkin discretization does not:
/// where the gap nearly closes (h at its floor, p h^3 tiny) the film is convection-dominated and
/// quadratic elements undershoot. In a violent whirl (C = 15 um, dH = 0, paper Section 4) an
/// iterate then went below zero in every sub-step down to 1e-13 s and the run could not go on.
/// Converged nodal values below the floor are raised to it and counted (`n_pressure_floored`,
/// an FMU output); in the Section 3 run-ups the floor never acts.
pub const P_FLOOR_REL: f64 = 1e-3;

/// A film's f64 factors (every slot of every lobe, without row interchanges) up to which its
/// solves read them as they are: 1 MB, one core's L2 on the project machine.
const F64_FACTORS_IN_CACHE_BYTES: usize = 1 << 20;

/// Whether the Newton solves should read factors rounded to f32: only where the film's f64
/// factors do not fit in a core's cache. On the paper mesh (1.46 MB per film) that paid when it
/// came (path 1 to 1.6 s with serial films 0.895; the Newton and Jacobian counts the same, the
/// onset 1e-10 s apart). On the run-ups' meshes (20 x 3: 0.46 MB, 20 x 4: 0.73 MB) it costs:
/// one lobe's solves with six lobes' matrices in turn 3.07 against 2.84 us at
/// 20 x 3 and 6.2-10.5 against 4.0-6.5 us at 20 x 4, the factorization with its rounding pass
/// 39-40 against 27-29 us at 20 x 4 (kernel bench).
fn single_precision_solves_pay(mesh: &Mesh) -> bool {
    let ldab = mesh.kl + mesh.ku + 1;
    let bytes = mesh.n_blocks * SLOTS_PER_LOBE * mesh.npb * ldab * std::mem::size_of::<f64>();
    bytes > F64_FACTORS_IN_CACHE_BYTES
}

/// Most memory a film's Newton matrices may take [bytes], by [`newton_matrix_bytes`]: the
/// paper's 20 x 6 mesh needs ~9 MB, 150 x 40 ~2.3 GB; 2000 x 500, inside the FMU's declared
/// ranges, would need ~4.6 TB (193 GB for one matrix), and an allocation that fails aborts the
/// process (the host's too) instead of returning an error.
pub const MAX_NEWTON_MATRIX_BYTES: f64 = 4e9;

/// Upper bound of the bytes a film's Newton matrices take with `p`'s mesh: every slot of every
/// lobe with its spare copies, each in band storage with room for pivoting (f64) and its f32
/// factors. The bandwidth is bounded from the numbering (`Mesh::new`): two phi lines of nodes,
/// four on a plain bore, whose lines alternate around the circumference.
pub fn newton_matrix_bytes(p: &BearingParams) -> f64 {
    let periodic = p.bore.plain_bore;
    let n_lines = if periodic {
        2 * p.n_elem_phi
    } else {
        2 * p.n_elem_phi + 1
    } as f64;
    let nz = (2 * p.n_elem_z + 1) as f64;
    let npb = n_lines * nz;
    let kl = if periodic {
        4.0 * nz + 2.0
    } else {
        2.0 * nz + 2.0
    };
    let per_matrix = npb * ((3.0 * kl + 1.0) * 8.0 + (2.0 * kl + 1.0) * 4.0);
    let matrices = p.bore.n_blocks() * SLOTS_PER_LOBE * (1 + MAX_SPARE_MATRICES_PER_SLOT);
    matrices as f64 * per_matrix
}

/// Counters of one `advance` call (or totals).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepStats {
    pub n_steps: usize,
    pub n_rejected: usize,
    pub n_newton_iters: usize,
    pub n_jacobians: usize,
    pub n_newton_failures: usize,
    /// Last accepted sub-step, s.
    pub h_last_s: f64,
    /// Nodal values raised to the vacuum floor [`P_FLOOR_REL`] in converged iterates. Not part
    /// of a serialized state (its format predates the floor): counts since the last restore.
    #[serde(skip)]
    pub n_pressure_floored: usize,
    /// Newton matrices factorized again with partial pivoting because elimination without row
    /// interchanges was not stable ([`crate::linsolve::GROWTH_LIMIT`]). Not part of a serialized
    /// state, like the floor's count.
    #[serde(skip)]
    pub n_pivoted_factorizations: usize,
}

impl StepStats {
    fn add(&mut self, o: &StepStats) {
        self.n_steps += o.n_steps;
        self.n_rejected += o.n_rejected;
        self.n_newton_iters += o.n_newton_iters;
        self.n_jacobians += o.n_jacobians;
        self.n_newton_failures += o.n_newton_failures;
        self.n_pivoted_factorizations += o.n_pivoted_factorizations;
        self.n_pressure_floored += o.n_pressure_floored;
        self.h_last_s = o.h_last_s;
    }
}

/// Why a Newton solve of one sub-step failed: the lobe (block) and the cause, for the error.
#[derive(Clone, Copy, Debug)]
struct NewtonFail {
    lobe: usize,
    cause: &'static str,
}

/// Scratch vectors: always fully overwritten before they are read, so a copy of a film (an FMU
/// state) does not carry them: `clone` gives empty ones (sized on the next step), `clone_from`
/// keeps the destination's.
#[derive(Debug, Default)]
struct Scratch {
    gap: GapField,
    res: Vec<f64>,
    hist: Vec<f64>,
    p_new: Vec<f64>,
    p_pred: Vec<f64>,
    wt: Vec<f64>,
    /// Factorized matrices off duty, for `matrix_to_refactor`; also not part of a copy.
    spare_lu: Vec<Arc<BandLu>>,
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Scratch::default()
    }

    fn clone_from(&mut self, _: &Self) {}
}

/// The whole state of one air film (pressure history, step size, Newton matrices).
#[derive(Debug, Serialize, Deserialize)]
pub struct AirFilm {
    params: BearingParams,
    mesh: Mesh,
    geom: Geometry,
    t_s: f64,
    /// Scaled nodal pressures P_n, P_{n-1}, P_{n-2} (all blocks).
    p: Vec<f64>,
    p1: Vec<f64>,
    p2: Vec<f64>,
    /// Last and second-last accepted step sizes, number of valid history levels.
    h1_s: f64,
    h2_s: f64,
    n_hist: usize,
    h_next_s: f64,
    /// Inputs at t_s.
    journal: JournalState,
    /// Factorized Newton matrices, [`SLOTS_PER_LOBE`] per block (slot i of block k at
    /// k * SLOTS_PER_LOBE + i; see [`factor_slots`]), whether each may be used, the c0 it was
    /// assembled with, its age and the sub-steps since it was last used (accepted sub-steps).
    /// Shared with the saved copies of this film (see `matrix_to_refactor`).
    lu: Vec<Arc<BandLu>>,
    lu_valid: Vec<bool>,
    lu_c0: Vec<f64>,
    lu_age: Vec<u32>,
    lu_idle: Vec<u32>,
    /// Last observed Newton contraction rate per slot (CVODE-style first-iteration test).
    newton_rate: Vec<f64>,
    totals: StepStats,
    #[serde(skip)]
    scratch: Scratch,
}

/// `clone_from` is the FMU state save and restore of a master that rolls back (every macro step
/// under macro-step control): it reuses the destination's buffers, copies the mesh and geometry
/// only when the parameters differ (they are functions of the parameters), and shares the
/// factorized Jacobians (reference counts; a film refactorizes into a matrix no copy holds,
/// `matrix_to_refactor`). That leaves the three pressure levels, ~40 kB on the paper mesh.
/// Copying each matrix that changed since the destination got it, 360 kB each, cost 12.7 s of a
/// 300 s run-up whose journals ride on their rings (C15/dH0/d50), where
/// a lobe refactorizes every third sub-step.
impl Clone for AirFilm {
    fn clone(&self) -> Self {
        let mut c = AirFilm {
            params: self.params.clone(),
            mesh: self.mesh.clone(),
            geom: self.geom.clone(),
            t_s: 0.0,
            p: vec![],
            p1: vec![],
            p2: vec![],
            h1_s: 0.0,
            h2_s: 0.0,
            n_hist: 0,
            h_next_s: 0.0,
            journal: JournalState::default(),
            lu: vec![],
            lu_valid: vec![],
            lu_c0: vec![],
            lu_age: vec![],
            lu_idle: vec![],
            newton_rate: vec![],
            totals: StepStats::default(),
            scratch: Scratch::default(),
        };
        c.clone_from(self);
        c
    }

    fn clone_from(&mut self, src: &Self) {
        // Destructured so that a new field fails to compile until it is copied here too.
        let AirFilm {
            params,
            mesh,
            geom,
            t_s,
            p,
            p1,
            p2,
            h1_s,
            h2_s,
            n_hist,
            h_next_s,
            journal,
            lu,
            lu_valid,
            lu_c0,
            lu_age,
            lu_idle,
            newton_rate,
            totals,
            scratch: _,
        } = src;
        if self.params != *params {
            self.params.clone_from(params);
            self.mesh.clone_from(mesh);
            self.geom.clone_from(geom);
        }
        self.t_s = *t_s;
        self.p.clone_from(p);
        self.p1.clone_from(p1);
        self.p2.clone_from(p2);
        (self.h1_s, self.h2_s, self.n_hist, self.h_next_s) = (*h1_s, *h2_s, *n_hist, *h_next_s);
        self.journal = *journal;
        self.lu.clone_from(lu);
        self.lu_valid.clone_from(lu_valid);
        self.lu_c0.clone_from(lu_c0);
        self.lu_age.clone_from(lu_age);
        self.lu_idle.clone_from(lu_idle);
        self.newton_rate.clone_from(newton_rate);
        self.totals = *totals;
    }
}

impl AirFilm {
    /// Err naming the first part whose size does not fit the mesh, for a state deserialized from
    /// bytes: a state saved by a build with another layout (e.g. one factorized matrix per lobe,
    /// before two) can pass the FMU's GUID check, which covers the interface only.
    pub fn check_layout(&self) -> Result<(), String> {
        let n = self.mesh.n_nodes();
        let n_slots = self.mesh.n_blocks * SLOTS_PER_LOBE;
        let sizes = [
            ("pressures", self.p.len(), n),
            ("pressure history 1", self.p1.len(), n),
            ("pressure history 2", self.p2.len(), n),
            ("factorized matrices", self.lu.len(), n_slots),
            ("matrix flags", self.lu_valid.len(), n_slots),
            ("matrix coefficients", self.lu_c0.len(), n_slots),
            ("matrix ages", self.lu_age.len(), n_slots),
            ("matrix idle counts", self.lu_idle.len(), n_slots),
            ("Newton rates", self.newton_rate.len(), n_slots),
        ];
        for (what, got, want) in sizes {
            if got != want {
                return Err(format!(
                    "{what}: {got} entries where this build's mesh and layout need {want} \
                     (a state saved by another version of the air film?)"
                ));
            }
        }
        let g = &self.geom;
        let nq = 3 * self.mesh.ne_phi;
        let n_q = self.mesh.n_blocks * nq;
        if g.nq != nq
            || [&g.cos_q, &g.sin_q, &g.step_q]
                .iter()
                .any(|v| v.len() != n_q)
            || !g.columns.fits(nq, self.mesh.npb)
            || !g.nodal.fits(self.mesh.n_blocks * self.mesh.npb)
        {
            return Err(
                "the geometry's tables do not fit the mesh (a state saved by another \
                        version of the air film?)"
                    .into(),
            );
        }
        if let Some(i) = self
            .lu
            .iter()
            .position(|lu| !lu.fits(self.mesh.npb, self.mesh.kl, self.mesh.ku))
        {
            return Err(format!(
                "factorized matrix {i} does not fit the mesh (a state saved by another version of \
                 the air film?)"
            ));
        }
        Ok(())
    }

    /// A film at ambient pressure everywhere, t = 0, centred journal at rest.
    pub fn new(params: BearingParams) -> Result<Self, FilmError> {
        params.validate()?;
        let mesh = Mesh::new(&params);
        let geom = Geometry::new(&params, &mesh);
        let n = mesh.n_nodes();
        let n_slots = mesh.n_blocks * SLOTS_PER_LOBE;
        Ok(AirFilm {
            lu: (0..n_slots)
                .map(|_| Arc::new(BandLu::new(mesh.npb, mesh.kl, mesh.ku)))
                .collect(),
            lu_valid: vec![false; n_slots],
            lu_c0: vec![0.0; n_slots],
            lu_age: vec![0; n_slots],
            lu_idle: vec![0; n_slots],
            newton_rate: vec![1.0; n_slots],
            h_next_s: params.h_init_s,
            params,
            mesh,
            geom,
            t_s: 0.0,
            p: vec![1.0; n],
            p1: vec![1.0; n],
            p2: vec![1.0; n],
            h1_s: 0.0,
            h2_s: 0.0,
            n_hist: 0,
            journal: JournalState::default(),
            totals: StepStats::default(),
            scratch: Scratch::default(),
        })
    }

    /// Replaces the pressure field by `p_rel` (P = p/p_a per node, e.g. a steady solution) at
    /// time `t_s` with inputs `journal`; the step history restarts (BDF1, initial step).
    pub fn set_pressures_rel(
        &mut self,
        t_s: f64,
        journal: JournalState,
        p_rel: &[f64],
    ) -> Result<(), FilmError> {
        if p_rel.len() != self.p.len() {
            return Err(FilmError::InvalidInput {
                what: "pressure vector length",
                value: p_rel.len() as f64,
                t_s,
            });
        }
        if let Some(v) = p_rel.iter().find(|v| !v.is_finite() || **v <= 0.0) {
            return Err(FilmError::InvalidInput {
                what: "scaled pressure",
                value: *v,
                t_s,
            });
        }
        crate::check_finite(&journal, t_s)?;
        self.p.copy_from_slice(p_rel);
        self.t_s = t_s;
        self.journal = journal;
        self.n_hist = 0;
        self.h_next_s = self.params.h_init_s;
        self.lu_valid.iter_mut().for_each(|v| *v = false);
        Ok(())
    }

    pub fn params(&self) -> &BearingParams {
        &self.params
    }
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }
    pub fn time_s(&self) -> f64 {
        self.t_s
    }
    pub fn journal(&self) -> JournalState {
        self.journal
    }
    /// Totals over the film's life.
    pub fn total_stats(&self) -> StepStats {
        self.totals
    }
    /// Scaled nodal pressures P = p/p_a, block after block (block-local numbering of `mesh()`).
    pub fn pressures_rel(&self) -> &[f64] {
        &self.p
    }
    /// Nodal absolute pressures (Pa).
    pub fn pressures_pa(&self) -> Vec<f64> {
        self.p.iter().map(|v| v * self.params.p_a_pa).collect()
    }

    /// Force and diagnostics at the current time.
    pub fn outputs(&self) -> FilmOutputs {
        outputs_for(&self.params, &self.mesh, &self.geom, &self.journal, &self.p)
    }

    /// Gas mass in the film times R T (J), at the current state.
    pub fn mass_times_rt_j(&self) -> f64 {
        let mut gap = GapField::default();
        self.geom
            .update(&self.journal, self.params.bore.c_m, &mut gap);
        forces::mass_times_rt_j(&self.params, &self.mesh, &gap, &self.p)
    }

    /// Gas mass outflow through the film boundary times R T (W), at the current state.
    pub fn mass_outflow_times_rt_w(&self) -> f64 {
        forces::mass_outflow_times_rt_w(&self.params, &self.mesh, &self.journal, &self.p)
    }

    /// Integrates from `t0_s` to `t0_s + h_s`; `journal(t)` gives the inputs inside the interval.
    /// On error the state stays at the last accepted sub-step (see the error's time).
    pub fn advance(
        &mut self,
        t0_s: f64,
        h_s: f64,
        journal: &dyn Fn(f64) -> JournalState,
    ) -> Result<StepStats, FilmError> {
        if !t0_s.is_finite() {
            return Err(FilmError::InvalidInput {
                what: "t0",
                value: t0_s,
                t_s: self.t_s,
            });
        }
        if !(h_s.is_finite() && h_s >= 0.0) {
            return Err(FilmError::InvalidInput {
                what: "step size",
                value: h_s,
                t_s: t0_s,
            });
        }
        let mut stats = StepStats::default();
        self.t_s = t0_s;
        if h_s == 0.0 {
            return Ok(stats);
        }
        self.ensure_scratch();
        let t_end = t0_s + h_s;
        let fixed = self.params.fixed_step_s > 0.0;
        let mut n_acc = 0usize;
        // After a rejection the next step must really be smaller: no stretching to the end.
        let mut just_rejected = false;
        let mut last_fail: Option<NewtonFail> = None;
        let result = loop {
            let t = self.t_s;
            let remaining = t_end - t;
            if remaining <= 1e-12 * h_s {
                break Ok(());
            }
            if n_acc >= self.params.max_substeps {
                break Err(FilmError::TooManySubsteps {
                    t_reached_s: t,
                    max_substeps: self.params.max_substeps,
                });
            }
            let proposal = if fixed {
                self.params.fixed_step_s
            } else {
                self.h_next_s.min(self.params.h_max_s)
            };
            let hs = if remaining <= proposal || (remaining <= 1.2 * proposal && !just_rejected) {
                remaining
            } else if remaining < 2.0 * proposal && !fixed {
                0.5 * remaining
            } else {
                proposal
            };
            let last = hs == remaining;
            let t_new = if last { t_end } else { t + hs };
            let j_new = journal(t_new);
            if let Err(e) = crate::check_finite(&j_new, t_new) {
                break Err(e);
            }
            let h_min_m = min_gap_m(&self.params.bore, &j_new);
            if h_min_m <= 0.0 {
                break Err(FilmError::BeyondContactLimit {
                    h_min_m,
                    t_s: t_new,
                });
            }
            just_rejected = true;
            match self.try_step(hs, &j_new, &mut stats) {
                Ok((err, order)) if fixed || err <= 1.0 => {
                    just_rejected = false;
                    self.accept(t_new, hs, j_new);
                    n_acc += 1;
                    stats.n_steps += 1;
                    stats.h_last_s = hs;
                    let ratio = step_ratio(err, order);
                    let ratio = if ratio > 1.0 && ratio < 1.25 {
                        1.0
                    } else {
                        ratio
                    };
                    let new = hs * ratio;
                    self.h_next_s = if hs < proposal && ratio >= 1.0 {
                        new.max(proposal)
                    } else {
                        new
                    };
                }
                Ok((err, order)) => {
                    stats.n_rejected += 1;
                    self.h_next_s = hs * step_ratio(err, order).min(0.9);
                }
                Err(fail) => {
                    stats.n_newton_failures += 1;
                    last_fail = Some(fail);
                    if fixed {
                        break Err(FilmError::NewtonFailure {
                            t_reached_s: t,
                            h_s: hs,
                            lobe: fail.lobe,
                            cause: fail.cause,
                        });
                    }
                    self.h_next_s = 0.25 * hs;
                    self.lu_valid.iter_mut().for_each(|v| *v = false);
                }
            }
            if self.h_next_s < H_MIN_S {
                let fail = last_fail.unwrap_or(NewtonFail {
                    lobe: 0,
                    cause: "step size below the minimum",
                });
                break Err(FilmError::NewtonFailure {
                    t_reached_s: t,
                    h_s: self.h_next_s,
                    lobe: fail.lobe,
                    cause: fail.cause,
                });
            }
        };
        self.totals.add(&stats);
        result.map(|_| stats)
    }

    fn ensure_scratch(&mut self) {
        let n = self.p.len();
        let s = &mut self.scratch;
        for v in [
            &mut s.res,
            &mut s.hist,
            &mut s.p_new,
            &mut s.p_pred,
            &mut s.wt,
        ] {
            v.resize(n, 0.0);
        }
    }

    fn accept(&mut self, t_new: f64, hs: f64, j_new: JournalState) {
        // Rotate history: p2 <- p1 <- p <- p_new (swaps, no copies of the big vectors).
        std::mem::swap(&mut self.p2, &mut self.p1);
        std::mem::swap(&mut self.p1, &mut self.p);
        std::mem::swap(&mut self.p, &mut self.scratch.p_new);
        self.h2_s = self.h1_s;
        self.h1_s = hs;
        self.n_hist = (self.n_hist + 1).min(2);
        self.t_s = t_new;
        self.journal = j_new;
        for a in self.lu_age.iter_mut().chain(self.lu_idle.iter_mut()) {
            *a = a.saturating_add(1);
        }
    }

    /// One BDF step of size `hs` from the current state. Ok((weighted error, order)) when Newton
    /// converged; the failing lobe and the cause when it did not.
    fn try_step(
        &mut self,
        hs: f64,
        j_new: &JournalState,
        stats: &mut StepStats,
    ) -> Result<(f64, usize), NewtonFail> {
        let prm = &self.params;
        let n = self.p.len();
        let (h1, h2) = (self.h1_s, self.h2_s);
        let s = &mut self.scratch;
        // BDF coefficients, predictor and error constant.
        let order;
        let c0;
        let fac;
        match self.n_hist {
            0 => {
                order = 1;
                c0 = 1.0 / hs;
                s.p_pred.copy_from_slice(&self.p);
                for i in 0..n {
                    s.hist[i] = c0 * self.p[i];
                }
                fac = 0.5;
            }
            1 => {
                order = 1;
                c0 = 1.0 / hs;
                let w = hs / h1;
                for i in 0..n {
                    s.p_pred[i] = self.p[i] + w * (self.p[i] - self.p1[i]);
                    s.hist[i] = c0 * self.p[i];
                }
                let (cc, cp) = (0.5 * hs * hs, 0.5 * hs * (hs + h1));
                fac = cc / (cc + cp);
            }
            _ => {
                order = 2;
                let w = hs / h1;
                c0 = (1.0 + 2.0 * w) / ((1.0 + w) * hs);
                let c1 = w * w / ((1.0 + w) * hs);
                // The quadratic through the last three levels at t + hs, y0 + hs f[01] + hs (hs
                // + h1) f[012], with its divided differences' divisions gathered into two
                // coefficients: no division per node (three per node were a third of the
                // samples outside the kernels in a step), and the loop vectorizes.
                let d01 = hs / h1 + hs * (hs + h1) / (h1 * (h1 + h2));
                let d12 = hs * (hs + h1) / (h2 * (h1 + h2));
                let levels = self.p.iter().zip(&self.p1).zip(&self.p2);
                for ((pred, hist), ((&y0, &y1), &y2)) in
                    s.p_pred.iter_mut().zip(s.hist.iter_mut()).zip(levels)
                {
                    *pred = y0 + d01 * (y0 - y1) - d12 * (y1 - y2);
                    *hist = c0 * y0 + c1 * (y0 - y1);
                }
                // Local truncation error of variable-step BDF2 (the interpolation error of the
                // derivative, h (h + h1) p'''/6, divided by c0) and of the quadratic predictor,
                // both per p'''. Without its factor hs (a length of time too few) cc would make
                // fac ~1 instead of 2/11 at equal steps: the estimate 5.5x too large and the
                // film's steps 1.8x too small.
                let cc = hs * hs * (hs + h1) * (hs + h1) / (6.0 * (2.0 * hs + h1));
                let cp = hs * (hs + h1) * (hs + h1 + h2) / 6.0;
                fac = cc / (cc + cp);
            }
        }
        let (rtol, atol) = (prm.rtol, prm.atol_pa / prm.p_a_pa);
        for (w, &p) in s.wt.iter_mut().zip(&self.p) {
            *w = 1.0 / (rtol * p.abs() + atol);
        }
        self.geom.update(j_new, prm.bore.c_m, &mut s.gap);
        let co = Coeffs {
            lambda: prm.bearing_number(j_new.omega_rad_s),
            tau_s: prm.squeeze_time_s(),
            c0_per_s: c0,
        };
        s.p_new.copy_from_slice(&s.p_pred);
        let npb = self.mesh.npb;
        for k in 0..self.mesh.n_blocks {
            let r = k * npb..(k + 1) * npb;
            let slots = k * SLOTS_PER_LOBE..(k + 1) * SLOTS_PER_LOBE;
            let infos: [SlotInfo; SLOTS_PER_LOBE] = std::array::from_fn(|i| SlotInfo {
                valid: self.lu_valid[slots.start + i],
                c0_per_s: self.lu_c0[slots.start + i],
                age: self.lu_age[slots.start + i],
                idle: self.lu_idle[slots.start + i],
            });
            let choice = factor_slots::choose(&infos, c0, MAX_LU_AGE);
            let m = slots.start + choice.slot;
            self.lu_idle[m] = 0;
            let mut need_jac = choice.refactor;
            let mut converged = Err(NewtonFail {
                lobe: k,
                cause: "no attempt",
            });
            for _attempt in 0..2 {
                if need_jac {
                    s.p_new[r.clone()].copy_from_slice(&s.p_pred[r.clone()]);
                    // Without row interchanges first: a third less memory for the solves to
                    // stream through, and stable on every Newton matrix seen (linsolve.rs,
                    // GROWTH_LIMIT). Where it is not, the matrix is assembled again and
                    // factorized with partial pivoting.
                    let lu = matrix_to_refactor(&mut self.lu[m], &mut s.spare_lu, &self.mesh);
                    // Modified Newton: the solves stream the factors at every iteration, and
                    // f32 halves that traffic where it does not fit in a core's cache (see
                    // `single_precision_solves_pay`).
                    lu.set_single_precision_solves(single_precision_solves_pay(&self.mesh));
                    self.lu_valid[m] = false;
                    let (gap, p_new) = (&s.gap, &s.p_new[r.clone()]);
                    let factored = lu.assemble_and_factor(|lu| {
                        reynolds::jacobian(&self.mesh, gap, k, co, p_new, lu)
                    });
                    // Both attempts failed (an error) or the second one served.
                    stats.n_pivoted_factorizations += usize::from(!matches!(factored, Ok(false)));
                    stats.n_jacobians += 1;
                    if factored.is_err() {
                        return Err(NewtonFail {
                            lobe: k,
                            cause: "singular Newton matrix",
                        });
                    }
                    self.lu_valid[m] = true;
                    self.lu_c0[m] = c0;
                    self.lu_age[m] = 0;
                    self.newton_rate[m] = 1.0;
                }
                match newton_block(
                    &self.mesh,
                    &s.gap,
                    k,
                    co,
                    &self.lu[m],
                    need_jac,
                    &mut s.p_new[r.clone()],
                    &s.hist[r.clone()],
                    &mut s.res[r.clone()],
                    &s.wt[r.clone()],
                    &mut self.newton_rate[m],
                    stats,
                ) {
                    Ok(iterations) => {
                        if !need_jac && iterations >= SLOW_SOLVE_ITERS {
                            // Aged out: `factor_slots::choose` refactorizes it at its next use.
                            self.lu_age[m] = self.lu_age[m].max(MAX_LU_AGE);
                        }
                        converged = Ok(());
                        break;
                    }
                    Err(_) if !need_jac => need_jac = true,
                    Err(cause) => {
                        converged = Err(NewtonFail { lobe: k, cause });
                        break;
                    }
                }
            }
            converged?;
        }
        // Local error estimate, RMS over the free nodes (a Dirichlet node's difference is 0).
        // The count is the mesh's, not counted per node: `i % npb` in this loop was an integer
        // division per node, 1 599 per sub-step on the paper mesh.
        let mut lanes = [0.0; SUM_LANES];
        let terms = s.p_new.iter().zip(&s.p_pred).zip(&s.wt);
        for (i, ((&new, &pred), &w)) in terms.enumerate() {
            let e = fac * (new - pred) * w;
            lanes[i % SUM_LANES] += e * e;
        }
        let sum: f64 = lanes.iter().sum();
        let cnt = self.mesh.n_blocks * self.mesh.dirichlet.iter().filter(|d| !**d).count();
        let err = (sum / cnt.max(1) as f64).sqrt();
        if !err.is_finite() {
            return Err(NewtonFail {
                lobe: 0,
                cause: "non-finite error estimate",
            });
        }
        Ok((err, order))
    }
}

/// Spare matrices a film keeps at most, per slot. A master that holds one saved copy (its
/// rollback state) needs one per slot: the copy's matrix and the film's alternate. The second
/// covers a master that also keeps a checkpoint; beyond that, spares still held by copies are
/// dropped from the list (the copies keep them alive) and new ones allocated when needed.
const MAX_SPARE_MATRICES_PER_SLOT: usize = 2;

/// The matrix in `slot`, to be assembled and factorized anew. Where a saved copy of the film
/// still holds it (an FMU state, the master's rollback copy), a spare that no copy holds any more
/// takes its place (a new one while there is none), and the held one joins the spares: saving a
/// state never copies a matrix, and refactorizing copies none either. The matrix's old contents
/// are never read: the Jacobian's assembly clears the band (`BandLu::zero`) and `set_pivoting`
/// sizes it.
fn matrix_to_refactor<'a>(
    slot: &'a mut Arc<BandLu>,
    spares: &mut Vec<Arc<BandLu>>,
    mesh: &Mesh,
) -> &'a mut BandLu {
    if Arc::get_mut(slot).is_none() {
        // A spare only this film refers to is nobody else's: no copy can reach it.
        let free = spares.iter().position(|m| Arc::strong_count(m) == 1);
        let fresh = match free {
            Some(i) => spares.swap_remove(i),
            None => Arc::new(BandLu::new(mesh.npb, mesh.kl, mesh.ku)),
        };
        spares.push(std::mem::replace(slot, fresh));
        let cap = MAX_SPARE_MATRICES_PER_SLOT * mesh.n_blocks * SLOTS_PER_LOBE;
        if spares.len() > cap {
            // The oldest first; a copy that still holds one keeps it alive.
            spares.drain(..spares.len() - cap);
        }
    }
    Arc::get_mut(slot).expect("no copy holds the slot's matrix now")
}

/// Step-size ratio from the weighted error of a step of order `order`.
fn step_ratio(err: f64, order: usize) -> f64 {
    if err <= 0.0 {
        return 2.0;
    }
    (0.9 * err.powf(-1.0 / (order as f64 + 1.0))).clamp(0.2, 2.0)
}

/// Further iterations, after one whose update had the weighted norm `norm`, until the updates,
/// shrinking by `rate` (0 < rate < 1) each, pass the convergence test
/// `norm_j rate / (1 - rate) < tol` (norm_j = norm rate^j).
fn further_iterations(norm: f64, rate: f64, tol: f64) -> f64 {
    ((tol * (1.0 - rate) / (norm * rate)).ln() / rate.ln()).max(0.0)
}

/// Modified Newton on one block with the factored matrix `lu` (`fresh`: just factorized).
/// The number of iterations when converged.
#[allow(clippy::too_many_arguments)]
fn newton_block(
    mesh: &Mesh,
    gap: &GapField,
    k: usize,
    co: Coeffs,
    lu: &BandLu,
    fresh: bool,
    p: &mut [f64],
    hist: &[f64],
    res: &mut [f64],
    wt: &[f64],
    rate_prev: &mut f64,
    stats: &mut StepStats,
) -> Result<usize, &'static str> {
    let mut norm_prev = f64::INFINITY;
    let mut rate = 0.0f64;
    let n = p.len();
    for it in 0..MAX_NEWTON_ITERS {
        reynolds::residual(mesh, gap, k, co, p, hist, None, res);
        lu.solve(res);
        stats.n_newton_iters += 1;
        let mut lanes = [0.0; SUM_LANES];
        for (i, ((p, &d), &w)) in p.iter_mut().zip(res.iter()).zip(wt).enumerate() {
            *p -= d;
            let e = d * w;
            lanes[i % SUM_LANES] += e * e;
        }
        let sum: f64 = lanes.iter().sum();
        let norm = (sum / n as f64).sqrt();
        if !norm.is_finite() {
            return Err("non-finite Newton update");
        }
        if it == 0 {
            // The contraction rate of the previous solve with this matrix predicts the error left
            // after the first update (CVODE's test); a fresh matrix has no history (rate 1).
            let r = rate_prev.clamp(0.2, 0.9);
            if norm * r / (1.0 - r) < NEWTON_TOL || norm < 0.1 * NEWTON_TOL {
                floor_pressure(p, stats);
                return Ok(1);
            }
        } else {
            rate = (norm / norm_prev).max(0.2 * rate);
            *rate_prev = rate;
            if rate >= 0.9 {
                return Err("Newton iteration diverges (contraction rate >= 0.9)");
            }
            if norm * rate / (1.0 - rate) < NEWTON_TOL {
                floor_pressure(p, stats);
                return Ok(it + 1);
            }
            if !fresh
                && (it + 1) as f64 + further_iterations(norm, rate, NEWTON_TOL)
                    > MAX_PREDICTED_ITERS
            {
                return Err("the reused Newton matrix converges too slowly");
            }
        }
        norm_prev = norm;
    }
    Err("no convergence within the iteration limit")
}

/// Raises converged nodal pressures below the vacuum floor to it (see [`P_FLOOR_REL`]).
fn floor_pressure(p: &mut [f64], stats: &mut StepStats) {
    for v in p.iter_mut() {
        // NaN is not reachable (the update norm was finite) but would be floored too.
        if v.is_nan() || *v < P_FLOOR_REL {
            *v = P_FLOOR_REL;
            stats.n_pressure_floored += 1;
        }
    }
}

/// Outputs for a pressure field (shared with the steady solver).
pub(crate) fn outputs_for(
    prm: &BearingParams,
    mesh: &Mesh,
    geom: &Geometry,
    j: &JournalState,
    p: &[f64],
) -> FilmOutputs {
    let fp = forces::pressure_force_n(prm, mesh, geom, p);
    let h_min_m = min_gap_m(&prm.bore, j);
    let fc = contact::contact_force_n(&prm.bore, &prm.contact, j, h_min_m);
    // In eight lanes, which vectorize (a running f64::max stays scalar); the same maximum for
    // the film's pressures, which are never NaN (floored, and a NaN update fails the step).
    let mut lanes = [f64::NEG_INFINITY; 8];
    let chunks = p.chunks_exact(8);
    let mut p_max = chunks
        .remainder()
        .iter()
        .fold(f64::NEG_INFINITY, |m, &v| m.max(v));
    for c in chunks {
        for i in 0..8 {
            lanes[i] = if c[i] > lanes[i] { c[i] } else { lanes[i] };
        }
    }
    p_max = lanes.iter().fold(p_max, |m, &v| m.max(v));
    let p_max = p_max * prm.p_a_pa;
    let in_force = if prm.contact_in_force { 1.0 } else { 0.0 };
    let friction_torque_nm = crate::friction::friction_torque(prm, mesh, geom, j, p).total_nm();
    FilmOutputs {
        fx_n: fp[0] + in_force * fc[0],
        fy_n: fp[1] + in_force * fc[1],
        fx_contact_n: fc[0],
        fy_contact_n: fc[1],
        f_contact_n: fc[0].hypot(fc[1]),
        eps: j.dx_m.hypot(j.dy_m) / prm.bore.c_m,
        h_min_m,
        p_max_pa: p_max,
        friction_torque_nm,
        power_loss_w: friction_torque_nm * j.omega_rad_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// f32 factors only where the f64 ones would not fit in a core's cache: the paper mesh, not
    /// the run-ups' 20 x 3 and 20 x 4; and a film on the paper mesh then solves with them.
    #[test]
    fn single_precision_solves_only_where_the_factors_do_not_fit_in_cache() {
        let mesh_for = |phi, z| {
            Mesh::new(&BearingParams {
                n_elem_phi: phi,
                n_elem_z: z,
                ..BearingParams::paper()
            })
        };
        assert!(single_precision_solves_pay(&mesh_for(20, 6)));
        assert!(!single_precision_solves_pay(&mesh_for(20, 4)));
        assert!(!single_precision_solves_pay(&mesh_for(20, 3)));
        for (z, f32_expected) in [(6, true), (3, false)] {
            let p = BearingParams {
                n_elem_z: z,
                ..BearingParams::paper()
            };
            let mut film = AirFilm::new(p).unwrap();
            let omega = 2.0 * PI * 500.0;
            let j = move |_t: f64| JournalState {
                dx_m: 4e-6,
                dy_m: -2e-6,
                vx_m_s: 0.0,
                vy_m_s: 0.0,
                omega_rad_s: omega,
            };
            film.advance(0.0, 1e-4, &j).unwrap();
            let used: Vec<bool> = film
                .lu
                .iter()
                .zip(&film.lu_valid)
                .filter(|(_, v)| **v)
                .map(|(lu, _)| lu.solves_in_single_precision())
                .collect();
            assert!(!used.is_empty(), "no factorized matrix after a step");
            assert!(used.iter().all(|&u| u == f32_expected), "{z}: {used:?}");
        }
    }

    /// The memory bound holds the meshes' real bandwidths (equal on a lobed bore), and a mesh
    /// inside the declared ranges whose matrices would not fit is refused by name instead of
    /// aborting on its allocation.
    #[test]
    fn the_newton_matrices_memory_is_bounded_and_checked_before_allocation() {
        for plain in [false, true] {
            for (phi, z) in [(8, 2), (20, 3), (20, 6), (33, 5), (60, 12)] {
                let p = BearingParams {
                    n_elem_phi: phi,
                    n_elem_z: z,
                    ..if plain {
                        BearingParams::plain_bore()
                    } else {
                        BearingParams::paper()
                    }
                };
                let mesh = Mesh::new(&p);
                let bound_kl = if plain {
                    4 * mesh.nz + 2
                } else {
                    2 * mesh.nz + 2
                };
                assert!(
                    mesh.kl <= bound_kl,
                    "{phi}x{z} plain {plain}: kl {}",
                    mesh.kl
                );
                if !plain {
                    assert_eq!(mesh.kl, bound_kl, "{phi}x{z}");
                }
                let one = BandLu::new(mesh.npb, mesh.kl, mesh.ku);
                let allocated = (one.ldab_for_test() * mesh.npb * 8) as f64;
                let matrices = (mesh.n_blocks * SLOTS_PER_LOBE * 3) as f64;
                assert!(newton_matrix_bytes(&p) >= matrices * allocated);
            }
        }
        let paper = BearingParams::paper();
        assert!(
            newton_matrix_bytes(&paper) < 1e7,
            "{}",
            newton_matrix_bytes(&paper)
        );
        let huge = BearingParams {
            n_elem_phi: 2000,
            n_elem_z: 500,
            ..paper.clone()
        };
        match huge.validate() {
            Err(e @ FilmError::MeshTooLarge { .. }) => assert!(
                e.to_string()
                    .starts_with("mesh n_elem_phi x n_elem_z = 2000 x 500 per lobe needs ~4"),
                "{e}"
            ),
            other => panic!("{other:?}"),
        }
        assert!(AirFilm::new(huge).is_err());
        let fine = BearingParams {
            n_elem_phi: 100,
            n_elem_z: 30,
            ..paper
        };
        assert!(fine.validate().is_ok());
    }

    /// The prediction against the sequence it models: updates shrinking geometrically pass the
    /// convergence test exactly after the predicted number of further iterations.
    #[test]
    fn predicted_iterations_match_a_geometric_contraction() {
        for (norm0, rate) in [(3.0, 0.5), (0.8, 0.3), (40.0, 0.7), (1.0, 0.25)] {
            let tol = NEWTON_TOL;
            let passes = |norm: f64| norm * rate / (1.0 - rate) < tol;
            let mut norm = norm0;
            let mut j = 0;
            while !passes(norm) {
                norm *= rate;
                j += 1;
            }
            let predicted = further_iterations(norm0, rate, tol);
            assert!(
                predicted <= j as f64 && predicted > j as f64 - 1.0,
                "norm {norm0}, rate {rate}: {predicted} predicted, {j} needed"
            );
        }
        assert_eq!(further_iterations(1e-3, 0.5, NEWTON_TOL), 0.0);
    }

    /// The state layout of the builds before two factorized matrices per lobe (one per lobe, no
    /// idle counts), written from a film of this build.
    #[derive(Serialize)]
    struct OneMatrixPerLobe<'a> {
        params: &'a BearingParams,
        mesh: &'a Mesh,
        geom: &'a Geometry,
        t_s: f64,
        p: &'a [f64],
        p1: &'a [f64],
        p2: &'a [f64],
        h1_s: f64,
        h2_s: f64,
        n_hist: usize,
        h_next_s: f64,
        journal: JournalState,
        lu: Vec<&'a BandLu>,
        lu_valid: Vec<bool>,
        lu_c0: Vec<f64>,
        lu_age: Vec<u32>,
        newton_rate: Vec<f64>,
        totals: StepStats,
    }

    /// A saved state of another layout passes the FMU's GUID check (the interface did not
    /// change); it must be refused with a reason, never stepped.
    #[test]
    fn a_state_of_the_one_matrix_layout_is_refused() {
        let prm = BearingParams {
            n_elem_phi: 6,
            n_elem_z: 2,
            ..BearingParams::paper()
        };
        let j = JournalState::at(0.3 * prm.bore.c_m, 0.0, 6000.0);
        let mut f = AirFilm::new(prm).unwrap();
        for i in 0..5 {
            f.advance(i as f64 * 1e-5, 1e-5, &|_| j).unwrap();
        }
        let same: AirFilm = bincode::deserialize(&bincode::serialize(&f).unwrap()).unwrap();
        assert_eq!(same.check_layout(), Ok(()));

        let every_first = |v: &[f64]| v.iter().step_by(SLOTS_PER_LOBE).copied().collect();
        let old = OneMatrixPerLobe {
            params: &f.params,
            mesh: &f.mesh,
            geom: &f.geom,
            t_s: f.t_s,
            p: &f.p,
            p1: &f.p1,
            p2: &f.p2,
            h1_s: f.h1_s,
            h2_s: f.h2_s,
            n_hist: f.n_hist,
            h_next_s: f.h_next_s,
            journal: f.journal,
            lu: f.lu.iter().step_by(SLOTS_PER_LOBE).map(|m| &**m).collect(),
            lu_valid: f.lu_valid.iter().step_by(SLOTS_PER_LOBE).copied().collect(),
            lu_c0: every_first(&f.lu_c0),
            lu_age: f.lu_age.iter().step_by(SLOTS_PER_LOBE).copied().collect(),
            newton_rate: every_first(&f.newton_rate),
            totals: f.totals,
        };
        let bytes = bincode::serialize(&old).unwrap();
        match bincode::deserialize::<AirFilm>(&bytes) {
            Err(e) => println!("refused by the decoder: {e}"),
            Ok(g) => {
                let e = g.check_layout().unwrap_err();
                assert!(e.contains("another version"), "{e}");
            }
        }
        // A matrix of the wrong size in the right number of slots.
        let mut g = f.clone();
        g.lu[1] = Arc::new(BandLu::new(4, 1, 1));
        assert!(g.check_layout().unwrap_err().contains("matrix 1"));
    }

    /// One order-2 step taken from exact history (a reference with 1/128 of the step): the
    /// step's error estimate must match its true local error, for equal steps and for a step
    /// twice and half its predecessors. The estimate is Milne's device, fac (p_new - p_pred), with
    /// the local truncation error of variable-step BDF2, h^2 (h + h1)^2 / (6 (2 h + h1)) p''', and
    /// the predictor's, h (h + h1) (h + h1 + h2) / 6 p'''. Before the fix the estimate was 6.3x
    /// the true error (the BDF2 constant lacked a factor h). rtol 1e-9 makes the local error
    /// (~40-200 tolerances) dwarf Newton's (at most NEWTON_TOL = 0.05 of one); the ratios, 1.10-1.15,
    /// tend to 1 as h shrinks (1.07 at h / 2): higher-order terms.
    #[test]
    fn order_two_error_estimate_matches_the_true_local_error() {
        let base = BearingParams {
            n_elem_phi: 8,
            n_elem_z: 3,
            rtol: 1e-9,
            atol_pa: 1e-4,
            ..BearingParams::paper()
        };
        let (e, w, om) = (0.4 * base.bore.c_m, 2.0 * PI * 400.0, 2.0 * PI * 1000.0);
        let orbit = move |t: f64| JournalState {
            dx_m: e * (w * t).cos(),
            dy_m: e * (w * t).sin(),
            vx_m_s: -e * w * (w * t).sin(),
            vy_m_s: e * w * (w * t).cos(),
            omega_rad_s: om,
        };
        let h = 8e-6;
        let fine = BearingParams {
            fixed_step_s: h / 128.0,
            ..base.clone()
        };
        let j0 = orbit(0.0);
        let mut reference = AirFilm::new(fine).unwrap();
        let steady = crate::steady_state(&reference.params, j0).unwrap();
        reference.set_pressures_rel(0.0, j0, &steady.p_rel).unwrap();
        // Reference pressures at t0 + k h / 2, k = -4..=2.
        let t0 = 2e-4;
        reference.advance(0.0, t0 - 2.0 * h, &orbit).unwrap();
        let mut at = vec![reference.p.clone()];
        for k in -3..=2 {
            let t = t0 + (k - 1) as f64 * 0.5 * h;
            reference.advance(t, 0.5 * h, &orbit).unwrap();
            at.push(reference.p.clone());
        }
        let p_ref = |k: i32| &at[(k + 4) as usize];
        // (step, previous step, the one before) in halves of h.
        for (hs, h1, h2) in [(2, 2, 2), (2, 1, 1), (1, 2, 2)] {
            let mut f = reference.clone();
            f.params = base.clone();
            f.t_s = t0;
            f.p.clone_from(p_ref(0));
            f.p1.clone_from(p_ref(-h1));
            f.p2.clone_from(p_ref(-h1 - h2));
            let half = |k: i32| k as f64 * 0.5 * h;
            (f.h1_s, f.h2_s, f.n_hist) = (half(h1), half(h2), 2);
            f.ensure_scratch();
            let mut stats = StepStats::default();
            let (estimate, order) = f
                .try_step(half(hs), &orbit(t0 + half(hs)), &mut stats)
                .unwrap();
            assert_eq!(order, 2);
            let atol = base.atol_pa / base.p_a_pa;
            let (mut sum, mut cnt) = (0.0, 0usize);
            for (i, (&p_new, &exact)) in f.scratch.p_new.iter().zip(p_ref(hs)).enumerate() {
                if !f.mesh.dirichlet[i % f.mesh.npb] {
                    let e = (p_new - exact) / (base.rtol * f.p[i].abs() + atol);
                    sum += e * e;
                    cnt += 1;
                }
            }
            let actual = (sum / cnt as f64).sqrt();
            let ratio = estimate / actual;
            println!(
                "steps {hs}/{h1}/{h2} x h/2: estimate {estimate:.3e}, actual {actual:.3e}, \
                 ratio {ratio:.3}"
            );
            assert!(
                actual > 20.0,
                "the local error must dominate Newton's ({actual})"
            );
            assert!((0.8..1.25).contains(&ratio), "estimate / actual = {ratio}");
        }
    }

    #[test]
    fn vacuum_floor_raises_and_counts_only_values_below_it() {
        let mut stats = StepStats::default();
        let mut p = [1.0, P_FLOOR_REL, 0.5 * P_FLOOR_REL, -0.2, f64::NAN, 3.0];
        floor_pressure(&mut p, &mut stats);
        assert_eq!(
            p[..5],
            [1.0, P_FLOOR_REL, P_FLOOR_REL, P_FLOOR_REL, P_FLOOR_REL]
        );
        assert_eq!(p[5], 3.0);
        assert_eq!(stats.n_pressure_floored, 3);
        let mut total = StepStats::default();
        total.add(&stats);
        total.add(&stats);
        assert_eq!(total.n_pressure_floored, 6);
    }

    /// A master saves the film before every macro step and restores it after a rejected one. The
    /// copy shares the factorized matrices; a refactorization after the save goes into a matrix
    /// no copy holds, so the copy's stay as they were (tests/transient.rs replays from such
    /// copies bit for bit), and the spares the film keeps for that stay bounded.
    #[test]
    fn a_saved_copy_shares_the_matrices_and_stepping_on_never_writes_into_them() {
        let prm = BearingParams {
            n_elem_phi: 6,
            n_elem_z: 2,
            ..BearingParams::paper()
        };
        let c = prm.bore.c_m;
        // A whirl of 0.4 C at 800 Hz: the gap moves enough for the lobes to refactorize.
        let orbit = |t: f64| {
            let a = 2.0 * PI * 800.0 * t;
            JournalState::at(0.4 * c * a.cos(), 0.4 * c * a.sin(), 6000.0)
        };
        let h = 1e-5;
        let mut f = AirFilm::new(prm).unwrap();
        let mut k = 0;
        let mut step = |f: &mut AirFilm, n: usize| {
            for _ in 0..n {
                f.advance(k as f64 * h, h, &orbit).unwrap();
                k += 1;
            }
        };
        step(&mut f, 20);
        let mut saved = f.clone();
        let cap = MAX_SPARE_MATRICES_PER_SLOT * f.lu.len();
        let mut refactorized_after_a_save = 0;
        for _round in 0..30 {
            saved.clone_from(&f);
            assert!(f.lu.iter().zip(&saved.lu).all(|(a, b)| Arc::ptr_eq(a, b)));
            let held: Vec<Arc<BandLu>> = saved.lu.clone();
            let jacobians = f.total_stats().n_jacobians;
            step(&mut f, 3);
            let refactorized = f.total_stats().n_jacobians - jacobians;
            refactorized_after_a_save += refactorized;
            // The copy still holds the very matrices it was saved with ...
            assert!(saved.lu.iter().zip(&held).all(|(a, b)| Arc::ptr_eq(a, b)));
            // ... and the film holds other ones where it refactorized.
            let moved =
                f.lu.iter()
                    .zip(&saved.lu)
                    .filter(|(a, b)| !Arc::ptr_eq(a, b))
                    .count();
            assert!(
                moved <= refactorized,
                "{moved} slots moved, {refactorized} refactorized"
            );
            assert!(refactorized == 0 || moved > 0);
            assert!(
                f.scratch.spare_lu.len() <= cap,
                "{}",
                f.scratch.spare_lu.len()
            );
        }
        assert!(
            refactorized_after_a_save >= 10,
            "only {refactorized_after_a_save} refactorizations: the test would mean nothing"
        );
    }
}
