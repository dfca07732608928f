//! Rate-distortion control of a reconstruction: the user asks for the
//! model's accuracy (its symmetric RMS distance to the input, measured on
//! the outer skin by the [`Report`]) or for its size (design parameters),
//! instead of the per-section tolerances.
//!
//! One coarseness `c` scales the pipeline's tolerances together:
//! `E_a = c·E_a⁰`, `E_M = c·E_M⁰`, the pruning tolerance (a section goes
//! where its neighbours' skinning passes its loop within it,
//! `plan/prune.rs`), the refinement tolerance and the digits' section
//! spacing by `c` (`c = 1` is the given options; the parts' spacing stays,
//! as the pruning takes out the sections the surface does not need; a
//! finger is too short for the pruning, which keeps three sections at
//! each end). A search on `log c` (a reconstruction per
//! trial) finds the coarsest model that meets the target RMS, or the
//! finest within the parameter budget, shrinking a bracket: each trial's
//! coarseness is where the line through the bracket's measured ends (log
//! RMS or log parameters against log c) meets the target, or from one end
//! along the usual slope (RMS about c^(1/3)), two or three
//! reconstructions on the shared bodies where a bisection took four to
//! seven. Where the RMS jumps across a target between two trials (a
//! section dropped or a transition left out), a second bisection scales
//! the curve tolerances alone, at the chosen coarseness, up to the
//! coarsest trial's. The trials share the input's preparation and
//! segmentation, and a scan's frame is chosen once (`body/repeat.rs`).
//! A target below what finer tolerances reach ends the search when a finer
//! trial's RMS hardly differs from a coarser one's (`FLOOR_GAIN`).

use crate::anatomy::BodyGeometry;
use crate::body::repeat::{reconstruct_each, Run};
use crate::body::{Body, ReconstructError, ReconstructOptions, Report};
use crate::geom::math::Real;
use thiserror::Error;

/// The narrowest bracket on `log c` (or `log f`) worth a trial: models
/// 2 % apart in their tolerances differ by a few parameters.
const NARROWEST: Real = 0.02;

/// A finer trial whose RMS is within this fraction of the coarser one's,
/// both above the target, ends a target RMS search: the model's error is
/// the segmentation's and the sections', not the curve tolerances'. (An
/// RMS that rises at a finer trial, a section dropped there, does not end
/// it.)
const FLOOR_GAIN: Real = 0.01;

/// What the search aims for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Goal {
    /// The symmetric RMS distance in mm ([`Report::distance_mm`]): the
    /// smallest model whose RMS is at most this.
    TargetRms(Real),
    /// The most accurate model of at most this many design parameters.
    MaxParameters(usize),
}

/// How the search runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RateOptions {
    /// The finest coarseness tried. Default 0.35.
    pub min_coarseness: Real,
    /// The coarsest. Default 6.
    pub max_coarseness: Real,
    /// Bisection steps after the bracket. Default 6.
    pub steps: usize,
    /// A goal is met closely enough (the search stops) when the model's
    /// RMS, or its parameters for a budget, lie within this fraction below
    /// it. Default 0.05.
    pub rms_slack: Real,
}

impl Default for RateOptions {
    fn default() -> Self {
        RateOptions {
            min_coarseness: 0.35,
            max_coarseness: 6.0,
            steps: 6,
            rms_slack: 0.05,
        }
    }
}

/// One reconstruction of the search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trial {
    pub coarseness: Real,
    /// The curve tolerances' further factor (1 in the first search).
    pub tolerance: Real,
    /// `None` when the reconstruction failed at this coarseness.
    pub design_parameters: Option<usize>,
    pub rms_mm: Option<Real>,
}

/// The model the search chose, and every trial.
#[derive(Clone, Debug)]
pub struct RateOutcome {
    pub body: Body,
    pub report: Report,
    /// The chosen model's coarseness.
    pub coarseness: Real,
    /// Its curve tolerances' further factor (E_a, E_M × `c` × this).
    pub tolerance: Real,
    /// Whether it meets the goal (a target RMS below what the finest
    /// trial reaches is not met: the most accurate model is returned).
    pub met: bool,
    pub trials: Vec<Trial>,
}

