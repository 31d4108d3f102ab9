//! Frequency-dependent linearized film coefficients K_ij(nu), D_ij(nu) from the FE model.
//!
//! About a steady state P0 (journal at rest at (dx, dy), speed Omega) the journal moves as
//! e = e0 + eps_j e^{i nu t} (e = d / C); the pressure answers P = P0 + P1 e^{i nu t}. Linearizing
//! the Galerkin residual of reynolds.rs (same weak form, same quadrature) gives per lobe
//!
//!   (J + i nu M) P1 = -(R_e + i nu R_v) eps_j,
//!
//! J = dF/dP (the steady analytic Jacobian, c0 = 0), M_ab = Int tau H0 N_a N_b (the d(PH)/dt term
//! acting on P), R_e = dF/de_j through H and dH/dphi, R_v = dF/d(de_j/dt) through the squeeze term
//! tau P dH/dt. The force perturbation F1 = -2 p_a r^2 Int P1 (cos theta, sin theta) gives the
//! impedance Z_ij = -F1_i / d_j = K_ij(nu) + i nu D_ij(nu) (forces on the journal, F = -K d - D d').
//! Gas compressibility (P H in the time derivative) is what makes Z depend on nu.
//!
//! The complex system is solved as a real one with interleaved (Re, Im) unknowns, so the existing
//! banded LU applies with half bandwidth 2 kl + 1. At nu = 0 only real solves are needed:
//! J P1 = -R_e gives K(0) and J P1' = -(R_v + M P1) gives D(0) = lim Im Z / nu.
//! The contact penalty (a position-only force) adds its stiffness by central differences.
//! Where the gap is floored (h <= h_floor, see geometry.rs) H does not depend on e, as in the
//! residual.

use crate::contact::contact_force_n;
use crate::error::FilmError;
use crate::forces::pressure_force_n;
use crate::geometry::{min_gap_m, GapField, Geometry};
use crate::linsolve::BandLu;
use crate::mesh::Mesh;
use crate::params::BearingParams;
use crate::reynolds::{self, Coeffs};
use crate::steady::{steady_state, SteadySolution};
use crate::JournalState;

/// 2x2 matrix, row = force component (x, y), column = displacement direction (x, y).
pub type Mat2 = [[f64; 2]; 2];

/// Linearized operators of one lobe (block-local numbering; Dirichlet rows are identity / zero).
struct BlockLin {
    /// dF/dP at the steady state (unfactored band storage).
    j: BandLu,
    /// tau H0 N_a N_b (same band).
    m: BandLu,
    /// dF/de_x, dF/de_y (e = d / C).
    r_e: [Vec<f64>; 2],
    /// dF/d(de_x/dt), dF/d(de_y/dt) [s].
    r_v: [Vec<f64>; 2],
}

/// The film linearized about one steady state; `impedance(nu)` is cheap to call repeatedly
/// (one banded factorization per lobe and frequency).
pub struct FilmLinearization {
    params: BearingParams,
    journal: JournalState,
    steady: SteadySolution,
    geom: Geometry,
    blocks: Vec<BlockLin>,
    /// Contact stiffness [N/m] (zero unless the gap is below h_con somewhere).
    k_contact: Mat2,
}

impl FilmLinearization {
    /// Steady state at `journal` (velocities are ignored: the linearization is about rest) and
    /// the linearized operators about it.
    pub fn new(params: &BearingParams, journal: JournalState) -> Result<Self, FilmError> {
        let j0 = JournalState::at(journal.dx_m, journal.dy_m, journal.omega_rad_s);
        let steady = steady_state(params, j0)?;
        Self::from_steady(params, j0, steady)
    }

