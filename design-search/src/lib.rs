//! Where to evaluate next, for `airring optimize`: a design space of variables with bounds and
//! scales, one or two objectives to minimise and constraints (feasible where <= 0), searched by
//! constrained efficient global optimisation (egobox: Gaussian-process surrogates of objectives
//! and constraints; with one objective expected improvement weighted by the probability of
//! feasibility, with two the expected hypervolume improvement of the Pareto front; a batch of
//! points per round), or by the baselines it must beat at the same budget: random sampling and a
//! full-factorial grid.
//!
//! The search works in the unit cube (log-scaled variables mapped by their logarithm) and asks
//! for evaluations in batches; the caller evaluates them however it likes (local jobs, a sweep's
//! cluster) and may stop and resume: the state of a search is its list of evaluations.
//! [`safe_set`] says what the constraint surrogates make of any point: the search's view of the
//! safe set, for maps and for checking it against a brute-force grid.

use egobox_doe::{FullFactorial, Lhs, Random, SamplingMethod};
use egobox_ego::{Cstr, EgorServiceFactory};
use ndarray::{Array2, Axis};
use rand_xoshiro::rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;

/// How a variable maps to the unit interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    /// By its logarithm (a stiffness over decades).
    Log,
}

/// A design variable: its name, bounds (in its own unit) and scale.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub lo: f64,
    pub hi: f64,
    pub scale: Scale,
}

impl Variable {
    pub fn new(name: &str, lo: f64, hi: f64, scale: Scale) -> Result<Variable, String> {
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(format!("{name}: the bounds [{lo}, {hi}] must be finite"));
        }
        if lo >= hi {
            return Err(format!(
                "{name}: the bounds [{lo}, {hi}] are empty or inverted (lower must be below upper)"
            ));
        }
        if scale == Scale::Log && lo <= 0.0 {
            return Err(format!(
                "{name}: a log-scaled variable needs bounds > 0 (lower = {lo})"
            ));
        }
        Ok(Variable {
            name: name.into(),
            lo,
            hi,
            scale,
        })
    }

    /// The value at `u` in [0, 1].
    pub fn at(&self, u: f64) -> f64 {
        match self.scale {
            Scale::Linear => self.lo + u * (self.hi - self.lo),
            Scale::Log => (self.lo.ln() + u * (self.hi.ln() - self.lo.ln())).exp(),
        }
    }

    /// Where `x` lies in [0, 1].
    pub fn unit(&self, x: f64) -> f64 {
        match self.scale {
            Scale::Linear => (x - self.lo) / (self.hi - self.lo),
            Scale::Log => (x.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln()),
        }
    }
}

/// One evaluated design: its variables (own units), objectives (to minimise), constraints
/// (<= 0 feasible).
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    pub x: Vec<f64>,
    pub objectives: Vec<f64>,
    pub constraints: Vec<f64>,
}

impl Evaluation {
    pub fn feasible(&self) -> bool {
        self.constraints.iter().all(|c| *c <= 0.0)
    }
}

/// The best feasible evaluation (smallest first objective), if any.
pub fn best_feasible(evals: &[Evaluation]) -> Option<&Evaluation> {
    evals
        .iter()
        .filter(|e| e.feasible() && e.objectives[0].is_finite())
        .min_by(|a, b| a.objectives[0].total_cmp(&b.objectives[0]))
}

/// The objectives and constraints of `evals` as the surrogates take them, one column each: an
/// evaluation that could not be completed (a failed run, no equilibrium) has non-finite values,
/// which a Gaussian process cannot hold. Each non-finite objective becomes the worst (largest)
/// finite value of that objective seen and each non-finite constraint the larger of 1 and the
/// worst finite value of that constraint: such a point counts as bad and as infeasible, so the
/// search moves away from it.
pub fn surrogate_data(
    evals: &[Evaluation],
    n_objectives: usize,
    n_constraints: usize,
) -> Array2<f64> {
    let worst = |values: &mut dyn Iterator<Item = f64>| -> Option<f64> {
        values.filter(|v| v.is_finite()).reduce(f64::max)
    };
    let value = |e: &Evaluation, j: usize| {
        if j < n_objectives {
            e.objectives[j]
        } else {
            e.constraints[j - n_objectives]
        }
    };
    let fallback: Vec<f64> = (0..n_objectives + n_constraints)
        .map(|j| {
            let w = worst(&mut evals.iter().map(|e| value(e, j)));
            if j < n_objectives {
                w.unwrap_or(0.0)
            } else {
                w.unwrap_or(1.0).max(1.0)
            }
        })
        .collect();
    Array2::from_shape_fn((evals.len(), n_objectives + n_constraints), |(i, j)| {
        let v = value(&evals[i], j);
        if v.is_finite() {
            v
        } else {
            fallback[j]
        }
    })
}

