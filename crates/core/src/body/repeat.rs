//! Several reconstructions of one input that differ only in their
//! tolerances (the rate search's trials, `rate.rs`): the input is put in
//! its own frame, cleaned or closed, and segmented once, and the cutter's
//! slicers and the input's distance structure are built once, where each
//! [`reconstruct`] would do it again.
//!
//! A scan's frames ([`ReconstructOptions::scan_frames`]) are compared
//! once, at the base options, and every other trial is made in the frame
//! chosen there: one reconstruction a trial instead of one a frame, and
//! the trials differ in their tolerances only, not in a frame picked anew.

use super::frames::{best_of_frames, turned_back, turned_options};
use super::pose::{own_frame, Prepared};
use super::*;

/// A reconstruction at given options, as [`reconstruct`] gives it.
pub(crate) type Run<'r> =
    dyn FnMut(&ReconstructOptions) -> Result<(Body, Report), ReconstructError> + 'r;

/// Whether `o` differs from `base` in nothing but the curve, pruning and
/// refinement tolerances.
fn tolerances_only(o: &ReconstructOptions, base: &ReconstructOptions) -> bool {
    let mut a = *o;
    a.fit.ea = base.fit.ea;
    a.fit.em = base.fit.em;
    a.prune_tolerance = base.prune_tolerance;
    a.refine_tolerance = base.refine_tolerance;
    a == *base
}

/// Calls `search` with a [`Run`] for `body`: at options that differ from
/// `base` only in their tolerances ([`tolerances_only`]) it reuses what
/// the input's preparation and segmentation made (see the module's
/// notes); at any other options, or when that preparation fails, it is
/// [`reconstruct`] itself, so that every error comes from the trial that
/// meets it.
pub(crate) fn reconstruct_each<R>(
    body: BodyGeometry<'_>,
    base: &ReconstructOptions,
    search: impl FnOnce(&mut Run<'_>) -> R,
) -> R {
    let mut fresh = |o: &ReconstructOptions| reconstruct(body, o);
    if check_options(base).is_err() {
        return search(&mut fresh);
    }
    // The input is checked once, here, not at every trial; the unit found
    // (given or inferred) holds for all of them.
    let Ok(checked) = checked_input(body, base) else {
        return search(&mut fresh);
    };
    let with_unit = |o: &ReconstructOptions| ReconstructOptions {
        units: checked.units,
        ..*o
    };
    let base_in_unit = &checked;
    let own = match own_frame(body, base_in_unit) {
        Ok(own) => Some(own),
        Err(_) => return search(&mut fresh),
    };
    let into = own.as_ref().map(|o| &o.1);
    let (prepared, own_base) = Prepared::in_own_frame(body, own.as_ref(), base_in_unit);
    // A scan's frame, chosen at the base options.
    let mut first = None;
    let mut frame = (0.0, None);
    let mut frames_compared = false;
    if let BodyGeometry::Cloud(cloud) = prepared.geometry() {
        if own_base.scan_frames > 1 {
            match best_of_frames(cloud, &own_base, &mut |_| {}) {
                Ok((result, chosen)) => {
                    first = Some(result);
                    frame = chosen;
                    frames_compared = true;
                }
                Err(_) => return search(&mut fresh),
            }
        }
    }
    let (angle, turn) = frame;
    let turned = match (&turn, prepared.geometry()) {
        (Some(t), BodyGeometry::Cloud(c)) => Some(t.cloud(c)),
        _ => None,
    };
    let geometry = turned
        .as_ref()
        .map_or(prepared.geometry(), BodyGeometry::Cloud);
    let frame_base = turn
        .as_ref()
        .map_or(own_base, |t| turned_options(&own_base, t));
    let Ok(segmented) = Segmented::of(geometry, &frame_base, &mut |_| {}) else {
        return search(&mut fresh);
    };
    let groundwork = Groundwork::new(&segmented);
    let mut run = |o: &ReconstructOptions| {
        check_options(o)?;
        let o = &with_unit(o);
        if !tolerances_only(o, base_in_unit) {
            return reconstruct_checked(body, o, &mut |_| {});
        }
        if o == base_in_unit {
            if let Some(result) = first.take() {
                return finished(result, &prepared, into, o);
            }
        }
        let mut at = frame_base;
        at.fit = o.fit;
        at.prune_tolerance = o.prune_tolerance;
        at.refine_tolerance = o.refine_tolerance;
        let mut result = build(&groundwork, &at, &mut |_| {})?;
        if let Some(t) = &turn {
            result = turned_back(result, &t.inverse())?;
        }
        if frames_compared {
            result.1.warnings.push(format!(
                "the scan's {angle:.0}° frame, chosen among {} at the first reconstruction, is kept",
                own_base.scan_frames
            ));
        }
        finished(result, &prepared, into, o)
    };
    search(&mut run)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes::stick_body;
    use crate::{virtual_scan, ScannerOptions};

    fn coarse(base: &ReconstructOptions, c: Real) -> ReconstructOptions {
        let mut o = *base;
        o.fit.ea *= c;
        o.fit.em *= c;
        o.prune_tolerance *= c;
        o.refine_tolerance *= c;
        o
    }

    #[test]
    fn a_mesh_is_reconstructed_as_reconstruct_does_at_any_options() {
        let mesh = stick_body(2);
        let body = BodyGeometry::Mesh(&mesh);
        let base = ReconstructOptions::default();
        let mut spacing = base;
        spacing.spacing *= 1.5;
        let asked = [base, coarse(&base, 3.0), spacing, coarse(&base, 0.5), base];
        let each = reconstruct_each(body, &base, |run| asked.map(|o| run(&o).expect("a model")));
        for (o, got) in asked.iter().zip(each) {
            let want = reconstruct(body, o).expect("a model");
            assert_eq!(got, want);
        }
        // Bad options are the error reconstruct gives.
        let mut bad = base;
        bad.fit.ea = -1.0;
        let e = reconstruct_each(body, &base, |run| run(&bad).map(|_| ()));
        assert_eq!(
            e.unwrap_err().to_string(),
            reconstruct(body, &bad).unwrap_err().to_string()
        );
    }

    #[test]
    fn a_scan_keeps_the_frame_its_first_reconstruction_chose() {
        let scan = virtual_scan(&stick_body(2), &ScannerOptions::default()).expect("a scan");
        let body = BodyGeometry::Cloud(&scan.cloud);
        let base = ReconstructOptions::default();
        let (first, later) = reconstruct_each(body, &base, |run| {
            (
                run(&base).expect("a model"),
                run(&coarse(&base, 2.0)).expect("a model"),
            )
        });
        assert_eq!(first, reconstruct(body, &base).expect("a model"));
        // The later trial is made in one frame and says which.
        assert!(
            later
                .1
                .warnings
                .iter()
                .any(|w| w.contains("frame, chosen among")),
            "{:?}",
            later.1.warnings
        );
        assert!(later.0.design_parameters() < first.0.design_parameters());
    }
}
