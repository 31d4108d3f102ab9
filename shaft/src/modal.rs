//! Modes of a flexible rotor at a spin speed (damped, with gyroscopic coupling), the Campbell
//! diagram, critical speeds and the synchronous response to an imbalance.
//!
//! The state matrix is ROSS's, A = [[0, I], [-M^-1 K, -M^-1 (C + Omega G)]], and so are the
//! reported quantities: natural frequency wn = |lambda|, damped frequency wd = Im lambda,
//! damping ratio -Re lambda / |lambda|, logarithmic decrement 2 pi zeta / sqrt(1 - zeta^2).
//! Only oscillating modes (Im lambda > 0) are reported; overdamped real eigenvalues and the
//! rigid-body zeros of an unsupported shaft are not modes one reads on a Campbell diagram.

use crate::eigen::{eigenpairs, C64};
use crate::model::{Matrices, ShaftModel, DOF_PER_NODE};
use crate::ShaftError;
use faer::linalg::solvers::Solve;

/// The direction a mode whirls in, relative to the spin (positive about z).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Whirl {
    Forward,
    Backward,
}

/// One mode at one speed.
#[derive(Clone, Debug)]
pub struct Mode {
    pub eigenvalue: C64,
    /// Natural frequency |lambda| [rad/s].
    pub wn_rad_s: f64,
    /// Damped frequency Im lambda [rad/s].
    pub wd_rad_s: f64,
    pub damping_ratio: f64,
    pub log_dec: f64,
    pub whirl: Whirl,
    /// Mode shape over the model's coordinates (largest component 1).
    pub shape: Vec<C64>,
}

/// The modes at spin speed `speed_rad_s`, by increasing damped frequency.
pub fn modes(model: &ShaftModel, speed_rad_s: f64) -> Result<Vec<Mode>, ShaftError> {
    model.validate()?;
    modes_of(&model.matrices(), speed_rad_s)
}

/// The modes of assembled matrices at spin speed `speed_rad_s`.
pub fn modes_of(mm: &Matrices, speed_rad_s: f64) -> Result<Vec<Mode>, ShaftError> {
    let n = mm.n;
    let a = state_matrix(mm, speed_rad_s)?;
    let pairs = eigenpairs(2 * n, &a).ok_or_else(|| {
        ShaftError::Numerical(format!(
            "the eigenvalue iteration did not converge at {} rad/s",
            bearing::num::Num(speed_rad_s)
        ))
    })?;
    let mut out: Vec<Mode> = pairs
        .into_iter()
        .filter(|(l, _)| l.im > 0.0)
        .map(|(l, v)| {
            let wn = l.norm();
            let zeta = -l.re / wn;
            let mut shape: Vec<C64> = v[..n].to_vec();
            let big = crate::eigen::largest(&shape);
            if big.norm() > 0.0 {
                for z in shape.iter_mut() {
                    *z /= big;
                }
            }
            // Forward whirl: x = cos, y = sin, i.e. Y = -i X, so Im(conj(X) Y) < 0 (summed over
            // the nodes, weighted by their amplitude).
            let turn: f64 = mm
                .whirl_pairs
                .iter()
                .map(|&[x, y]| (shape[x].conj() * shape[y]).im)
                .sum();
            Mode {
                eigenvalue: l,
                wn_rad_s: wn,
                wd_rad_s: l.im,
                damping_ratio: zeta,
                log_dec: 2.0 * std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt(),
                whirl: if turn < 0.0 {
                    Whirl::Forward
                } else {
                    Whirl::Backward
                },
                shape,
            }
        })
        .collect();
    out.sort_by(|a, b| a.wd_rad_s.total_cmp(&b.wd_rad_s));
    Ok(out)
}