/// What evaluating one design gives: its objectives and its constraints.
pub type Outcome = (Vec<f64>, Vec<f64>);

/// What the constraint surrogates say about one point.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    /// Each constraint's predicted mean (<= 0 feasible) and standard deviation.
    pub mean: Vec<f64>,
    pub sd: Vec<f64>,
    /// The probability that every constraint holds (the constraints taken as independent).
    pub p_feasible: f64,
}

impl Prediction {
    /// The surrogates' verdict: every predicted constraint mean <= 0.
    pub fn feasible(&self) -> bool {
        self.mean.iter().all(|m| *m <= 0.0)
    }
}

/// The search's view of the safe set at `points` (own units): Gaussian processes of the
/// constraints fitted to `evals` as the search fits them (egobox's default mixture of one
/// cluster, on the unit cube, non-finite values replaced as in [`surrogate_data`]).
pub fn safe_set(
    variables: &[Variable],
    evals: &[Evaluation],
    n_constraints: usize,
    points: &[Vec<f64>],
) -> Result<Vec<Prediction>, String> {
    use egobox_moe::GpMixture;
    use linfa::traits::Fit;
    if evals.len() < 2 {
        return Err(format!(
            "the surrogates need at least 2 evaluations ({} given)",
            evals.len()
        ));
    }
    let dim = variables.len();
    let unit =
        |x: &[f64]| -> Vec<f64> { variables.iter().zip(x).map(|(v, &x)| v.unit(x)).collect() };
    let xt = Array2::from_shape_fn((evals.len(), dim), |(i, j)| {
        variables[j].unit(evals[i].x[j])
    });
    let xp = Array2::from_shape_fn((points.len(), dim), |(i, j)| unit(&points[i])[j]);
    let n_objectives = evals[0].objectives.len();
    let y = surrogate_data(evals, n_objectives, n_constraints);
    let mut means = vec![];
    let mut sds = vec![];
    for j in 0..n_constraints {
        let yj = y.column(n_objectives + j).to_owned();
        // Seeded: the default generator draws from entropy, and a map or a replaced repeat
        // must come out the same on every run.
        let gp = GpMixture::params()
            .with_rng(Xoshiro256Plus::seed_from_u64(0))
            .fit(&linfa::Dataset::new(xt.clone(), yj))
            .map_err(|e| format!("constraint {j}: the surrogate cannot be fitted: {e}"))?;
        let (m, v) = gp
            .predict_valvar(&xp.view())
            .map_err(|e| format!("constraint {j}: the surrogate cannot predict: {e}"))?;
        means.push(m);
        sds.push(v.mapv(|v| v.max(0.0).sqrt()));
    }
    Ok((0..points.len())
        .map(|i| {
            let mean: Vec<f64> = means.iter().map(|m| m[i]).collect();
            let sd: Vec<f64> = sds.iter().map(|s| s[i]).collect();
            let p_feasible = mean
                .iter()
                .zip(&sd)
                .map(|(&m, &s)| {
                    if s > 0.0 {
                        // P(c <= 0) for c ~ N(m, s^2).
                        0.5 * libm::erfc(m / (s * std::f64::consts::SQRT_2))
                    } else if m <= 0.0 {
                        1.0
                    } else {
                        0.0
                    }
                })
                .product();
            Prediction {
                mean,
                sd,
                p_feasible,
            }
        })
        .collect())
}