    /// As `new`, from an already converged steady solution at `journal` (journal at rest).
    pub fn from_steady(
        params: &BearingParams,
        journal: JournalState,
        steady: SteadySolution,
    ) -> Result<Self, FilmError> {
        params.validate()?;
        crate::check_finite(&journal, 0.0)?;
        let mesh = &steady.mesh;
        let geom = Geometry::new(params, mesh);
        let mut gap = GapField::default();
        geom.update(&journal, params.bore.c_m, &mut gap);
        let co = Coeffs {
            lambda: params.bearing_number(journal.omega_rad_s),
            tau_s: params.squeeze_time_s(),
            c0_per_s: 0.0,
        };
        let npb = mesh.npb;
        let mut blocks = Vec::with_capacity(mesh.n_blocks);
        for k in 0..mesh.n_blocks {
            let pb = &steady.p_rel[k * npb..(k + 1) * npb];
            let mut j = BandLu::new(npb, mesh.kl, mesh.ku);
            reynolds::jacobian(mesh, &gap, k, co, pb, &mut j);
            blocks.push(assemble_block(params, mesh, &geom, &journal, k, co, pb, j));
        }
        let k_contact = contact_stiffness(params, &journal);
        Ok(FilmLinearization {
            params: params.clone(),
            journal,
            steady,
            geom,
            blocks,
            k_contact,
        })
    }

    pub fn steady(&self) -> &SteadySolution {
        &self.steady
    }

    pub fn journal(&self) -> JournalState {
        self.journal
    }

    /// Stiffness K(nu) [N/m] and damping D(nu) [N s/m] at whirl frequency `nu_rad_s` (>= 0;
    /// a negative nu gives the complex conjugate impedance, i.e. the same K and D).
    pub fn impedance(&self, nu_rad_s: f64) -> Result<(Mat2, Mat2), FilmError> {
        if !nu_rad_s.is_finite() {
            return Err(FilmError::InvalidInput {
                what: "nu",
                value: nu_rad_s,
                t_s: 0.0,
            });
        }
        let nu = nu_rad_s.abs();
        let (z_re, z_im_over_nu) = if nu == 0.0 {
            self.response_static()?
        } else {
            self.response_harmonic(nu)?
        };
        let c = self.params.bore.c_m;
        let mut k = [[0.0; 2]; 2];
        let mut d = [[0.0; 2]; 2];
        for i in 0..2 {
            for jd in 0..2 {
                // Response per unit e = d / C: divide by C for per metre; Z = -F1.
                k[i][jd] = -z_re[jd][i] / c + self.k_contact[i][jd];
                d[i][jd] = -z_im_over_nu[jd][i] / c;
            }
        }
        Ok((k, d))
    }

    /// Force response per unit e_j, indexed [j][i]: (real part, imaginary part / nu).
    fn response_harmonic(&self, nu: f64) -> Result<(Mat2, Mat2), FilmError> {
        let mesh = &self.steady.mesh;
        let npb = mesh.npb;
        let n = mesh.n_nodes();
        let mut p1 = [[vec![1.0; n], vec![1.0; n]], [vec![1.0; n], vec![1.0; n]]];
        let kl2 = 2 * mesh.kl + 1;
        let ku2 = 2 * mesh.ku + 1;
        let mut rhs = vec![0.0; 2 * npb];
        let mut a = BandLu::new(2 * npb, kl2, ku2);
        for (k, b) in self.blocks.iter().enumerate() {
            // Without row interchanges first, as the integrator's Newton matrices: a narrower
            // band to eliminate (the linear analysis spent half its time in these pivoted
            // factorizations); where that is not stable (`linsolve::GROWTH_LIMIT`), assembled
            // again and factorized with partial pivoting.
            let factored = a.assemble_and_factor(|a| {
                a.zero();
                for r in 0..npb {
                    let c_lo = r.saturating_sub(mesh.kl);
                    let c_hi = (r + mesh.ku).min(npb - 1);
                    for c in c_lo..=c_hi {
                        let jv = b.j.get(r, c);
                        let mv = nu * b.m.get(r, c);
                        a.add(2 * r, 2 * c, jv);
                        a.add(2 * r + 1, 2 * c + 1, jv);
                        if mv != 0.0 {
                            a.add(2 * r, 2 * c + 1, -mv);
                            a.add(2 * r + 1, 2 * c, mv);
                        }
                    }
                }
            });
            factored.map_err(|e| FilmError::SingularMatrix {
                lobe: k,
                row: e.row(a.n),
            })?;
            for dir in 0..2 {
                for r in 0..npb {
                    rhs[2 * r] = -b.r_e[dir][r];
                    rhs[2 * r + 1] = -nu * b.r_v[dir][r];
                }
                a.solve(&mut rhs);
                for r in 0..npb {
                    // Stored as 1 + P1 so that pressure_force_n (linear in P - 1) gives F1.
                    p1[dir][0][k * npb + r] = 1.0 + rhs[2 * r];
                    p1[dir][1][k * npb + r] = 1.0 + rhs[2 * r + 1] / nu;
                }
            }
        }
        let mut re = [[0.0; 2]; 2];
        let mut im = [[0.0; 2]; 2];
        for dir in 0..2 {
            re[dir] = pressure_force_n(&self.params, mesh, &self.geom, &p1[dir][0]);
            im[dir] = pressure_force_n(&self.params, mesh, &self.geom, &p1[dir][1]);
        }
        Ok((re, im))
    }