/// The real eigenvalues [1/s] of assembled matrices at spin speed `speed_rad_s`: non-oscillating
/// motion (overdamped, or a static divergence where one is > 0).
pub fn real_eigenvalues_of(mm: &Matrices, speed_rad_s: f64) -> Result<Vec<f64>, ShaftError> {
    let a = state_matrix(mm, speed_rad_s)?;
    let ev = crate::eigen::eigenvalues(2 * mm.n, &a).ok_or_else(|| {
        ShaftError::Numerical(format!(
            "the eigenvalue iteration did not converge at {} rad/s",
            bearing::num::Num(speed_rad_s)
        ))
    })?;
    Ok(ev
        .into_iter()
        .filter(|l| l.im == 0.0)
        .map(|l| l.re)
        .collect())
}

fn state_matrix(mm: &Matrices, speed_rad_s: f64) -> Result<Vec<f64>, ShaftError> {
    let n = mm.n;
    let m = faer::MatRef::from_row_major_slice(&mm.m, n, n);
    let lu = m.partial_piv_lu();
    let k = faer::MatRef::from_row_major_slice(&mm.k, n, n);
    let cg =
        faer::Mat::<f64>::from_fn(n, n, |i, j| mm.c[i * n + j] + speed_rad_s * mm.g[i * n + j]);
    let mk = lu.solve(k);
    let mc = lu.solve(&cg);
    let mut a = vec![0.0; 4 * n * n];
    let w = 2 * n;
    for i in 0..n {
        a[i * w + n + i] = 1.0;
        for j in 0..n {
            a[(n + i) * w + j] = -mk[(i, j)];
            a[(n + i) * w + n + j] = -mc[(i, j)];
        }
    }
    if a.iter().any(|v| !v.is_finite()) {
        return Err(ShaftError::Numerical(
            "the mass matrix is singular (a coordinate without inertia)".into(),
        ));
    }
    Ok(a)
}

/// A critical speed: where a mode's damped frequency equals the spin speed.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CriticalSpeed {
    /// Index of the mode (by damped frequency) whose curve crosses the 1x line.
    pub mode: usize,
    pub speed_rad_s: f64,
    pub whirl: Whirl,
    pub log_dec: f64,
}

/// Critical speeds of the first `n_modes` modes, as ROSS finds them: for mode i, the speed s with
/// s = wd_i(s), by the secant method from s = wd_i(0); converged to a relative 1e-10.
pub fn critical_speeds(
    model: &ShaftModel,
    n_modes: usize,
) -> Result<Vec<CriticalSpeed>, ShaftError> {
    model.validate()?;
    let mm = model.matrices();
    let at_rest = modes_of(&mm, 0.0)?;
    let mut out = vec![];
    for i in 0..n_modes.min(at_rest.len()) {
        let f = |s: f64| -> Result<f64, ShaftError> {
            let ms = modes_of(&mm, s)?;
            ms.get(i).map(|m| m.wd_rad_s - s).ok_or_else(|| {
                ShaftError::Numerical(format!(
                    "mode {i} is not oscillating at {} rad/s",
                    bearing::num::Num(s)
                ))
            })
        };
        let mut s0 = at_rest[i].wd_rad_s;
        let mut f0 = f(s0)?;
        let mut s1 = s0 * 1.01 + 1e-3;
        let mut f1 = f(s1)?;
        let mut converged = false;
        for _ in 0..60 {
            if f1 == f0 {
                converged = f1.abs() <= 1e-10 * s1.abs();
                break;
            }
            let s2 = s1 - f1 * (s1 - s0) / (f1 - f0);
            (s0, f0) = (s1, f1);
            s1 = s2;
            f1 = f(s1)?;
            if (s1 - s0).abs() <= 1e-10 * s1.abs() {
                converged = true;
                break;
            }
        }
        if !converged || s1.is_nan() || s1 < 0.0 {
            return Err(ShaftError::Numerical(format!(
                "the critical speed of mode {i} did not converge (last speed {} rad/s)",
                bearing::num::Num(s1)
            )));
        }
        let m = &modes_of(&mm, s1)?[i];
        out.push(CriticalSpeed {
            mode: i,
            speed_rad_s: s1,
            whirl: m.whirl,
            log_dec: m.log_dec,
        });
    }
    Ok(out)
}

