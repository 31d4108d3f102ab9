//! The shaft's reduced model: Craig-Bampton with the journals' translations as the interface.
//!
//! The air films, the contact and the disturbance act on the journals alone, so the x and y of the
//! two bearing nodes are kept exactly (the constraint modes: the static shape of the shaft when one
//! of them moves and the others stay); the rest of the shaft is described by its modes with the
//! journals held (fixed-interface modes) below a cut-off frequency. The constraint modes carry
//! every load to the journals as the full model does (Craig-Bampton is statically exact at its
//! interface), and they contain the rigid motions, so a stiff shaft reduces to the rigid rotor:
//! its fixed-interface modes lie far above any cut-off. What the dropped modes would add between
//! the journals under the loads that act there (gravity, the imbalances) is their static
//! deflection (residual flexibility): it moves no journal, so it enters the outputs (the centre
//! of mass) and not the equations, where its coordinates would be stiff beyond any use (they
//! would hold the integrator to steps of nanoseconds while the films' forces change every
//! macro step).
//!
//! The error of the reduction is measured, not assumed: [`Reduced::frequency_error`] compares the
//! natural frequencies of the full and the reduced shaft on springs at the bearings.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};
use serde::{Deserialize, Serialize};
use shaft::{ShaftModel, DOF_PER_NODE};

/// A shaft reduced to `n` coordinates: the journals' (x, y) first (bearing C, then T), then the
/// fixed-interface modes. Matrices row-major n x n.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reduced {
    pub n: usize,
    pub m: Vec<f64>,
    pub k: Vec<f64>,
    pub c: Vec<f64>,
    pub g: Vec<f64>,
    /// The full coordinates of each reduced one: row-major n_full x n.
    pub basis: Vec<f64>,
    pub n_full: usize,
    /// Natural frequencies of the kept fixed-interface modes [Hz].
    pub kept_modes_hz: Vec<f64>,
    /// Fixed-interface modes left out (above the cut-off).
    pub dropped_modes: usize,
    /// The residual static deflection (full coordinates) under gravity in x and in y (1 m/s^2),
    /// then under unit forces in x and y at each load node: what the dropped modes add.
    pub residuals: Vec<Vec<f64>>,
}

/// The journals' coordinates in the full model: x and y of bearing C, then of bearing T.
pub fn interface_dofs(bearing_nodes: [usize; 2]) -> [usize; 4] {
    let [c, t] = bearing_nodes;
    [
        DOF_PER_NODE * c,
        DOF_PER_NODE * c + 1,
        DOF_PER_NODE * t,
        DOF_PER_NODE * t + 1,
    ]
}

fn mat(n: usize, a: &[f64]) -> MatRef<'_, f64> {
    MatRef::from_row_major_slice(a, n, n)
}

/// What every reduction of one shaft shares: the constraint modes, all fixed-interface modes
/// (ascending) and the residual deflections' ingredients. The eigenproblem is solved once; a
/// reduction at a cut-off then takes the modes below it.
pub struct Analysis {
    mm: shaft::Matrices,
    b: [usize; 4],
    interior: Vec<usize>,
    /// Constraint modes: interior x 4.
    phi_c: Mat<f64>,
    /// (frequency [Hz], M-normalized interior shape), ascending.
    modes: Vec<(f64, Vec<f64>)>,
    /// Per load: its interior part and the static response K_ii^-1 f_i.
    loads: Vec<(Vec<f64>, Vec<f64>)>,
}

