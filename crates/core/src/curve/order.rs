//! Choosing the order `J` of a fit (paper §2, last part; method.md §3).
//!
//! Two strategies over one cached error evaluator:
//!
//! * [`paper_search`]: evaluate `J = 3` and `J = 10`, keep a bracket
//!   `[lo, hi]` with `lo` failing and `hi` meeting the tolerances, and propose
//!   the next `J` by linear inter- or extrapolation of the error-versus-J line
//!   through two known points, aimed at the tolerance, rounded and clamped
//!   strictly inside the bracket, until the bracket closes.
//! * [`minimal_order`]: the exact smallest `J` that meets both tolerances,
//!   scanning upward (errors are cheap for every `J` once the data are
//!   transformed).
//!
//! Errors need not fall monotonically with `J`, so the two can differ; the
//! fit reports both.

use crate::curve::lsq::FitErrors;
use crate::geom::math::{Real, DEFAULT_EA, DEFAULT_EM};
use std::collections::BTreeMap;

/// The default highest order a search may try.
pub const DEFAULT_MAX_ORDER: usize = 32;

/// Tolerances and limits of the order search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderOptions {
    /// Average relative error tolerance `E_a` (default 1 %).
    pub ea: Real,
    /// Maximum relative error tolerance `E_M` (default 5 %).
    pub em: Real,
    /// Highest order tried (default [`DEFAULT_MAX_ORDER`]); also limited by
    /// the number of points (`2J + 1 ≤ I`).
    pub max_order: usize,
}

impl Default for OrderOptions {
    fn default() -> Self {
        OrderOptions {
            ea: DEFAULT_EA,
            em: DEFAULT_EM,
            max_order: DEFAULT_MAX_ORDER,
        }
    }
}

/// Memoizes an error evaluator `J → errors` (`None`: order not available).
#[derive(Debug)]
pub struct ErrorCache<F> {
    eval: F,
    seen: BTreeMap<usize, Option<FitErrors>>,
}

impl<F: FnMut(usize) -> Option<FitErrors>> ErrorCache<F> {
    pub fn new(eval: F) -> Self {
        ErrorCache {
            eval,
            seen: BTreeMap::new(),
        }
    }
    /// The errors at order `j`, evaluated at most once.
    pub fn get(&mut self, j: usize) -> Option<FitErrors> {
        if let Some(e) = self.seen.get(&j) {
            return *e;
        }
        let e = (self.eval)(j);
        self.seen.insert(j, e);
        e
    }
    /// Every order evaluated so far with its errors, ascending.
    pub fn evaluated(&self) -> Vec<(usize, FitErrors)> {
        self.seen
            .iter()
            .filter_map(|(&j, e)| e.map(|e| (j, e)))
            .collect()
    }
}

/// The outcome of the paper's interpolation search.
#[derive(Clone, Debug, PartialEq)]
pub struct PaperSearch {
    /// Every `J` evaluated, in the order tried.
    pub tried: Vec<usize>,
    /// The smallest tried `J` that met both tolerances (`None`: none did).
    pub pick: Option<usize>,
}

/// Which error drives the line for a failing point, and its tolerance:
/// the one that fails; if both fail, the average error. For a point that
/// meets both, the one closest to its tolerance (the binding one).
fn driving_error(e: &FitErrors, o: &OrderOptions) -> (bool, Real) {
    let (fa, fm) = (e.ea > o.ea, e.em > o.em);
    let use_average = match (fa, fm) {
        (true, _) => true,
        (false, true) => false,
        (false, false) => e.ea / o.ea >= e.em / o.em,
    };
    (use_average, if use_average { o.ea } else { o.em })
}

fn value(e: &FitErrors, average: bool) -> Real {
    if average {
        e.ea
    } else {
        e.em
    }
}