/// How to choose the points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Constrained EGO: a Latin hypercube of `initial` points, then `batch` points per round.
    /// A point asked within `repeat_distance` (unit cube) of one evaluated or earlier in its
    /// batch is replaced (`replace_repeats`); 0 keeps every point EGO asks for. A caller that
    /// rounds its designs sets it to that resolution: closer points are the same design.
    Ego {
        initial: usize,
        batch: usize,
        seed: u64,
        repeat_distance: f64,
    },
    /// Uniform random points.
    Random { seed: u64 },
    /// A full-factorial grid of about the budget's size.
    Grid,
}

/// The search: `evaluate` takes a batch of points (own units) and returns, for each, the
/// objectives (`n_objectives`, 1 or 2) and the constraints (`n_constraints`). Stops after
/// `budget` evaluations.
/// `done` holds evaluations of an earlier, interrupted search of the same method: they count
/// against the budget and are not repeated (random and grid continue their sequence; EGO asks
/// for what follows them).
pub fn search(
    variables: &[Variable],
    n_objectives: usize,
    n_constraints: usize,
    method: Method,
    budget: usize,
    done: Vec<Evaluation>,
    mut evaluate: impl FnMut(&[Vec<f64>]) -> Result<Vec<Outcome>, String>,
) -> Result<Vec<Evaluation>, String> {
    let dim = variables.len();
    if dim == 0 {
        return Err("no design variables".into());
    }
    if !(1..=2).contains(&n_objectives) {
        return Err(format!(
            "one or two objectives are supported ({n_objectives} given)"
        ));
    }
    let unit = Array2::from_shape_fn((dim, 2), |(_, j)| j as f64);
    let to_x = |u: &[f64]| -> Vec<f64> {
        variables
            .iter()
            .zip(u)
            .map(|(v, &u)| v.at(u.clamp(0.0, 1.0)))
            .collect()
    };
    let mut evals = done;
    let mut run = |points: Vec<Vec<f64>>, evals: &mut Vec<Evaluation>| -> Result<(), String> {
        let xs: Vec<Vec<f64>> = points.iter().map(|u| to_x(u)).collect();
        let ys = evaluate(&xs)?;
        if ys.len() != xs.len() {
            return Err(format!(
                "{} points asked, {} evaluations returned",
                xs.len(),
                ys.len()
            ));
        }
        for (x, (objectives, constraints)) in xs.into_iter().zip(ys) {
            if objectives.len() != n_objectives {
                return Err(format!(
                    "an evaluation returned {} objectives, the problem has {n_objectives}",
                    objectives.len()
                ));
            }
            if constraints.len() != n_constraints {
                return Err(format!(
                    "an evaluation returned {} constraints, the problem has {n_constraints}",
                    constraints.len()
                ));
            }
            evals.push(Evaluation {
                x,
                objectives,
                constraints,
            });
        }
        Ok(())
    };
    let rows =
        |a: Array2<f64>| -> Vec<Vec<f64>> { a.rows().into_iter().map(|r| r.to_vec()).collect() };
    match method {
        Method::Random { seed } => {
            let all = rows(
                Random::new(&unit)
                    .with_rng(Xoshiro256Plus::seed_from_u64(seed))
                    .sample(budget),
            );
            let next: Vec<_> = all.into_iter().skip(evals.len()).collect();
            if !next.is_empty() {
                run(next, &mut evals)?;
            }
        }
        Method::Grid => {
            let all = rows(FullFactorial::new(&unit).sample(budget));
            let next: Vec<_> = all.into_iter().take(budget).skip(evals.len()).collect();
            if !next.is_empty() {
                run(next, &mut evals)?;
            }
        }
        Method::Ego {
            initial,
            batch,
            seed,
            repeat_distance,
        } => {
            if initial < 2 || initial > budget || batch == 0 {
                return Err(format!(
                    "EGO needs at least 2 initial points within the budget ({budget}) and a \
                     batch >= 1 (initial = {initial}, batch = {batch})"
                ));
            }
            let doe = rows(
                Lhs::new(&unit)
                    .with_rng(Xoshiro256Plus::seed_from_u64(seed))
                    .sample(initial),
            );
            let next: Vec<_> = doe.into_iter().skip(evals.len()).collect();
            if !next.is_empty() {
                run(next, &mut evals)?;
            }
            let egor = EgorServiceFactory::<Cstr>::optimize()
                // Two objectives: egobox's default multi-objective criterion (the expected
                // hypervolume improvement of the constrained Pareto front), batches by qEI.
                .configure(|c| {
                    c.n_obj(n_objectives)
                        .n_cstr(n_constraints)
                        .seed(seed)
                        .configure_qei(|q| q.batch(batch))
                })
                .min_within(&unit)
                .map_err(|e| format!("the optimiser cannot be set up: {e}"))?;
            while evals.len() < budget {
                let x = Array2::from_shape_fn((evals.len(), dim), |(i, j)| {
                    variables[j].unit(evals[i].x[j])
                });
                let y = surrogate_data(&evals, n_objectives, n_constraints);
                let asked = egor.suggest(&x, &y);
                let want = budget - evals.len();
                let next: Vec<Vec<f64>> = asked
                    .axis_iter(Axis(0))
                    .take(want)
                    .map(|r| r.to_vec())
                    .collect();
                let next = if repeat_distance > 0.0 {
                    replace_repeats(
                        variables,
                        &evals,
                        n_constraints,
                        next,
                        seed,
                        repeat_distance,
                    )
                } else {
                    next
                };
                if next.is_empty() {
                    break;
                }
                run(next, &mut evals)?;
            }
        }
    }
    Ok(evals)
}

