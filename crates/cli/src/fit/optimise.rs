//! The search behind `nearfield fit`: Nelder–Mead (argmin) over the named settings, each mapped
//! onto the unit interval of its declared range (logarithmically for `log` settings), values
//! rounded to what a preset can state (four significant digits, whole numbers for integer
//! settings), every distinct point evaluated once, at most `budget` evaluations.

use anyhow::{Result, anyhow};
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use nearfield_render::settings::{Setting, SettingKind};
use std::cell::RefCell;

/// One setting the search moves, within `lo..=hi` of its declaration (or a narrower range the
/// user gave), starting at `start`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dimension {
    pub key: String,
    pub lo: f64,
    pub hi: f64,
    pub integer: bool,
    /// Searched on a log scale (the setting's kind is `log` and `lo > 0`).
    pub log: bool,
    pub start: f64,
}

impl Dimension {
    /// The search dimension of a declared numeric setting, within `range` when given (checked
    /// against the declaration), starting at `start` (clamped into the range).
    pub fn new(
        setting: &Setting,
        range: Option<(f64, f64)>,
        start: f64,
    ) -> std::result::Result<Self, String> {
        let SettingKind::Number {
            lo,
            hi,
            integer,
            log,
        } = setting.kind
        else {
            return Err(format!(
                "'{}' is not a numeric setting (it takes {}); fit searches numbers only",
                setting.key,
                setting.range_text().replace("\\|", "|")
            ));
        };
        let (lo, hi) = (f64::from(lo), f64::from(hi));
        let (lo, hi) = match range {
            None => (lo, hi),
            Some((a, b)) => {
                if !(a.is_finite() && b.is_finite() && a < b && a >= lo && b <= hi) {
                    return Err(format!(
                        "{}={a}..{b}: expected LO..HI with {lo} ≤ LO < HI ≤ {hi}",
                        setting.key
                    ));
                }
                (a, b)
            }
        };
        if integer && hi - lo < 1.0 {
            return Err(format!(
                "{}: the range {lo}..{hi} holds one whole number",
                setting.key
            ));
        }
        // A log range that starts at 0 is searched from a small positive value: the start / 1000,
        // at most a millionth of the range.
        let log_lo = if lo > 0.0 {
            lo
        } else {
            (start.abs() * 1e-3)
                .clamp(hi * 1e-9, hi * 1e-6)
                .max(f64::MIN_POSITIVE)
        };
        let log = log && !integer && hi > log_lo;
        Ok(Dimension {
            key: setting.key.to_string(),
            lo: if log { log_lo } else { lo },
            hi,
            integer,
            log,
            start: start.clamp(if log { log_lo } else { lo }, hi),
        })
    }

    /// The point of the unit interval a value sits at.
    fn to_unit(&self, x: f64) -> f64 {
        if self.log {
            (x.max(self.lo) / self.lo).ln() / (self.hi / self.lo).ln()
        } else {
            (x - self.lo) / (self.hi - self.lo)
        }
    }

    /// The value at a point of the unit interval (clamped into it), rounded as it is stated.
    fn value_at(&self, u: f64) -> f64 {
        let u = if u.is_finite() {
            u.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let x = if self.log {
            self.lo * (self.hi / self.lo).powf(u)
        } else {
            self.lo + u * (self.hi - self.lo)
        };
        self.round(x)
    }

    /// Whole numbers for integer settings, four significant digits otherwise.
    pub fn round(&self, x: f64) -> f64 {
        let x = x.clamp(self.lo, self.hi);
        if self.integer {
            return x.round();
        }
        if x == 0.0 {
            return 0.0;
        }
        let digits = 3 - x.abs().log10().floor() as i32;
        let scale = 10f64.powi(digits);
        ((x * scale).round() / scale).clamp(self.lo, self.hi)
    }

    /// The first step of the search from the start, on the unit interval: a tenth of the range,
    /// a factor of two on log ranges, at least one whole number for integer settings.
    fn step(&self) -> f64 {
        if self.log {
            return (2f64.ln() / (self.hi / self.lo).ln()).min(0.25);
        }
        let mut step: f64 = 0.1;
        if self.integer {
            step = step.max(1.5 / (self.hi - self.lo));
        }
        step.min(0.5)
    }

    /// A value as written after `key=`.
    pub fn text(&self, x: f64) -> String {
        if self.integer {
            format!("{}", x as i64)
        } else {
            let s = format!("{x}");
            // f64 round trips of four-digit values print short; guard against a long tail.
            if s.len() > 12 { format!("{x:.6e}") } else { s }
        }
    }
}

/// One evaluated point.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    pub values: Vec<f64>,
    pub cost: f64,
}

/// What the search found.
#[derive(Clone, Debug)]
pub struct Optimum {
    /// The best point evaluated.
    pub best: Evaluation,
    /// The start's cost (the first evaluation).
    pub start_cost: f64,
    /// Every distinct point, in the order evaluated.
    pub history: Vec<Evaluation>,
    /// Why it stopped: converged, or the budget was spent.
    pub stopped: &'static str,
}