/// The steady response to an imbalance `magnitude_kg_m` (mass times radius) at `node`, phase
/// `phase_rad`, spinning at `speed_rad_s`: the complex amplitude of every coordinate,
/// q(t) = Re(Q e^{i Omega t}). Solves (K - Omega^2 M + i Omega (C + Omega G)) Q = F with the
/// rotating force F = m e Omega^2 e^{i phase} (1, -i) on the node's x and y.
pub fn unbalance_response(
    model: &ShaftModel,
    node: usize,
    magnitude_kg_m: f64,
    phase_rad: f64,
    speed_rad_s: f64,
) -> Result<Vec<C64>, ShaftError> {
    model.validate()?;
    if node >= model.n_nodes() {
        return Err(ShaftError::Model(format!(
            "the imbalance is at node {node}, off the shaft (nodes 0 to {})",
            model.n_nodes() - 1
        )));
    }
    if !(magnitude_kg_m.is_finite() && phase_rad.is_finite() && speed_rad_s.is_finite()) {
        return Err(ShaftError::Model(
            "the imbalance's magnitude, phase and speed must be finite numbers".into(),
        ));
    }
    unbalance_response_of(
        &model.matrices(),
        node,
        magnitude_kg_m,
        phase_rad,
        speed_rad_s,
    )
}

