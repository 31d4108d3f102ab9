//! Where to evaluate next, for `airring optimize`: a design space of variables with bounds and
//! scales, an objective to minimise and constraints (feasible where <= 0), searched by
//! constrained efficient global optimisation (egobox: Gaussian-process surrogates of objective
//! and constraints, expected improvement weighted by the probability of feasibility, a batch of
//! points per round), or by the baselines it must beat at the same budget: random sampling and a
//! full-factorial grid.
//!
//! The search works in the unit cube (log-scaled variables mapped by their logarithm) and asks
//! for evaluations in batches; the caller evaluates them however it likes (local jobs, a sweep's
//! cluster) and may stop and resume: the state of a search is its list of evaluations.

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

/// One evaluated design: its variables (own units), objective, constraints (<= 0 feasible).
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    pub x: Vec<f64>,
    pub objective: f64,
    pub constraints: Vec<f64>,
}

impl Evaluation {
    pub fn feasible(&self) -> bool {
        self.constraints.iter().all(|c| *c <= 0.0)
    }
}

/// The best feasible evaluation (smallest objective), if any.
pub fn best_feasible(evals: &[Evaluation]) -> Option<&Evaluation> {
    evals
        .iter()
        .filter(|e| e.feasible() && e.objective.is_finite())
        .min_by(|a, b| a.objective.total_cmp(&b.objective))
}

/// The objective and constraints of `evals` as the surrogates take them: an evaluation that
/// could not be completed (a failed run, no equilibrium) has non-finite values, which a Gaussian
/// process cannot hold. Its objective becomes the worst (largest) finite objective seen and each
/// non-finite constraint the larger of 1 and the worst finite value of that constraint: such a
/// point counts as bad and as infeasible, so the search moves away from it.
pub fn surrogate_data(evals: &[Evaluation], n_constraints: usize) -> Array2<f64> {
    let worst = |values: &mut dyn Iterator<Item = f64>| -> Option<f64> {
        values.filter(|v| v.is_finite()).reduce(f64::max)
    };
    let worst_objective = worst(&mut evals.iter().map(|e| e.objective)).unwrap_or(0.0);
    let worst_constraint: Vec<f64> = (0..n_constraints)
        .map(|j| {
            worst(&mut evals.iter().map(|e| e.constraints[j]))
                .unwrap_or(1.0)
                .max(1.0)
        })
        .collect();
    Array2::from_shape_fn((evals.len(), 1 + n_constraints), |(i, j)| {
        let (v, fallback) = if j == 0 {
            (evals[i].objective, worst_objective)
        } else {
            (evals[i].constraints[j - 1], worst_constraint[j - 1])
        };
        if v.is_finite() {
            v
        } else {
            fallback
        }
    })
}

/// How to choose the points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Constrained EGO: a Latin hypercube of `initial` points, then `batch` points per round.
    Ego {
        initial: usize,
        batch: usize,
        seed: u64,
    },
    /// Uniform random points.
    Random { seed: u64 },
    /// A full-factorial grid of about the budget's size.
    Grid,
}

/// The search: `evaluate` takes a batch of points (own units) and returns, for each, the
/// objective and the constraints (`n_constraints` of them). Stops after `budget` evaluations.
/// `done` holds evaluations of an earlier, interrupted search of the same method: they count
/// against the budget and are not repeated (random and grid continue their sequence; EGO asks
/// for what follows them).
pub fn search(
    variables: &[Variable],
    n_constraints: usize,
    method: Method,
    budget: usize,
    done: Vec<Evaluation>,
    mut evaluate: impl FnMut(&[Vec<f64>]) -> Result<Vec<(f64, Vec<f64>)>, String>,
) -> Result<Vec<Evaluation>, String> {
    let dim = variables.len();
    if dim == 0 {
        return Err("no design variables".into());
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
        for (x, (objective, constraints)) in xs.into_iter().zip(ys) {
            if constraints.len() != n_constraints {
                return Err(format!(
                    "an evaluation returned {} constraints, the problem has {n_constraints}",
                    constraints.len()
                ));
            }
            evals.push(Evaluation {
                x,
                objective,
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
                .configure(|c| {
                    c.n_cstr(n_constraints)
                        .seed(seed)
                        .configure_qei(|q| q.batch(batch))
                })
                .min_within(&unit)
                .map_err(|e| format!("the optimiser cannot be set up: {e}"))?;
            while evals.len() < budget {
                let x = Array2::from_shape_fn((evals.len(), dim), |(i, j)| {
                    variables[j].unit(evals[i].x[j])
                });
                let y = surrogate_data(&evals, n_constraints);
                let asked = egor.suggest(&x, &y);
                let want = budget - evals.len();
                let next: Vec<Vec<f64>> = asked
                    .axis_iter(Axis(0))
                    .take(want)
                    .map(|r| r.to_vec())
                    .collect();
                if next.is_empty() {
                    break;
                }
                run(next, &mut evals)?;
            }
        }
    }
    Ok(evals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_evaluations_reach_the_surrogates_as_the_worst_values_seen() {
        let e = |objective: f64, c: f64| Evaluation {
            x: vec![0.0],
            objective,
            constraints: vec![c],
        };
        let evals = [
            e(2.0, -0.5),
            e(f64::NAN, f64::INFINITY),
            e(5.0, 3.0),
            e(1.0, f64::NAN),
        ];
        let y = surrogate_data(&evals, 1);
        assert_eq!(y.column(0).to_vec(), vec![2.0, 5.0, 5.0, 1.0]);
        assert_eq!(y.column(1).to_vec(), vec![-0.5, 3.0, 3.0, 3.0]);
        // With only feasible finite constraints, a failed point is still infeasible (1 > 0).
        let y = surrogate_data(&[e(1.0, -2.0), e(f64::NAN, f64::NAN)], 1);
        assert_eq!(y.column(1).to_vec(), vec![-2.0, 1.0]);
        assert_eq!(y.column(0).to_vec(), vec![1.0, 1.0]);
    }
}