/// The budget is spent: ends the run (argmin's executor has no evaluation limit).
#[derive(Debug)]
struct BudgetSpent;

impl std::fmt::Display for BudgetSpent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("evaluation budget spent")
    }
}

impl std::error::Error for BudgetSpent {}

struct Problem<'a, F> {
    dims: &'a [Dimension],
    budget: usize,
    objective: RefCell<F>,
    history: RefCell<Vec<Evaluation>>,
    /// An error of the objective (a lost device): ends the run and is returned.
    failed: RefCell<Option<anyhow::Error>>,
}

impl<F: FnMut(&[f64]) -> Result<f64>> Problem<'_, F> {
    fn evaluate(&self, values: Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        if let Some(e) = self.history.borrow().iter().find(|e| e.values == values) {
            return Ok(e.cost);
        }
        if self.history.borrow().len() >= self.budget {
            return Err(BudgetSpent.into());
        }
        let cost = match (self.objective.borrow_mut())(&values) {
            Ok(c) if c.is_finite() => c,
            Ok(_) => f64::MAX,
            Err(e) => {
                *self.failed.borrow_mut() = Some(e);
                return Err(BudgetSpent.into());
            }
        };
        self.history.borrow_mut().push(Evaluation { values, cost });
        Ok(cost)
    }
}

impl<F: FnMut(&[f64]) -> Result<f64>> CostFunction for Problem<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> std::result::Result<f64, argmin::core::Error> {
        let values = self
            .dims
            .iter()
            .zip(u)
            .map(|(d, &u)| d.value_at(u))
            .collect();
        self.evaluate(values)
    }
}

/// The problem lent to argmin's executor (which takes its problem by value), so that its record
/// survives a run that the budget ends.
struct ByRef<'p, P>(&'p P);

impl<P: CostFunction> CostFunction for ByRef<'_, P> {
    type Param = P::Param;
    type Output = P::Output;

    fn cost(&self, p: &Self::Param) -> std::result::Result<Self::Output, argmin::core::Error> {
        self.0.cost(p)
    }
}