/// `unbalance_response` of assembled matrices (node and values checked by the caller).
pub fn unbalance_response_of(
    mm: &Matrices,
    node: usize,
    magnitude_kg_m: f64,
    phase_rad: f64,
    speed_rad_s: f64,
) -> Result<Vec<C64>, ShaftError> {
    let n = mm.n;
    let w = speed_rad_s;
    let z = faer::Mat::<C64>::from_fn(n, n, |i, j| {
        let ij = i * n + j;
        C64::new(mm.k[ij] - w * w * mm.m[ij], w * (mm.c[ij] + w * mm.g[ij]))
    });
    let f0 = C64::from_polar(magnitude_kg_m * w * w, phase_rad);
    let rhs = faer::Mat::<C64>::from_fn(n, 1, |i, _| {
        if i == DOF_PER_NODE * node {
            f0
        } else if i == DOF_PER_NODE * node + 1 {
            f0 * C64::new(0.0, -1.0)
        } else {
            C64::new(0.0, 0.0)
        }
    });
    let q = z.partial_piv_lu().solve(&rhs);
    let out: Vec<C64> = (0..n).map(|i| q[(i, 0)]).collect();
    if out.iter().any(|c| !(c.re.is_finite() && c.im.is_finite())) {
        return Err(ShaftError::Numerical(format!(
            "the dynamic stiffness is singular at {} rad/s (an undamped resonance)",
            bearing::num::Num(w)
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{Material, ShaftElement};
    use crate::model::{Disk, Support};

    /// Two half masses on a very light, very short element, each on half the spring: its rigid
    /// translation is a mode at sqrt(k/m) exactly (the rocking one lies as close: a dumbbell).
    fn disk_on_spring(k: f64, m: f64) -> ShaftModel {
        // A very short, very light shaft element carries the node (its inertia negligible).
        let mut e = ShaftElement::cylinder(1e-3, 0.0, 1e-3, Material::steel());
        e.material.rho_kg_m3 = 1e-6;
        ShaftModel {
            elements: vec![e],
            disks: vec![
                Disk {
                    node: 0,
                    mass_kg: m / 2.0,
                    id_kg_m2: 1e-9,
                    ip_kg_m2: 0.0,
                    tag: "a".into(),
                },
                Disk {
                    node: 1,
                    mass_kg: m / 2.0,
                    id_kg_m2: 1e-9,
                    ip_kg_m2: 0.0,
                    tag: "b".into(),
                },
            ],
            point_masses: vec![],
            supports: [0, 1]
                .map(|node| Support {
                    node,
                    k_n_m: [[k / 2.0, 0.0], [0.0, k / 2.0]],
                    c_n_s_m: [[0.0; 2]; 2],
                    m_kg: [[0.0; 2]; 2],
                    tag: format!("B{node}"),
                })
                .to_vec(),
            rings: vec![],
        }
    }

    /// The mode in which both nodes translate alike (x or y).
    fn translation(ms: &[Mode]) -> &Mode {
        ms.iter()
            .find(|m| {
                let s = &m.shape;
                (0..2).any(|d| s[d].norm() > 0.99 && (s[d] - s[4 + d]).norm() < 1e-6)
            })
            .expect("a translation mode")
    }

    #[test]
    fn a_mass_on_springs_oscillates_at_sqrt_k_over_m() {
        let (k, m) = (4e6, 2.5);
        let ms = modes(&disk_on_spring(k, m), 0.0).unwrap();
        let w = (k / m).sqrt();
        let t = translation(&ms);
        assert!((t.wn_rad_s - w).abs() <= 1e-9 * w, "{} {w}", t.wn_rad_s);
        assert!(t.damping_ratio.abs() < 1e-9);
    }

    /// Viscous damping c on the mass: zeta = c / (2 sqrt(k m)), and at resonance the response
    /// to a rotating force F is F / (c w).
    #[test]
    fn damping_ratio_and_resonant_amplitude_of_a_damped_mass() {
        let (k, m, c) = (4e6, 2.5, 300.0);
        let mut s = disk_on_spring(k, m);
        for sp in s.supports.iter_mut() {
            sp.c_n_s_m = [[c / 2.0, 0.0], [0.0, c / 2.0]];
        }
        let ms = modes(&s, 0.0).unwrap();
        let zeta = c / (2.0 * (k * m).sqrt());
        let t = translation(&ms);
        assert!(
            (t.damping_ratio - zeta).abs() <= 1e-6 * zeta,
            "{}",
            t.damping_ratio
        );
        let w = (k / m).sqrt();
        let me = 1e-5;
        // Half the imbalance at each node: the rigid translation only.
        let q0 = unbalance_response(&s, 0, me, 0.0, w).unwrap();
        let q1 = unbalance_response(&s, 1, me, 0.0, w).unwrap();
        let x = q0[0] + q1[0];
        let expect = 2.0 * me * w * w / (c * w);
        assert!(
            (x.norm() - expect).abs() <= 1e-6 * expect,
            "{} {expect}",
            x.norm()
        );
    }

    /// A spinning disk: gyroscopic stiffening splits the conical modes into a forward one that
    /// rises and a backward one that falls with speed.
    #[test]
    fn gyroscopic_splitting_forward_rises_backward_falls() {
        let e = ShaftElement::cylinder(0.3, 0.0, 0.03, Material::steel());
        let s = ShaftModel {
            elements: vec![e.clone(), e],
            disks: vec![Disk {
                node: 2,
                mass_kg: 5.0,
                id_kg_m2: 0.02,
                ip_kg_m2: 0.04,
                tag: "overhung".into(),
            }],
            point_masses: vec![],
            supports: [0, 1]
                .map(|node| Support {
                    node,
                    k_n_m: [[1e7, 0.0], [0.0, 1e7]],
                    c_n_s_m: [[0.0; 2]; 2],
                    m_kg: [[0.0; 2]; 2],
                    tag: format!("B{node}"),
                })
                .to_vec(),
            rings: vec![],
        };
        let rest = modes(&s, 0.0).unwrap();
        let fast = modes(&s, 3000.0).unwrap();
        let fw: Vec<&Mode> = fast.iter().filter(|m| m.whirl == Whirl::Forward).collect();
        let bw: Vec<&Mode> = fast.iter().filter(|m| m.whirl == Whirl::Backward).collect();
        assert!(
            fw[0].wd_rad_s > rest[0].wd_rad_s,
            "{} {}",
            fw[0].wd_rad_s,
            rest[0].wd_rad_s
        );
        assert!(bw[0].wd_rad_s < rest[0].wd_rad_s);
    }
}
