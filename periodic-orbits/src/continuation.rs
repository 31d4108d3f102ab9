//! A branch of periodic orbits followed in a parameter (the speed) by pseudo-arclength
//! continuation, which passes folds: a subcritical Hopf branch starts unstable at the Hopf
//! point, turns at a fold and comes back stable with a large amplitude.
//!
//! Unknowns y = (x0 / s, T / T_ref, lambda / lambda_s); equations the periodicity and the phase
//! condition of [`super::shooting`] plus the arclength condition t . (y - y_pred) = 0 along the
//! branch's unit tangent t.

use super::shooting::{linearize, Flow, PeriodicOrbit, PhasePlane, ShootingOptions};
use nalgebra::{DMatrix, DVector};

/// A flow with one parameter (the rotor speed).
pub trait ParamFlow: Flow {
    fn param(&self) -> f64;
    fn set_param(&mut self, value: f64) -> Result<(), String>;
    /// A typical magnitude of the parameter (its unknown is scaled by it).
    fn param_scale(&self) -> f64;
    /// Called with each orbit the branch accepts, before its multipliers and tangent are
    /// computed: a flow whose fast variables are not unknowns (the co-simulation's film
    /// pressures) relaxes them onto the orbit here. Nothing by default.
    fn accepted(&mut self, _x0: &[f64], _period_s: f64) -> Result<(), String> {
        Ok(())
    }
}

#[derive(Clone, Copy, Debug)]
pub struct ContinuationOptions {
    /// Arclength step in scaled unknowns: first, smallest and largest.
    pub ds: f64,
    pub ds_min: f64,
    pub ds_max: f64,
    /// Points on the branch at most (the start included).
    pub max_points: usize,
    /// The branch ends when the parameter leaves this range.
    pub param_min: f64,
    pub param_max: f64,
    /// The branch ends at the Hopf point: when an orbit's scaled size falls below this.
    pub min_size: f64,
    /// Corrector iterations per step before the step is halved.
    pub max_corrector: usize,
    /// Finite differences and tolerance, as in shooting.
    pub shooting: ShootingOptions,
    /// Finite-difference step of the parameter column, relative to the parameter's scale.
    pub fd_param_rel: f64,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        ContinuationOptions {
            ds: 0.05,
            ds_min: 1e-4,
            ds_max: 0.2,
            max_points: 200,
            param_min: f64::NEG_INFINITY,
            param_max: f64::INFINITY,
            min_size: 1e-3,
            max_corrector: 6,
            shooting: ShootingOptions::default(),
            fd_param_rel: 1e-6,
        }
    }
}

/// One orbit of a branch.
#[derive(Clone, Debug)]
pub struct BranchPoint {
    pub param: f64,
    pub orbit: PeriodicOrbit,
    /// RMS distance of the orbit's points from their mean, in scaled state units.
    pub size: f64,
    /// The flow's own measures of the orbit.
    pub measures: Vec<(String, f64)>,
}

/// Why a branch ended.
#[derive(Clone, Debug, PartialEq)]
pub enum BranchEnd {
    /// The orbit shrank onto the equilibrium: the Hopf point.
    ReachedHopf,
    LeftRange,
    MaxPoints,
    /// The corrector failed at the smallest step: the message says why.
    Failed(String),
}

#[derive(Clone, Debug)]
pub struct Branch {
    pub points: Vec<BranchPoint>,
    /// Indices i where the parameter turns between point i and i + 1.
    pub folds: Vec<usize>,
    pub end: BranchEnd,
}

