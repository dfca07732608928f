//! A scan reconstructed in a few frames, the model nearest its input kept.
//!
//! A scan's segmentation and sections turn on the cells of its slab images
//! and grids, so the same scan turned a little can give a different model
//! (a section dropped, an arm's end or a junction chosen otherwise), and
//! now and then a much worse one. Reconstructing it in its own frame and
//! turned about its up axis by [`FRAME_STEP`] steps, and keeping the model whose
//! distance to the input (the report's two-way RMS, what a user measures)
//! is clearly least ([`CLEAR_GAIN`]), picks the good outcome: on the
//! corpus scans the pick by that distance was the one nearest the truth
//! mesh as well.

use super::*;
use crate::geom::rigid::Rigid;

/// The turn between two frames, about the up axis (less than the quarter
/// turn that maps an axis-aligned grid onto itself).
pub(super) const FRAME_STEP: Real = 15.0;

/// A turned frame's model replaces the unturned one only when its RMS is
/// lower by more than this fraction: nearly equal distances do not say
/// which model is better (on body_010_scan 3.56 against 3.59 mm picked a
/// frame whose ankle lay 50 mm off), and the unturned frame is the one a
/// user can reproduce with `--scan-frames 1`.
pub(super) const CLEAR_GAIN: Real = 0.02;

/// A frame of a scan: its turn about the up axis in degrees and the
/// motion that turns the cloud into it (`None` for the unturned frame).
pub(super) type Frame = (Real, Option<Rigid>);

/// The best of [`ReconstructOptions::scan_frames`] reconstructions of
/// `cloud` (already cleaned), turned back into the cloud's frame, with a
/// warning naming each frame's distance, and the frame chosen; the first
/// frame's error when every frame fails.
pub(super) fn best_of_frames(
    cloud: &PointCloud,
    opts: &ReconstructOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<((Body, Report), Frame), ReconstructError> {
    // The cloud is in its own frame (`pose::own_pose_cloud`), whose +y is
    // the principal axis nearest its up: the frames are turned about it,
    // not about the up its segmentation finds (which jitters by a fraction
    // of a degree with the slab images' pixels). The turned frames are
    // reconstructed on the other cores while the first one reports its
    // progress here.
    let segmented = Segmented::of(BodyGeometry::Cloud(cloud), opts, progress);
    let n = cloud.positions.len().max(1) as Real;
    let centre = cloud.positions.iter().fold(Vec3::ZERO, |a, &p| a + p) / n;
    let turns: Vec<(Real, Rigid)> = (1..opts.scan_frames)
        .map_while(|k| {
            let angle = k as Real * FRAME_STEP;
            let turn = Rigid::turn_about(centre, Vec3::Y, angle.to_radians())?;
            Some((angle, turn))
        })
        .collect();
    let mut turned: Vec<Option<Result<(Body, Report), ReconstructError>>> =
        turns.iter().map(|_| None).collect();
    let first = rayon::in_place_scope(|scope| {
        for (slot, (_, turn)) in turned.iter_mut().zip(&turns) {
            scope.spawn(move |_| {
                let moved = turn.cloud(cloud);
                let o = turned_options(opts, turn);
                *slot = Some(
                    reconstruct_steps(BodyGeometry::Cloud(&moved), &o, &mut |_| {})
                        .and_then(|r| turned_back(r, &turn.inverse())),
                );
            });
        }
        segmented.and_then(|s| build(&Groundwork::new(&s), opts, progress))
    });
    // Every spawned frame has run when the scope ends.
    let mut tries = vec![(0.0, first)];
    let mut frames = vec![None];
    for ((angle, turn), result) in turns.into_iter().zip(turned.into_iter().flatten()) {
        tries.push((angle, result));
        frames.push(Some(turn));
    }
    let rms = |t: &(Real, Result<(Body, Report), ReconstructError>)| {
        t.1.as_ref()
            .map_or(Real::INFINITY, |(_, r)| r.distance_mm.rms)
    };
    let summary: Vec<String> = tries
        .iter()
        .map(|t| match &t.1 {
            Ok(_) => format!("{:.0}°: {:.2} mm", t.0, rms(t)),
            Err(_) => format!("{:.0}°: failed", t.0),
        })
        .collect();
    let best = (0..tries.len())
        .min_by(|&a, &b| rms(&tries[a]).total_cmp(&rms(&tries[b])))
        .unwrap_or(0);
    let clear = rms(&tries[best]) < (1.0 - CLEAR_GAIN) * rms(&tries[0]);
    let chosen = if tries[best].1.is_ok() && clear {
        best
    } else {
        0
    };
    let (angle, result) = tries.swap_remove(chosen);
    let turn = frames.swap_remove(chosen);
    let (body, mut report) = result?;
    if summary.len() > 1 {
        report.warnings.push(format!(
            "the scan was reconstructed in {} frames turned about its up axis ({}); the {angle:.0}° frame's model is kept (a turned frame's only when over {:.0} % nearer the scan)",
            summary.len(),
            summary.join(", "),
            100.0 * CLEAR_GAIN
        ));
    }
    Ok(((body, report), (angle, turn)))
}

/// `opts` for a cloud moved by `turn`: a given up and front turned with it.
pub(super) fn turned_options(opts: &ReconstructOptions, turn: &Rigid) -> ReconstructOptions {
    let mut o = *opts;
    o.segment.up = opts.segment.up.map(|u| turn.vector(u));
    o.segment.front = opts.segment.front.map(|f| turn.vector(f));
    o
}

/// A model and its report's joints moved by `back`.
pub(super) fn turned_back(
    (body, mut report): (Body, Report),
    back: &Rigid,
) -> Result<(Body, Report), ReconstructError> {
    for (_, p) in report.joints.iter_mut() {
        *p = back.point(*p);
    }
    Ok((body.moved(back)?, report))
}