/// A replacement keeps at least this distance from every point evaluated or asked for.
const REPLACEMENT_SPACING: f64 = 0.05;

/// EGO asks again for a design it has evaluated when its criterion is flat there (an objective
/// equal over a whole region, such as a margin capped on a stable plateau): a wasted evaluation.
/// Each such repeat (within `repeat_distance` in the unit cube: the caller's resolution, below
/// which two points are one design), and each point of the batch repeating an earlier one, is
/// replaced by the
/// design the constraint surrogates are least sure about, p (1 - p) largest for p the
/// probability of feasibility, among a seeded Latin hypercube of candidates kept
/// `REPLACEMENT_SPACING` from every other point: it sharpens the boundary of the safe set. Without
/// constraints, the candidate farthest from all points. Deterministic in `evals` and `seed`, so a
/// resumed search asks for the same points.
fn replace_repeats(
    variables: &[Variable],
    evals: &[Evaluation],
    n_constraints: usize,
    next: Vec<Vec<f64>>,
    seed: u64,
    repeat_distance: f64,
) -> Vec<Vec<f64>> {
    let dim = variables.len();
    let mut taken: Vec<Vec<f64>> = evals
        .iter()
        .map(|e| {
            variables
                .iter()
                .zip(&e.x)
                .map(|(v, &x)| v.unit(x))
                .collect()
        })
        .collect();
    let dist = |a: &[f64], b: &[f64]| -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let nearest = |taken: &[Vec<f64>], u: &[f64]| -> f64 {
        taken
            .iter()
            .map(|t| dist(t, u))
            .fold(f64::INFINITY, f64::min)
    };
    let mut pool: Option<(Vec<Vec<f64>>, Vec<f64>)> = None;
    let mut out = Vec::with_capacity(next.len());
    for u in next {
        if nearest(&taken, &u) >= repeat_distance {
            taken.push(u.clone());
            out.push(u);
            continue;
        }
        let (cands, score) = pool.get_or_insert_with(|| {
            let unit = Array2::from_shape_fn((dim, 2), |(_, j)| j as f64);
            let cands: Vec<Vec<f64>> = Lhs::new(&unit)
                .with_rng(Xoshiro256Plus::seed_from_u64(
                    seed.wrapping_add(evals.len() as u64),
                ))
                .sample(256 * dim)
                .rows()
                .into_iter()
                .map(|r| r.to_vec())
                .collect();
            let xs: Vec<Vec<f64>> = cands
                .iter()
                .map(|u| variables.iter().zip(u).map(|(v, &u)| v.at(u)).collect())
                .collect();
            let score =
                match (n_constraints > 0).then(|| safe_set(variables, evals, n_constraints, &xs)) {
                    Some(Ok(pred)) => pred
                        .iter()
                        .map(|p| p.p_feasible * (1.0 - p.p_feasible))
                        .collect(),
                    _ => vec![0.0; cands.len()],
                };
            (cands, score)
        });
        let best = (0..cands.len())
            .filter(|&i| nearest(&taken, &cands[i]) >= REPLACEMENT_SPACING)
            .max_by(|&a, &b| {
                score[a]
                    .total_cmp(&score[b])
                    .then(nearest(&taken, &cands[a]).total_cmp(&nearest(&taken, &cands[b])))
            });
        let v = match best {
            Some(i) => cands[i].clone(),
            // The cube is full at this spacing: the candidate farthest from every point.
            None => (0..cands.len())
                .max_by(|&a, &b| nearest(&taken, &cands[a]).total_cmp(&nearest(&taken, &cands[b])))
                .map(|i| cands[i].clone())
                .unwrap_or(u),
        };
        taken.push(v.clone());
        out.push(v);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_evaluations_reach_the_surrogates_as_the_worst_values_seen() {
        let e = |objective: f64, c: f64| Evaluation {
            x: vec![0.0],
            objectives: vec![objective],
            constraints: vec![c],
        };
        let evals = [
            e(2.0, -0.5),
            e(f64::NAN, f64::INFINITY),
            e(5.0, 3.0),
            e(1.0, f64::NAN),
        ];
        let y = surrogate_data(&evals, 1, 1);
        assert_eq!(y.column(0).to_vec(), vec![2.0, 5.0, 5.0, 1.0]);
        assert_eq!(y.column(1).to_vec(), vec![-0.5, 3.0, 3.0, 3.0]);
        // With only feasible finite constraints, a failed point is still infeasible (1 > 0).
        let y = surrogate_data(&[e(1.0, -2.0), e(f64::NAN, f64::NAN)], 1, 1);
        assert_eq!(y.column(1).to_vec(), vec![-2.0, 1.0]);
        assert_eq!(y.column(0).to_vec(), vec![1.0, 1.0]);
    }

    #[test]
    fn a_repeated_point_is_replaced_where_the_safe_set_is_least_certain() {
        let v = vec![
            Variable::new("a", 0.0, 1.0, Scale::Linear).unwrap(),
            Variable::new("b", 0.0, 1.0, Scale::Linear).unwrap(),
        ];
        // Feasible left of a = 0.49, a step in the constraint as a whirl that sets in is:
        // evaluations on a 5 x 5 grid.
        let evals: Vec<Evaluation> = (0..25)
            .map(|k| {
                let x = vec![(k % 5) as f64 / 4.0, (k / 5) as f64 / 4.0];
                Evaluation {
                    constraints: vec![if x[0] < 0.49 { -1.0 } else { 1.0 }],
                    objectives: vec![0.0],
                    x,
                }
            })
            .collect();
        let fresh = vec![0.1, 0.9];
        let out = replace_repeats(
            &v,
            &evals,
            1,
            vec![evals[7].x.clone(), fresh.clone(), evals[7].x.clone()],
            3,
            1e-3,
        );
        assert_eq!(out[1], fresh, "a new point is kept");
        let d = |a: &[f64], b: &[f64]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        for r in [&out[0], &out[2]] {
            assert!(
                evals.iter().all(|e| d(&e.x, r) >= REPLACEMENT_SPACING),
                "{r:?}"
            );
            // Between the last safe and the first unsafe column (a = 0.25 and 0.5), where the
            // boundary lies, not deep in either side.
            assert!((0.25..=0.5).contains(&r[0]), "{r:?}");
        }
        assert!(d(&out[0], &out[2]) >= REPLACEMENT_SPACING, "{out:?}");
        // The same inputs, the same replacements (a resumed search asks for the same points).
        let again = replace_repeats(
            &v,
            &evals,
            1,
            vec![evals[7].x.clone(), fresh, evals[7].x.clone()],
            3,
            1e-3,
        );
        assert_eq!(out, again);
    }
}