/// RMS distance of `n_samples` equally spaced points of the orbit from their mean [scaled].
pub fn orbit_size(
    flow: &mut dyn Flow,
    x0: &[f64],
    period_s: f64,
    scale: &[f64],
) -> Result<f64, String> {
    const N_SAMPLES: usize = 64;
    let times: Vec<f64> = (1..=N_SAMPLES)
        .map(|k| period_s * k as f64 / N_SAMPLES as f64)
        .collect();
    let pts = flow.flow(x0, &times)?;
    let n = x0.len();
    let mean: Vec<f64> = (0..n)
        .map(|i| pts.iter().map(|p| p[i]).sum::<f64>() / N_SAMPLES as f64)
        .collect();
    let ms = pts
        .iter()
        .map(|p| {
            (0..n)
                .map(|i| ((p[i] - mean[i]) / scale[i]).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / N_SAMPLES as f64;
    Ok(ms.sqrt())
}

/// The extended Jacobian (n + 1 rows: periodicity, phase; n + 2 columns: state, period,
/// parameter) and residual at y, all scaled.
struct Extended {
    jac: DMatrix<f64>,
    residual: DVector<f64>,
    monodromy: DMatrix<f64>,
}

struct Scaling {
    state: Vec<f64>,
    period_s: f64,
    param: f64,
}

fn unpack(y: &DVector<f64>, sc: &Scaling) -> (Vec<f64>, f64, f64) {
    let n = sc.state.len();
    let x0 = (0..n).map(|i| y[i] * sc.state[i]).collect();
    (x0, y[n] * sc.period_s, y[n + 1] * sc.param)
}

fn pack(x0: &[f64], period_s: f64, param: f64, sc: &Scaling) -> DVector<f64> {
    let n = x0.len();
    let mut y = DVector::zeros(n + 2);
    for i in 0..n {
        y[i] = x0[i] / sc.state[i];
    }
    y[n] = period_s / sc.period_s;
    y[n + 1] = param / sc.param;
    y
}

fn extended(
    flow: &mut dyn ParamFlow,
    y: &DVector<f64>,
    plane: &PhasePlane,
    sc: &Scaling,
    opts: &ContinuationOptions,
) -> Result<Extended, String> {
    let n = sc.state.len();
    let (x0, period, param) = unpack(y, sc);
    flow.set_param(param)?;
    let lin = linearize(flow, &x0, period, &sc.state, &opts.shooting)?;
    let dp = opts.fd_param_rel * sc.param;
    flow.set_param(param + dp)?;
    let shifted = flow.flow(&x0, &[period]);
    flow.set_param(param)?;
    let shifted = shifted?.remove(0);
    let mut jac = DMatrix::zeros(n + 1, n + 2);
    let mut residual = DVector::zeros(n + 1);
    for i in 0..n {
        for k in 0..n {
            let id = if i == k { 1.0 } else { 0.0 };
            jac[(i, k)] = (lin.monodromy[(i, k)] - id) * sc.state[k] / sc.state[i];
        }
        jac[(i, n)] = lin.field_end[i] * sc.period_s / sc.state[i];
        jac[(i, n + 1)] = (shifted[i] - lin.end[i]) / dp * sc.param / sc.state[i];
        residual[i] = (lin.end[i] - x0[i]) / sc.state[i];
    }
    for k in 0..n {
        jac[(n, k)] = plane.normal[k];
    }
    residual[n] = plane.defect(&x0, &sc.state);
    Ok(Extended {
        jac,
        residual,
        monodromy: lin.monodromy,
    })
}

/// The unit tangent: the null vector of `jac`, oriented along `previous`.
fn tangent(jac: &DMatrix<f64>, previous: &DVector<f64>) -> Result<DVector<f64>, String> {
    let rows = jac.nrows();
    let mut a = jac.clone().insert_row(rows, 0.0);
    for k in 0..a.ncols() {
        a[(rows, k)] = previous[k];
    }
    let mut b = DVector::zeros(rows + 1);
    b[rows] = 1.0;
    let t = a
        .lu()
        .solve(&b)
        .ok_or("singular continuation Jacobian: a branch point, or the orbit is not isolated")?;
    let norm = t.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return Err("no tangent to the branch".into());
    }
    Ok(t / norm)
}

/// Follows the branch through `start` (an orbit at parameter `flow.param()`), first in the
/// direction of increasing parameter when `increasing`, else decreasing. `on_point` sees each
/// new point as soon as it is accepted (progress, and partial branches written as they grow).
pub fn continue_branch(
    flow: &mut dyn ParamFlow,
    start: &PeriodicOrbit,
    increasing: bool,
    opts: &ContinuationOptions,
    on_point: &mut dyn FnMut(&BranchPoint),
) -> Result<Branch, String> {
    let n = flow.dim();
    let sc = Scaling {
        state: flow.scale(),
        period_s: start.period_s,
        param: flow.param_scale(),
    };
    let param0 = flow.param();
    let mut y = pack(&start.x0, start.period_s, param0, &sc);
    let field0 = flow.flow(&start.x0, &[start.period_s * opts.shooting.dt_rel])?[0]
        .iter()
        .zip(&start.x0)
        .map(|(e, x)| (e - x) / (start.period_s * opts.shooting.dt_rel))
        .collect::<Vec<_>>();
    let mut plane = PhasePlane::new(&start.x0, &field0, &sc.state)?;
    let mut ext = extended(flow, &y, &plane, &sc, opts)?;
    let mut guide = DVector::zeros(n + 2);
    guide[n + 1] = if increasing { 1.0 } else { -1.0 };
    let mut t = tangent(&ext.jac, &guide)?;
    let size0 = orbit_size(flow, &start.x0, start.period_s, &sc.state)?;
    let measures0 = flow.measures(&start.x0, start.period_s)?;
    let mut points = vec![BranchPoint {
        param: param0,
        orbit: start.clone(),
        size: size0,
        measures: measures0,
    }];
    let mut folds = Vec::new();
    let mut ds = opts.ds;
    let end = loop {
        if points.len() >= opts.max_points {
            break BranchEnd::MaxPoints;
        }
        // Predictor, then Newton's corrector on the arclength plane; halve the step on failure.
        // The step stays below a third of the orbit's size and a corrected orbit may not lose
        // more than half its size: else the corrector slides onto the equilibrium, which is a
        // "periodic orbit" of every period.
        let size_prev = points.last().map_or(f64::INFINITY, |p| p.size);
        ds = ds.min(size_prev / 3.0).max(opts.ds_min);
        let corrected = loop {
            let y_pred = &y + &t * ds;
            let attempt = correct(flow, &y_pred, &t, &plane, &sc, opts).and_then(|(yc, it)| {
                let (x0, period, param) = unpack(&yc, &sc);
                flow.set_param(param)?;
                let size = orbit_size(flow, &x0, period, &sc.state)?;
                if size < 0.5 * size_prev {
                    Err(format!(
                        "the orbit's size fell from {size_prev:.3e} to {size:.3e} in one step"
                    ))
                } else {
                    Ok((yc, it))
                }
            });
            match attempt {
                Ok(c) => break Ok(c),
                Err(e) => {
                    ds *= 0.5;
                    if ds < opts.ds_min {
                        break Err(e);
                    }
                }
            }
        };
        let (y_new, iterations) = match corrected {
            Ok(c) => c,
            Err(e) => break BranchEnd::Failed(e),
        };
        let (x0, period, param) = unpack(&y_new, &sc);
        flow.set_param(param)?;
        flow.accepted(&x0, period)?;
        let f0 = flow.flow(&x0, &[period * opts.shooting.dt_rel])?[0]
            .iter()
            .zip(&x0)
            .map(|(e, x)| (e - x) / (period * opts.shooting.dt_rel))
            .collect::<Vec<_>>();
        plane = PhasePlane::new(&x0, &f0, &sc.state)?;
        ext = extended(flow, &y_new, &plane, &sc, opts)?;
        let t_new = tangent(&ext.jac, &t)?;
        if t_new[n + 1].signum() != t[n + 1].signum() && t[n + 1] != 0.0 {
            folds.push(points.len() - 1);
        }
        let residual = (0..n).map(|i| ext.residual[i].abs()).fold(0.0, f64::max);
        let size = orbit_size(flow, &x0, period, &sc.state)?;
        let measures = flow.measures(&x0, period)?;
        points.push(BranchPoint {
            param,
            orbit: PeriodicOrbit::new(x0, period, ext.monodromy.clone(), iterations, residual),
            size,
            measures,
        });
        on_point(points.last().expect("just pushed"));
        y = y_new;
        t = t_new;
        if size < opts.min_size {
            break BranchEnd::ReachedHopf;
        }
        if !(opts.param_min..=opts.param_max).contains(&param) {
            break BranchEnd::LeftRange;
        }
        // Quick corrections earn a longer step.
        if iterations <= 2 {
            ds = (ds * 1.5).min(opts.ds_max);
        }
    };
    Ok(Branch { points, folds, end })
}

fn correct(
    flow: &mut dyn ParamFlow,
    y_pred: &DVector<f64>,
    t: &DVector<f64>,
    plane: &PhasePlane,
    sc: &Scaling,
    opts: &ContinuationOptions,
) -> Result<(DVector<f64>, usize), String> {
    let n = sc.state.len();
    let mut y = y_pred.clone();
    for iter in 0..opts.max_corrector {
        let ext = extended(flow, &y, plane, sc, opts)?;
        let res = ext.residual.iter().map(|r| r.abs()).fold(0.0, f64::max);
        let arc = t.dot(&(&y - y_pred));
        if !res.is_finite() {
            return Err("the flow left the finite numbers in the corrector".into());
        }
        if res < opts.shooting.tol && arc.abs() < opts.shooting.tol {
            return Ok((y, iter));
        }
        let mut a = ext.jac.insert_row(n + 1, 0.0);
        for k in 0..n + 2 {
            a[(n + 1, k)] = t[k];
        }
        let mut b = DVector::zeros(n + 2);
        for i in 0..=n {
            b[i] = -ext.residual[i];
        }
        b[n + 1] = -arc;
        let dy = a.lu().solve(&b).ok_or("singular corrector Jacobian")?;
        y += dy;
        if y[n] <= 0.0 {
            return Err("the corrector reached a non-positive period".into());
        }
    }
    Err(format!(
        "the corrector did not converge in {} iterations",
        opts.max_corrector
    ))
}

/// Where the branch meets the equilibrium: the parameter at which size^2 (linear in the
/// parameter near a Hopf point) extrapolates to zero from the branch's last two points, when
/// the branch ended there.
pub fn hopf_estimate(branch: &Branch) -> Option<f64> {
    if branch.end != BranchEnd::ReachedHopf || branch.points.len() < 2 {
        return None;
    }
    let b = &branch.points[branch.points.len() - 1];
    let a = &branch.points[branch.points.len() - 2];
    let (sa, sb) = (a.size * a.size, b.size * b.size);
    if (sa - sb).abs() == 0.0 {
        return None;
    }
    Some(b.param - sb * (a.param - b.param) / (sa - sb))
}

/// The Hopf bifurcation's type, read off the branch that starts at it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Criticality {
    /// Small stable orbits on the side where the equilibrium is unstable: the whirl grows
    /// gently from zero past the threshold.
    Supercritical,
    /// Small unstable orbits on the side where the equilibrium is stable: past the threshold
    /// the whirl jumps to a large orbit, and runs down to a lower speed (hysteresis).
    Subcritical,
}

/// The criticality from the smallest orbit of a branch that reached its Hopf point at
/// `hopf_param`, given on which side the equilibrium is unstable.
pub fn criticality(branch: &Branch, hopf_param: f64, unstable_above: bool) -> Option<Criticality> {
    let smallest = branch
        .points
        .iter()
        .min_by(|a, b| a.size.total_cmp(&b.size))?;
    let on_unstable_side = (smallest.param > hopf_param) == unstable_above;
    match (smallest.orbit.stable(), on_unstable_side) {
        (true, true) => Some(Criticality::Supercritical),
        (false, false) => Some(Criticality::Subcritical),
        _ => None,
    }
}