    /// nu -> 0: J P1 = -R_e, J P1' = -(R_v + M P1).
    fn response_static(&self) -> Result<(Mat2, Mat2), FilmError> {
        let mesh = &self.steady.mesh;
        let npb = mesh.npb;
        let n = mesh.n_nodes();
        let mut p1 = [[vec![1.0; n], vec![1.0; n]], [vec![1.0; n], vec![1.0; n]]];
        for (k, b) in self.blocks.iter().enumerate() {
            let mut lu = b.j.clone();
            lu.factor().map_err(|e| FilmError::SingularMatrix {
                lobe: k,
                row: e.row(lu.n),
            })?;
            for dir in 0..2 {
                let mut x: Vec<f64> = b.r_e[dir].iter().map(|v| -v).collect();
                lu.solve(&mut x);
                let mut y = vec![0.0; npb];
                for r in 0..npb {
                    let c_lo = r.saturating_sub(mesh.kl);
                    let c_hi = (r + mesh.ku).min(npb - 1);
                    let mut mx = 0.0;
                    for c in c_lo..=c_hi {
                        mx += b.m.get(r, c) * x[c];
                    }
                    y[r] = -(b.r_v[dir][r] + mx);
                }
                lu.solve(&mut y);
                for r in 0..npb {
                    p1[dir][0][k * npb + r] = 1.0 + x[r];
                    p1[dir][1][k * npb + r] = 1.0 + y[r];
                }
            }
        }
        let mut re = [[0.0; 2]; 2];
        let mut im = [[0.0; 2]; 2];
        for dir in 0..2 {
            re[dir] = pressure_force_n(&self.params, mesh, &self.geom, &p1[dir][0]);
            im[dir] = pressure_force_n(&self.params, mesh, &self.geom, &p1[dir][1]);
        }
        Ok((re, im))
    }
}