/// The paper's search (see the module docs). `limit` is the highest order
/// available (the smaller of the option and what the points support).
pub fn paper_search<F: FnMut(usize) -> Option<FitErrors>>(
    cache: &mut ErrorCache<F>,
    opts: &OrderOptions,
    limit: usize,
) -> PaperSearch {
    let mut tried = Vec::new();
    if limit == 0 {
        return PaperSearch { tried, pick: None };
    }
    let mut eval = |j: usize, tried: &mut Vec<usize>| -> Option<FitErrors> {
        let e = cache.get(j);
        if e.is_some() && !tried.contains(&j) {
            tried.push(j);
        }
        e
    };
    let (j0, j1) = (3.min(limit), 10.min(limit));
    let Some(e0) = eval(j0, &mut tried) else {
        return PaperSearch { tried, pick: None };
    };
    let e1 = if j1 != j0 { eval(j1, &mut tried) } else { None };
    // Known points (J, errors); bracket ends: lo fails (0 = none known),
    // hi meets (limit + 1 = none known).
    let mut known: Vec<(usize, FitErrors)> = vec![(j0, e0)];
    if let Some(e1) = e1 {
        known.push((j1, e1));
    }
    let meets = |e: &FitErrors| e.meets(opts.ea, opts.em);
    let (mut lo, mut hi) = (0usize, limit + 1);
    for &(j, e) in &known {
        if meets(&e) {
            hi = hi.min(j);
        } else {
            lo = lo.max(j);
        }
    }
    // Errors need not be monotone: a failing J above a meeting one leaves an
    // inverted bracket; search below the meeting J then.
    if lo > hi {
        lo = 0;
    }
    while hi > lo + 1 {
        // The line through two known points: the bracket ends when both are
        // known, else the known end and its nearest other known point. The
        // error driving it is the failing end's (the meeting end's when no
        // failing point is known).
        let errors_of = |j: usize| known.iter().find(|k| k.0 == j).map(|k| k.1);
        let anchor = if lo > 0 { lo } else { hi };
        let partner = if lo > 0 && hi <= limit {
            Some(hi)
        } else {
            known
                .iter()
                .map(|k| k.0)
                .filter(|&j| j != anchor)
                .min_by_key(|&j| j.abs_diff(anchor))
        };
        let mut next = (lo + hi) / 2;
        if let (Some(ea), Some(jo)) = (errors_of(anchor), partner) {
            if let Some(eo) = errors_of(jo) {
                let (average, tol) = driving_error(&ea, opts);
                let (ya, yo) = (value(&ea, average), value(&eo, average));
                if (yo - ya).abs() > 0.0 {
                    let j = anchor as Real + (tol - ya) * (jo as Real - anchor as Real) / (yo - ya);
                    if j.is_finite() {
                        next = j.round().clamp(0.0, (limit + 1) as Real) as usize;
                    }
                }
            }
        }
        let next = next.clamp(lo + 1, hi - 1);
        let Some(e) = eval(next, &mut tried) else {
            // Not available: the order is beyond what the data support.
            hi = next;
            continue;
        };
        known.push((next, e));
        if meets(&e) {
            hi = next;
        } else {
            lo = next;
        }
    }
    let pick = known
        .iter()
        .filter(|(_, e)| meets(e))
        .map(|(j, _)| *j)
        .min();
    PaperSearch { tried, pick }
}

/// The exact smallest order in `1..=limit` that meets both tolerances.
pub fn minimal_order<F: FnMut(usize) -> Option<FitErrors>>(
    cache: &mut ErrorCache<F>,
    opts: &OrderOptions,
    limit: usize,
) -> Option<usize> {
    (1..=limit).find(|&j| cache.get(j).is_some_and(|e| e.meets(opts.ea, opts.em)))
}

/// The evaluated order with the best score `max(E_a/tol_a, E_M/tol_M)`: the
/// fit returned when no order meets the tolerances.
pub fn best_evaluated<F: FnMut(usize) -> Option<FitErrors>>(
    cache: &ErrorCache<F>,
    opts: &OrderOptions,
) -> Option<usize> {
    cache
        .evaluated()
        .into_iter()
        .min_by(|(_, a), (_, b)| {
            let s = |e: &FitErrors| (e.ea / opts.ea).max(e.em / opts.em);
            s(a).total_cmp(&s(b))
        })
        .map(|(j, _)| j)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic loop whose errors halve with each order.
    fn geometric(j: usize) -> Option<FitErrors> {
        let ea = 0.2 * 0.5f64.powi(j as i32);
        Some(FitErrors {
            ea,
            em: 4.0 * ea,
            rms: 0.0,
            max: 0.0,
        })
    }

    #[test]
    fn paper_and_minimal_agree_on_monotone_errors() {
        let opts = OrderOptions::default();
        let mut c = ErrorCache::new(geometric);
        let m = minimal_order(&mut c, &opts, 32).unwrap();
        let p = paper_search(&mut c, &opts, 32);
        // ea ≤ 1 % needs 0.2/2^J ≤ 0.01 → J ≥ 5; em = 4 ea ≤ 5 % → J ≥ 5.
        assert_eq!(m, 5);
        assert_eq!(p.pick, Some(5));
        assert_eq!(&p.tried[..2], &[3, 10]);
    }

    #[test]
    fn extrapolates_below_three_and_above_ten() {
        let opts = OrderOptions::default();
        // Easy: met already at J = 1.
        let mut easy = ErrorCache::new(|j| geometric(j + 6));
        assert_eq!(paper_search(&mut easy, &opts, 32).pick, Some(1));
        assert_eq!(minimal_order(&mut easy, &opts, 32), Some(1));
        // Hard: needs J = 14.
        let mut hard = ErrorCache::new(|j: usize| geometric(j.saturating_sub(9)));
        assert_eq!(minimal_order(&mut hard, &opts, 32), Some(14));
        let p = paper_search(&mut hard, &opts, 32);
        assert_eq!(p.pick, Some(14));
        assert!(p.tried.iter().all(|&j| j <= 32));
    }

    #[test]
    fn never_met_returns_none_and_best() {
        let opts = OrderOptions::default();
        let mut c = ErrorCache::new(|_| {
            Some(FitErrors {
                ea: 0.5,
                em: 0.9,
                rms: 0.0,
                max: 0.0,
            })
        });
        let p = paper_search(&mut c, &opts, 12);
        assert_eq!(p.pick, None);
        assert_eq!(minimal_order(&mut c, &opts, 12), None);
        assert!(best_evaluated(&c, &opts).is_some());
    }

    #[test]
    fn respects_a_low_limit() {
        let opts = OrderOptions::default();
        let mut c = ErrorCache::new(geometric);
        let p = paper_search(&mut c, &opts, 2);
        assert_eq!(p.pick, None);
        assert!(p.tried.iter().all(|&j| j <= 2));
    }
}