/// Why the search gave no model.
#[derive(Debug, Error)]
pub enum RateError {
    /// Every trial failed; the error of the one at coarseness 1.
    #[error(transparent)]
    Reconstruct(#[from] ReconstructError),
    /// Even the coarsest trial needs more parameters than the budget.
    #[error("no model within {budget} design parameters: the coarsest reconstruction tried needs {fewest}")]
    Budget { budget: usize, fewest: usize },
    /// A goal that is not a positive number.
    #[error("the goal {0} is not a positive number")]
    BadGoal(String),
}

/// The options at coarseness `c`.
pub fn coarsened(base: &ReconstructOptions, c: Real) -> ReconstructOptions {
    let mut o = *base;
    o.fit.ea = base.fit.ea * c;
    o.fit.em = base.fit.em * c;
    o.prune_tolerance = (base.prune_tolerance * c).min(crate::body::MAX_PRUNE_TOLERANCE);
    o.refine_tolerance = base.refine_tolerance * c;
    o.digit_spacing = base.digit_spacing * c;
    o
}

/// The searched quantity on a log scale: the RMS for a target RMS, the
/// parameters for a budget.
fn metric(goal: Goal, r: &Report) -> Real {
    match goal {
        Goal::TargetRms(_) => r.distance_mm.rms.ln(),
        Goal::MaxParameters(_) => (r.design_parameters as Real).ln(),
    }
}

/// The [`metric`] aimed at (the middle of the accepted band) and its usual
/// slope against log c (the built-in and shared bodies: RMS about
/// c^(1/3), parameters c^-0.65).
fn aim_and_slope(goal: Goal, options: &RateOptions) -> (Real, Real) {
    let band = 1.0 - 0.5 * options.rms_slack;
    match goal {
        Goal::TargetRms(t) => ((t * band).ln(), 1.0 / 3.0),
        Goal::MaxParameters(n) => ((n as Real * band).ln(), -0.65),
    }
}

/// The next trial's log coarseness inside the bracket `(lo, hi)`: where
/// the line through the two ends' metrics (the log RMS or log parameters,
/// when measured) reaches `aim`, or from one measured end along the usual
/// `slope`, else the middle; kept a tenth of the bracket inside it, so
/// that a curve the line misjudges still shrinks the bracket.
fn next_trial(
    (lo, lo_m): (Real, Option<Real>),
    (hi, hi_m): (Real, Option<Real>),
    aim: Real,
    slope: Real,
) -> Real {
    let guess = match (lo_m, hi_m) {
        (Some(a), Some(b)) if (b - a).abs() > 1e-9 => lo + (aim - a) * (hi - lo) / (b - a),
        (Some(a), _) => lo + (aim - a) / slope,
        (None, Some(b)) => hi + (aim - b) / slope,
        (None, None) => Real::NAN,
    };
    let margin = 0.1 * (hi - lo);
    if guess.is_finite() {
        guess.clamp(lo + margin, hi - margin)
    } else {
        0.5 * (lo + hi)
    }
}

/// The options at coarseness `c` with the curve tolerances further
/// scaled by `f`.
fn at(base: &ReconstructOptions, c: Real, f: Real) -> ReconstructOptions {
    let mut o = coarsened(base, c);
    o.fit.ea *= f;
    o.fit.em *= f;
    o
}

/// A trial's coarseness, tolerance factor and result.
type Evaluated = ((Real, Real), Result<(Body, Report), ReconstructError>);
/// A kept model with its coarseness and tolerance factor.
type Kept = ((Real, Real), Body, Report);

/// Reconstructs `input` to meet `goal` (see the module's notes). The
/// trials share the input's preparation and segmentation, and a scan's
/// frame is chosen at the first (`body/repeat.rs`).
pub fn reconstruct_for(
    input: BodyGeometry<'_>,
    base: &ReconstructOptions,
    goal: Goal,
    options: &RateOptions,
    on_trial: impl FnMut(&Trial),
) -> Result<RateOutcome, RateError> {
    match goal {
        Goal::TargetRms(t) if !(t.is_finite() && t > 0.0) => {
            return Err(RateError::BadGoal(format!("rms {t} mm")))
        }
        Goal::MaxParameters(0) => return Err(RateError::BadGoal("0 parameters".to_string())),
        _ => {}
    }
    reconstruct_each(input, base, |run| {
        search(run, base, goal, options, on_trial)
    })
}

/// The search of [`reconstruct_for`], `run` reconstructing the input.
fn search(
    run: &mut Run<'_>,
    base: &ReconstructOptions,
    goal: Goal,
    options: &RateOptions,
    mut on_trial: impl FnMut(&Trial),
) -> Result<RateOutcome, RateError> {
    let feasible = |r: &Report| match goal {
        Goal::TargetRms(t) => r.distance_mm.rms <= t,
        Goal::MaxParameters(n) => r.design_parameters <= n,
    };
    // Among feasible models: fewer parameters for a target RMS, a lower
    // RMS for a budget.
    let better = |a: &Report, b: &Report| match goal {
        Goal::TargetRms(_) => a.design_parameters < b.design_parameters,
        Goal::MaxParameters(_) => a.distance_mm.rms < b.distance_mm.rms,
    };
    let close_enough = |r: &Report| match goal {
        Goal::TargetRms(t) => r.distance_mm.rms >= (1.0 - options.rms_slack) * t,
        Goal::MaxParameters(n) => {
            r.design_parameters as Real >= (1.0 - options.rms_slack) * n as Real
        }
    };
    let metric = |r: &Report| metric(goal, r);
    let (aim, slope) = aim_and_slope(goal, options);
    let mut trials = Vec::new();
    let mut evaluate = |c: Real, f: Real| -> Evaluated {
        let result = run(&at(base, c, f));
        let trial = Trial {
            coarseness: c,
            tolerance: f,
            design_parameters: result.as_ref().ok().map(|(_, r)| r.design_parameters),
            rms_mm: result.as_ref().ok().map(|(_, r)| r.distance_mm.rms),
        };
        on_trial(&trial);
        trials.push(trial);
        ((c, f), result)
    };
    let mut best: Option<Kept> = None;
    let mut first_error = None;
    let mut any: Option<Kept> = None;
    let mut keep = |(c, result): Evaluated, best: &mut Option<Kept>| -> Option<bool> {
        match result {
            Ok((body, report)) => {
                let ok = feasible(&report);
                if ok && best.as_ref().is_none_or(|(_, _, b)| better(&report, b)) {
                    *best = Some((c, body.clone(), report.clone()));
                }
                // The fallback when nothing is feasible: the most accurate
                // (target RMS) or the smallest (budget) model seen.
                let fallback = any.as_ref().is_none_or(|(_, _, a)| match goal {
                    Goal::TargetRms(_) => report.distance_mm.rms < a.distance_mm.rms,
                    Goal::MaxParameters(_) => report.design_parameters < a.design_parameters,
                });
                if fallback {
                    any = Some((c, body, report));
                }
                Some(ok)
            }
            Err(e) => {
                first_error.get_or_insert(e);
                None
            }
        }
    };
    // Feasibility holds on the fine side for a target RMS and on the coarse
    // side for a budget; bisect the bracket on log c.
    let fine_feasible = matches!(goal, Goal::TargetRms(_));
    // The bracket on log c, with the metric where an end was measured.
    let (mut lo, mut hi) = (options.min_coarseness.ln(), options.max_coarseness.ln());
    let (mut lo_m, mut hi_m): (Option<Real>, Option<Real>) = (None, None);
    let first = evaluate(1.0, 1.0);
    let m = first.1.as_ref().ok().map(|(_, r)| metric(r));
    match keep(first, &mut best) {
        Some(ok) if ok == fine_feasible => (lo, lo_m) = (0.0, m),
        Some(_) => (hi, hi_m) = (0.0, m),
        None => {}
    }
    let done = |best: &Option<Kept>| best.as_ref().is_some_and(|(_, _, r)| close_enough(r));
    // A target RMS below what finer tolerances reach: a finer trial still
    // too far, its RMS hardly other than the coarser one's.
    let mut floor = false;
    for _ in 0..options.steps {
        if done(&best) || hi - lo < NARROWEST {
            break;
        }
        let mid = next_trial((lo, lo_m), (hi, hi_m), aim, slope);
        let trial = evaluate(mid.exp(), 1.0);
        let m = trial.1.as_ref().ok().map(|(_, r)| metric(r));
        match keep(trial, &mut best) {
            // A failed reconstruction counts as too coarse.
            None => (hi, hi_m) = (mid, None),
            Some(ok) if ok == fine_feasible => (lo, lo_m) = (mid, m),
            Some(_) => {
                if let (true, Some(coarser), Some(m)) = (fine_feasible, hi_m, m) {
                    floor = (m - coarser).abs() < FLOOR_GAIN;
                }
                (hi, hi_m) = (mid, m);
                if floor {
                    break;
                }
            }
        }
    }
    // A target the RMS jumps across: coarser curve tolerances alone, at
    // the chosen coarseness, up to the coarsest trial's.
    if let (true, Some(((c, _), ..))) = (fine_feasible, &best) {
        let c = *c;
        let (mut lo, mut hi) = (0.0, (options.max_coarseness / c).max(1.0).ln());
        for _ in 0..options.steps {
            if done(&best) || hi - lo < NARROWEST {
                break;
            }
            let mid = 0.5 * (lo + hi);
            match keep(evaluate(c, mid.exp()), &mut best) {
                Some(true) => lo = mid,
                _ => hi = mid,
            }
        }
    }
    // Nothing feasible in the bracket: try its far end once (unless the
    // RMS stopped falling before it).
    if best.is_none() && !floor {
        let end = if fine_feasible {
            options.min_coarseness
        } else {
            options.max_coarseness
        };
        keep(evaluate(end, 1.0), &mut best);
    }
    outcome(best, any, first_error, goal, trials)
}

/// The search's answer: the best feasible model (`best`), else the
/// fallback (`any`) marked not met, an error for a budget no model meets,
/// or the first trial's error when none was built.
fn outcome(
    best: Option<Kept>,
    any: Option<Kept>,
    first_error: Option<ReconstructError>,
    goal: Goal,
    trials: Vec<Trial>,
) -> Result<RateOutcome, RateError> {
    let met = best.is_some();
    let Some(((coarseness, tolerance), body, report)) = best.or(any) else {
        return Err(first_error.map_or(
            RateError::BadGoal("no trial ran".to_string()),
            RateError::Reconstruct,
        ));
    };
    if let (false, Goal::MaxParameters(budget)) = (met, goal) {
        return Err(RateError::Budget {
            budget,
            fewest: report.design_parameters,
        });
    }
    Ok(RateOutcome {
        body,
        report,
        coarseness,
        tolerance,
        met,
        trials,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_next_trial_follows_the_measured_line_inside_the_bracket() {
        // Both ends measured: the line through them reaches the aim at
        // three quarters of the bracket.
        let x = next_trial((0.0, Some(0.0)), (2.0, Some(1.0)), 0.75, 1.0 / 3.0);
        assert!((x - 1.5).abs() < 1e-12, "{x}");
        // One end measured: along the usual slope from it.
        let x = next_trial((0.0, Some(0.0)), (3.0, None), 0.5, 1.0 / 3.0);
        assert!((x - 1.5).abs() < 1e-12, "{x}");
        let x = next_trial((-1.0, None), (0.0, Some(1.0)), 0.9, 1.0 / 3.0);
        assert!((x + 0.3).abs() < 1e-12, "{x}");
        // A guess beyond the bracket stays a tenth inside it; nothing
        // measured: the middle.
        let x = next_trial((0.0, Some(0.0)), (1.0, None), 5.0, 1.0 / 3.0);
        assert!((x - 0.9).abs() < 1e-12, "{x}");
        assert_eq!(next_trial((0.0, None), (1.0, None), 0.3, 1.0), 0.5);
    }
}