/// M, R_e and R_v of block `k` (element loop mirroring `reynolds::residual`).
fn assemble_block(
    prm: &BearingParams,
    mesh: &Mesh,
    geom: &Geometry,
    journal: &JournalState,
    k: usize,
    co: Coeffs,
    pb: &[f64],
    j: BandLu,
) -> BlockLin {
    let npb = mesh.npb;
    let mut m = BandLu::new(npb, mesh.kl, mesh.ku);
    let mut r_e = [vec![0.0; npb], vec![0.0; npb]];
    let mut r_v = [vec![0.0; npb], vec![0.0; npb]];
    let b = &mesh.basis;
    let sy = 2.0 / mesh.dzeta_e;
    let nq = geom.nq;
    let (ex, ey) = (journal.dx_m / prm.bore.c_m, journal.dy_m / prm.bore.c_m);
    for (e, nodes) in mesh.elem.iter().enumerate() {
        let col = mesh.elem_col[e] as usize;
        // Each column's own size (on a uniform mesh `dphi_e` itself: the same bits).
        let (sx, jac) = (
            2.0 / mesh.col_dphi[col],
            0.25 * mesh.col_dphi[col] * mesh.dzeta_e,
        );
        let mut pe = [0.0; 9];
        for a in 0..9 {
            pe[a] = pb[nodes[a] as usize];
        }
        for q in 0..9 {
            let gi = k * nq + 3 * col + q / 3;
            let (cs, sn) = (geom.cos_q[gi], geom.sin_q[gi]);
            let h_raw = 1.0 - ex * cs - ey * sn + geom.step_q[gi];
            let floored = h_raw <= geom.h_floor_rel;
            let h = if floored { geom.h_floor_rel } else { h_raw };
            let (n, nxr, nyr) = (&b.n[q], &b.dx[q], &b.dy[q]);
            let (mut pq, mut px, mut py) = (0.0, 0.0, 0.0);
            for a in 0..9 {
                pq += n[a] * pe[a];
                px += nxr[a] * pe[a];
                py += nyr[a] * pe[a];
            }
            px *= sx;
            py *= sy;
            let w = b.w[q] * jac;
            let wm = w * co.tau_s * h;
            for a in 0..9 {
                let ra = nodes[a] as usize;
                for bb in 0..9 {
                    m.add(ra, nodes[bb] as usize, wm * n[a] * n[bb]);
                }
            }
            if floored {
                continue;
            }
            // dH/de and d(dH/dphi)/de for e_x, e_y.
            for (dir, (h1, hphi1)) in [(-cs, sn), (-sn, -cs)].into_iter().enumerate() {
                let flux = w * 3.0 * pq * h * h * h1;
                let src = w * co.lambda * (px * h1 + pq * hphi1);
                let sq = w * co.tau_s * pq * h1;
                for a in 0..9 {
                    let ra = nodes[a] as usize;
                    r_e[dir][ra] += flux * (px * nxr[a] * sx + py * nyr[a] * sy) + src * n[a];
                    r_v[dir][ra] += sq * n[a];
                }
            }
        }
    }
    for (i, d) in mesh.dirichlet.iter().enumerate() {
        if *d {
            for dir in 0..2 {
                r_e[dir][i] = 0.0;
                r_v[dir][i] = 0.0;
            }
            let c_lo = i.saturating_sub(mesh.kl);
            let c_hi = (i + mesh.ku).min(npb - 1);
            for c in c_lo..=c_hi {
                let v = m.get(i, c);
                m.add(i, c, -v);
            }
        }
    }
    BlockLin { j, m, r_e, r_v }
}

/// Stiffness of the contact penalty force by central differences (step 1e-4 C).
fn contact_stiffness(prm: &BearingParams, journal: &JournalState) -> Mat2 {
    let step = 1e-4 * prm.bore.c_m;
    let mut k = [[0.0; 2]; 2];
    for dir in 0..2 {
        let mut f = [[0.0; 2]; 2];
        for (si, sign) in [1.0, -1.0].into_iter().enumerate() {
            let mut js = *journal;
            if dir == 0 {
                js.dx_m += sign * step;
            } else {
                js.dy_m += sign * step;
            }
            f[si] = contact_force_n(&prm.bore, &prm.contact, &js, min_gap_m(&prm.bore, &js));
        }
        for i in 0..2 {
            k[i][dir] = -(f[0][i] - f[1][i]) / (2.0 * step);
        }
    }
    k
}

/// Frequency-dependent stiffness K [N/m] and damping D [N s/m] of the film about the steady
/// state at `journal` (position and speed; velocities ignored), at whirl frequency `nu_rad_s`:
/// the force on the journal for a small motion d e^{i nu t} is -(K + i nu D) d.
pub fn dynamic_coefficients(
    params: &BearingParams,
    journal: JournalState,
    nu_rad_s: f64,
) -> Result<(Mat2, Mat2), FilmError> {
    FilmLinearization::new(params, journal)?.impedance(nu_rad_s)
}