/// The shaft `model` (no rings: the rings are the rotor simulator's own coordinates) with the
/// journals at `bearing_nodes` as interface; `load_nodes` get residual deflections for forces in
/// x and y.
pub fn analyse(
    model: &ShaftModel,
    bearing_nodes: [usize; 2],
    load_nodes: &[usize],
) -> Result<Analysis, String> {
    let mm = model.matrices();
    let nf = mm.n;
    let b = interface_dofs(bearing_nodes);
    let interior: Vec<usize> = (0..nf).filter(|i| !b.contains(i)).collect();
    let ni = interior.len();
    let sub = |a: &[f64], rows: &[usize], cols: &[usize]| {
        Mat::<f64>::from_fn(rows.len(), cols.len(), |i, j| a[rows[i] * nf + cols[j]])
    };
    let k_ii = sub(&mm.k, &interior, &interior);
    let m_ii = sub(&mm.m, &interior, &interior);
    let k_ib = sub(&mm.k, &interior, &b);
    let llt = k_ii.llt(Side::Lower).map_err(|_| {
        "the shaft held at its two bearings can still move without deforming (a mechanism): \
         check the elements' stiffness and the bearing nodes"
            .to_string()
    })?;
    // Constraint modes: the interior's static response to a unit displacement of each journal
    // coordinate.
    let phi_c = -llt.solve(&k_ib);
    // Fixed-interface modes from A = L^-1 M_ii L^-T, whose eigenvalues are 1 / omega^2: the
    // lowest modes are its largest eigenvalues, computed to full relative accuracy however
    // stiff the highest ones are.
    let l = llt.L();
    let evd = inverse_congruence(l, m_ii.as_ref())
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| "the fixed-interface eigenproblem did not converge".to_string())?;
    let (s, u) = (evd.S(), evd.U());
    let mut modes: Vec<(f64, Vec<f64>)> = Vec::new();
    for j in (0..ni).rev() {
        let mu = s[j];
        if mu <= 0.0 {
            continue;
        }
        let f_hz = (1.0 / mu).sqrt() / (2.0 * std::f64::consts::PI);
        // phi = L^-T z, M-normalized (phi^T M_ii phi = mu).
        let mut z = Mat::<f64>::from_fn(ni, 1, |i, _| u[(i, j)]);
        faer::linalg::triangular_solve::solve_upper_triangular_in_place(
            l.transpose(),
            z.as_mut(),
            faer::Par::Seq,
        );
        let scale = 1.0 / mu.sqrt();
        modes.push((f_hz, (0..ni).map(|i| z[(i, 0)] * scale).collect()));
    }
    // Loads: gravity (x and y, 1 m/s^2) and unit forces at the load nodes.
    let mut full_loads: Vec<Vec<f64>> = Vec::new();
    for dir in 0..2 {
        full_loads.push(
            (0..nf)
                .map(|i| {
                    (dir..nf)
                        .step_by(DOF_PER_NODE)
                        .map(|j| mm.m[i * nf + j])
                        .sum()
                })
                .collect(),
        );
    }
    for &node in load_nodes {
        for dir in 0..2 {
            let mut f = vec![0.0; nf];
            f[DOF_PER_NODE * node + dir] = 1.0;
            full_loads.push(f);
        }
    }
    let loads = full_loads
        .iter()
        .map(|f| {
            let fi = Mat::<f64>::from_fn(ni, 1, |i, _| f[interior[i]]);
            let ui = llt.solve(&fi);
            (
                (0..ni).map(|i| fi[(i, 0)]).collect(),
                (0..ni).map(|i| ui[(i, 0)]).collect(),
            )
        })
        .collect();
    Ok(Analysis {
        mm,
        b,
        interior,
        phi_c,
        modes,
        loads,
    })
}

/// [`analyse`], then [`Analysis::reduce`] at `cutoff_hz`.
pub fn reduce(
    model: &ShaftModel,
    bearing_nodes: [usize; 2],
    load_nodes: &[usize],
    cutoff_hz: f64,
) -> Result<Reduced, String> {
    Ok(analyse(model, bearing_nodes, load_nodes)?.reduce(cutoff_hz))
}

impl Analysis {
    /// The fixed-interface modes' frequencies [Hz], ascending.
    pub fn modes_hz(&self) -> Vec<f64> {
        self.modes.iter().map(|m| m.0).collect()
    }