/// Minimises `objective` over `dims` from their start values with at most `budget` distinct
/// evaluations (≥ 1). `tolerance`: the search has converged when the costs of the simplex's
/// corners spread by less than this (standard deviation).
pub fn minimise<F>(
    dims: &[Dimension],
    budget: usize,
    tolerance: f64,
    objective: F,
) -> Result<Optimum>
where
    F: FnMut(&[f64]) -> Result<f64>,
{
    assert!(budget >= 1 && !dims.is_empty());
    let problem = Problem {
        dims,
        budget,
        objective: RefCell::new(objective),
        history: RefCell::new(Vec::new()),
        failed: RefCell::new(None),
    };
    // The start, evaluated first so that it is the reference point of every report.
    let start: Vec<f64> = dims.iter().map(|d| d.round(d.start)).collect();
    let start_cost = problem.evaluate(start.clone()).map_err(|e| {
        problem
            .failed
            .borrow_mut()
            .take()
            .unwrap_or_else(|| anyhow!("{e}"))
    })?;
    let u0: Vec<f64> = dims
        .iter()
        .zip(&start)
        .map(|(d, &x)| d.to_unit(x))
        .collect();
    // The initial simplex: the start and one step along each axis (back where a step forward
    // would leave the range).
    let mut simplex = vec![u0.clone()];
    for (i, d) in dims.iter().enumerate() {
        let mut p = u0.clone();
        let step = d.step();
        p[i] = if u0[i] + step <= 1.0 {
            u0[i] + step
        } else {
            u0[i] - step
        };
        simplex.push(p);
    }
    let mut stopped = "converged";
    // The simplex's corners are evaluated here (argmin's initialisation cannot stop early), so
    // that its own evaluation of them finds them done.
    let room = budget > dims.len();
    if room {
        for p in &simplex[1..] {
            if problem.cost(p).is_err() {
                return Err(problem
                    .failed
                    .borrow_mut()
                    .take()
                    .unwrap_or_else(|| anyhow!("evaluation budget spent")));
            }
        }
    }
    if room {
        let solver = NelderMead::new(simplex)
            .with_sd_tolerance(tolerance)
            .map_err(|e| anyhow!("{e}"))?;
        let run = Executor::new(ByRef(&problem), solver)
            .configure(|state| state.max_iters(budget as u64 * 4))
            .run();
        match run {
            Ok(result) => {
                if result
                    .state()
                    .get_termination_reason()
                    .is_some_and(|r| matches!(r, argmin::core::TerminationReason::MaxItersReached))
                {
                    stopped = "iteration limit";
                }
            }
            Err(e) if e.downcast_ref::<BudgetSpent>().is_some() => {
                if let Some(failed) = problem.failed.borrow_mut().take() {
                    return Err(failed);
                }
                stopped = "budget spent";
            }
            Err(e) => return Err(anyhow!("the search failed: {e}")),
        }
    } else {
        stopped = "budget spent";
    }
    let history = problem.history.into_inner();
    let best = history
        .iter()
        .min_by(|a, b| a.cost.total_cmp(&b.cost))
        .cloned()
        .expect("the start was evaluated");
    Ok(Optimum {
        best,
        start_cost,
        history,
        stopped,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn number(key: &'static str, lo: f32, hi: f32, integer: bool, log: bool) -> Setting {
        Setting {
            key,
            kind: SettingKind::Number {
                lo,
                hi,
                integer,
                log,
            },
            role: nearfield_render::settings::Role::Uniform,
            only: &[],
            default: "1",
            unit: "",
            doc: "",
        }
    }

    #[test]
    fn finds_the_minimum_of_a_parabola_in_a_linear_range() {
        let s = number("strength", 0.0, 16.0, false, false);
        let d = vec![Dimension::new(&s, None, 1.0).unwrap()];
        let o = minimise(&d, 40, 1e-9, |x| Ok((x[0] - 6.37).powi(2) + 0.5)).unwrap();
        assert!((o.best.values[0] - 6.37).abs() < 0.02, "{o:?}");
        assert_eq!(o.start_cost, (1.0f64 - 6.37).powi(2) + 0.5);
        assert!(o.history.len() <= 40);
    }

    #[test]
    fn finds_a_minimum_decades_away_in_a_log_range_that_starts_at_zero() {
        let s = number("distance_clamp", 0.0, 1e6, false, true);
        let d = vec![Dimension::new(&s, None, 0.1).unwrap()];
        assert!(d[0].log && d[0].lo > 0.0);
        // Minimal at 0.0023 (log-parabola).
        let o = minimise(&d, 60, 1e-10, |x| Ok((x[0] / 0.0023).ln().powi(2))).unwrap();
        let x = o.best.values[0];
        assert!((x / 0.0023).ln().abs() < 0.05, "{x} {o:?}");
    }

    #[test]
    fn finds_the_optimum_of_two_settings_with_one_integer() {
        let a = number("steps", 1.0, 16.0, true, false);
        let b = number("falloff", 0.0, 1.0, false, false);
        let d = vec![
            Dimension::new(&a, None, 2.0).unwrap(),
            Dimension::new(&b, None, 0.1).unwrap(),
        ];
        let o = minimise(&d, 80, 1e-12, |x| {
            Ok((x[0] - 9.0).powi(2) + 40.0 * (x[1] - 0.62).powi(2))
        })
        .unwrap();
        assert_eq!(o.best.values[0], 9.0, "{o:?}");
        assert!((o.best.values[1] - 0.62).abs() < 0.02, "{o:?}");
    }

    #[test]
    fn stops_at_the_budget_and_never_evaluates_a_point_twice() {
        let s = number("strength", 0.0, 16.0, false, false);
        let d = vec![Dimension::new(&s, None, 1.0).unwrap()];
        let mut calls = 0;
        let o = minimise(&d, 5, 0.0, |x| {
            calls += 1;
            Ok((x[0] - 12.0).abs())
        })
        .unwrap();
        assert_eq!(calls, 5);
        assert_eq!(o.history.len(), 5);
        assert_eq!(o.stopped, "budget spent");
        let mut seen: Vec<f64> = o.history.iter().map(|e| e.values[0]).collect();
        seen.sort_by(f64::total_cmp);
        seen.dedup();
        assert_eq!(seen.len(), 5);
    }

    #[test]
    fn stays_within_a_narrowed_range_and_rounds_to_four_digits() {
        let s = number("strength", 0.0, 16.0, false, false);
        let d = vec![Dimension::new(&s, Some((0.5, 2.0)), 1.0).unwrap()];
        let o = minimise(&d, 30, 1e-9, |x| Ok(-x[0])).unwrap();
        assert!(o.history.iter().all(|e| (0.5..=2.0).contains(&e.values[0])));
        assert_eq!(o.best.values[0], 2.0);
        assert_eq!(d[0].round(1.234567), 1.235);
        assert_eq!(d[0].round(0.5123456), 0.5123);
        assert!(Dimension::new(&s, Some((3.0, 2.0)), 1.0).is_err());
        assert!(Dimension::new(&s, Some((0.0, 17.0)), 1.0).is_err());
    }

    #[test]
    fn an_objective_error_ends_the_search_with_that_error() {
        let s = number("strength", 0.0, 16.0, false, false);
        let d = vec![Dimension::new(&s, None, 1.0).unwrap()];
        let mut n = 0;
        let r = minimise(&d, 30, 1e-9, |_| {
            n += 1;
            if n == 3 {
                Err(anyhow!("device lost"))
            } else {
                Ok(n as f64)
            }
        });
        assert_eq!(r.unwrap_err().to_string(), "device lost");
    }
}