    /// The reduced shaft with the fixed-interface modes below `cutoff_hz`.
    pub fn reduce(&self, cutoff_hz: f64) -> Reduced {
        let (mm, nf) = (&self.mm, self.mm.n);
        let kept: Vec<&(f64, Vec<f64>)> = self.modes.iter().filter(|m| m.0 < cutoff_hz).collect();
        // Residual deflections: each load's static response less the kept modes' share
        // (sum of phi phi^T f / omega^2).
        let residuals = self
            .loads
            .iter()
            .map(|(fi, ui)| {
                let shares: Vec<f64> = kept
                    .iter()
                    .map(|(f_hz, phi)| {
                        let w2 = (2.0 * std::f64::consts::PI * f_hz).powi(2);
                        phi.iter().zip(fi).map(|(a, b)| a * b).sum::<f64>() / w2
                    })
                    .collect();
                let mut full = vec![0.0; nf];
                for (ii, &row) in self.interior.iter().enumerate() {
                    let modal: f64 = kept
                        .iter()
                        .zip(&shares)
                        .map(|((_, phi), p)| phi[ii] * p)
                        .sum();
                    full[row] = ui[ii] - modal;
                }
                full
            })
            .collect();
        // The basis T (n_full x n).
        let n = 4 + kept.len();
        let mut t = vec![0.0; nf * n];
        for (col, &dof) in self.b.iter().enumerate() {
            t[dof * n + col] = 1.0;
            for (ii, &row) in self.interior.iter().enumerate() {
                t[row * n + col] = self.phi_c[(ii, col)];
            }
        }
        for (k, (_, v)) in kept.iter().enumerate() {
            for (ii, &row) in self.interior.iter().enumerate() {
                t[row * n + 4 + k] = v[ii];
            }
        }
        let tm = MatRef::from_row_major_slice(&t, nf, n);
        let project = |a: &[f64]| -> Vec<f64> {
            let p = tm.transpose() * mat(nf, a) * tm;
            let mut out = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    out[i * n + j] = p[(i, j)];
                }
            }
            out
        };
        let mut m = project(&mm.m);
        let mut k = project(&mm.k);
        // Exactly symmetric (the products round differently on either side).
        for a in [&mut m, &mut k] {
            for i in 0..n {
                for j in 0..i {
                    let s = 0.5 * (a[i * n + j] + a[j * n + i]);
                    a[i * n + j] = s;
                    a[j * n + i] = s;
                }
            }
        }
        Reduced {
            n,
            m,
            k,
            c: project(&mm.c),
            g: project(&mm.g),
            basis: t,
            n_full: nf,
            kept_modes_hz: kept.iter().map(|(f, _)| *f).collect(),
            dropped_modes: self.modes.len() - kept.len(),
            residuals,
        }
    }
}

impl Reduced {
    /// `Tᵀ f` for a full load vector.
    pub fn load(&self, f_full: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|j| {
                (0..self.n_full)
                    .map(|i| self.basis[i * self.n + j] * f_full[i])
                    .sum()
            })
            .collect()
    }

    /// The largest relative error of the natural frequencies below `up_to_hz` of the shaft with
    /// an isotropic spring `k_n_m` from each journal to the ground, this reduction against
    /// `full` (the full model's, [`full_frequencies_hz`]; not spinning, undamped): the
    /// reduction's measured error bound. Rayleigh-Ritz: a reduced frequency is never below the
    /// full one. Returns (error, frequencies compared).
    pub fn frequency_error(
        &self,
        full: &[f64],
        k_n_m: f64,
        up_to_hz: f64,
    ) -> Result<(f64, usize), String> {
        let mut k_red = self.k.clone();
        for d in 0..4 {
            k_red[d * self.n + d] += k_n_m;
        }
        let red = natural_frequencies_hz(self.n, &self.m, &k_red)?;
        let mut worst = 0.0f64;
        let mut count = 0;
        for (f, r) in full.iter().zip(&red) {
            if *f > up_to_hz {
                break;
            }
            worst = worst.max((r - f).abs() / f);
            count += 1;
        }
        Ok((worst, count))
    }
}

/// The full model's natural frequencies [Hz] with an isotropic spring `k_n_m` from each journal
/// to the ground (not spinning, undamped), ascending.
pub fn full_frequencies_hz(
    model: &ShaftModel,
    bearing_nodes: [usize; 2],
    k_n_m: f64,
) -> Result<Vec<f64>, String> {
    let mm = model.matrices();
    let nf = mm.n;
    let mut k_full = mm.k.clone();
    for d in interface_dofs(bearing_nodes) {
        k_full[d * nf + d] += k_n_m;
    }
    natural_frequencies_hz(nf, &mm.m, &k_full)
}

/// L^-1 M L^-T for the Cholesky factor L of a stiffness matrix, exactly symmetric: its
/// eigenvalues are 1 / omega^2 of K x = omega^2 M x, the lowest modes its largest.
fn inverse_congruence(l: MatRef<'_, f64>, m: MatRef<'_, f64>) -> Mat<f64> {
    let n = m.nrows();
    let mut a = m.to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, a.as_mut(), faer::Par::Seq);
    let mut a = a.transpose().to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, a.as_mut(), faer::Par::Seq);
    Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// Ascending natural frequencies [Hz] of K x = w^2 M x (K positive definite).
pub fn natural_frequencies_hz(n: usize, m: &[f64], k: &[f64]) -> Result<Vec<f64>, String> {
    let km = mat(n, k).to_owned();
    let llt = km
        .llt(Side::Lower)
        .map_err(|_| "the stiffness matrix is not positive definite".to_string())?;
    let mu = inverse_congruence(llt.L(), mat(n, m))
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|_| "the eigenproblem did not converge".to_string())?;
    let mut f: Vec<f64> = mu
        .iter()
        .filter(|m| **m > 0.0)
        .map(|m| (1.0 / m).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(|a, b| a.total_cmp(b));
    Ok(f)
}
