//! The head's, arms' and legs' section plans: where each is cut, and how
//! its end (a dome to the crown, the hand's tip or the sole) is found.

use super::*;

/// What the head's, arms' and legs' section plans need: the cutter, the
/// segmentation (legs extended to the floor) and the original one, the
/// options, the floor's height and the level the legs start below.
pub(in crate::body) struct LimbPlans<'a, 'o> {
    pub(in crate::body) cutter: &'a Cutter<'a>,
    pub(in crate::body) seg: &'a Segmentation,
    pub(in crate::body) seg0: &'a Segmentation,
    pub(in crate::body) opts: &'o ReconstructOptions,
    pub(in crate::body) floor: Real,
    pub(in crate::body) leg_top: Real,
}

impl<'a> LimbPlans<'a, '_> {
    /// Every part with an axis but the torso and the feet (the legs cover
    /// them with shoe ends), in [`PartName::ALL`]'s order, and whether the
    /// segmentation has a torso to plan after them.
    pub(in crate::body) fn parts(
        &self,
        warnings: &mut Vec<String>,
    ) -> (Vec<(PartName, &'a PartAxis)>, bool) {
        let mut parts = Vec::new();
        let mut with_torso = false;
        let feet = [PartName::LeftFoot, PartName::RightFoot];
        for name in PartName::ALL.into_iter().filter(|n| !feet.contains(n)) {
            let Some(axis) = self.seg.part(name) else {
                warnings.push(format!("{name} not found: left out of the model"));
                continue;
            };
            if !(axis.length() > 0.0) {
                warnings.push(format!("{name}: axis of zero length, left out"));
                continue;
            }
            if name == PartName::Torso {
                with_torso = true;
            } else {
                parts.push((name, axis));
            }
        }
        (parts, with_torso)
    }

    /// The plan of one of [`LimbPlans::parts`], and an arm's hand's split
    /// where its digits are parts of their own ([`split_hand`]).
    pub(in crate::body) fn plan(
        &self,
        name: PartName,
        axis: &PartAxis,
        warnings: &mut Vec<String>,
    ) -> (Plan, Option<HandSplit>) {
        let step = self.opts.spacing * self.seg.height / axis.length();
        match name {
            PartName::Head => (self.head(axis, step, warnings), None),
            PartName::LeftArm | PartName::RightArm => self.arm(name, axis, step, warnings),
            _ => (self.leg(name, axis, step, warnings), None),
        }
    }

    /// The head: from the neck to a rounded top closed by a dome.
    fn head(&self, axis: &PartAxis, step: Real, warnings: &mut Vec<String>) -> Plan {
        let name = PartName::Head;
        let mut cuts = cut_to_rounded_end(
            self.cutter,
            name,
            RoundedEnd {
                t0: 0.0,
                until: 1.0,
                watch_from: 0.5,
                step,
                against: EndArea::Largest,
                within_last: true,
            },
            self.opts,
            warnings,
        );
        let mut tip = axis.points.last().copied();
        let crown = unseen_crown(&cuts, self.cutter.body().positions(), self.seg.frame.up);
        if let Some(c) = crown {
            warnings.push(format!(
                "{name}: the input ends in an open rim {:.0} mm across above the head (its crown unseen): the crown is estimated from the head's shape, {:.0} mm above the rim; {} section(s) at the rim dropped",
                2.0 * c.rim_radius * self.opts.units.to_mm(),
                c.rise * self.opts.units.to_mm(),
                cuts.len() - c.keep,
            ));
            cuts.truncate(c.keep);
            tip = Some(c.tip);
        }
        Plan {
            name,
            cuts,
            start_cap: CapKind::Open,
            end_cap: CapKind::dome(),
            tip,
            end_unchecked: crown.is_some(),
            shoulders: Shoulders::default(),
        }
    }

    /// An arm: evenly to the wrist, finely over the hand to a dome.
    fn arm(
        &self,
        name: PartName,
        axis: &PartAxis,
        step: Real,
        warnings: &mut Vec<String>,
    ) -> (Plan, Option<HandSplit>) {
        let (opts, h, len) = (self.opts, self.seg.height, axis.length());
        let wrist_kind = if name == PartName::LeftArm {
            LandmarkKind::LeftWrist
        } else {
            LandmarkKind::RightWrist
        };
        let wrist = landmark(self.seg, wrist_kind)
            .map(|w| fraction_of(axis, w))
            .unwrap_or(0.8);
        let fine = (0.5 * step).max(0.25 * opts.foot_spacing * h / len);
        let mut cuts = cut_all(
            self.cutter,
            name,
            &fractions(0.0, wrist, step),
            opts,
            Shoulders::default(),
            warnings,
        );
        // The wrist itself starts the hand's run.
        cuts.pop();
        // The arm starts where its loops leave the trunk.
        if let Some(torso) = self.seg.part(PartName::Torso) {
            let k = cuts.iter().take_while(|c| holds_axis(c, torso)).count();
            drop_first(
                &mut cuts,
                k,
                name,
                "their loops hold the torso's axis",
                warnings,
            );
        }
        // Nor, on a scan, where its loop takes in some of the trunk: a
        // first loop much larger than the next ones' (the slab's image at
        // the shoulder closed across the armpit onto the chest). A mesh's
        // loops are exact, and an arm pressed to its side legitimately
        // widens there (body_027 lost 1.2 mm to this rule); but first
        // loops cut off from the rest by planes that meet no loop of the
        // arm are not its tube (a shoulder cut lengthwise where the axis
        // leaves the trunk sideways): those go when larger than the loops
        // past the gap by the same third.
        let k = match self.cutter.body() {
            BodyGeometry::Cloud(_) => (0..cuts.len())
                .take_while(|&i| takes_in_trunk(&cuts[i], &cuts[i + 1..]))
                .count(),
            BodyGeometry::Mesh(_) => cuts
                .windows(2)
                .position(|w| w[1].at - w[0].at > 1.5 * step)
                .filter(|&g| (0..=g).all(|i| takes_in_trunk(&cuts[i], &cuts[g + 1..])))
                .map_or(0, |g| g + 1),
        };
        let why = "their loops take in the trunk: larger than the next ones' by over a third";
        drop_first(&mut cuts, k, name, why, warnings);
        // A scan's slab past the palm merges the fingers, the thumb and the
        // scanner's gaps into blobs whose sections fold: its hand ends
        // where the loop falls under the palm with its thumb.
        let against = match self.cutter.body() {
            BodyGeometry::Mesh(_) => EndArea::First,
            BodyGeometry::Cloud(_) => EndArea::Largest,
        };
        // Fingers apart are digits of their own ([`split_hand`]): the
        // palm's run stops where the last one parts, its end flat and not
        // checked against the input (the digits go on). A mesh's fingers
        // that touch are loops of their own past the knuckles only here
        // and there: the run takes them inside the palm's outline (a
        // mitten), with a warning. A scan's slab there is one blob
        // already, and taking the loops inside the last one changed no
        // corpus scan's hand for the better.
        let split = split_hand(self.cutter, name, wrist, opts)
            .map_err(|why| warnings.push(format!("{name}: the hand is a mitten ({why})")))
            .ok();
        // A palm whose digits were found ends where they part: its loops
        // are not watched for the end (a scan's palm, held against its
        // largest loop with the thumb, would end where the thumb leaves).
        let hand = RoundedEnd {
            t0: wrist,
            until: split.as_ref().map_or(1.0, |s| s.palm_end),
            watch_from: split.as_ref().map_or(wrist, |s| s.palm_end),
            step: fine,
            against,
            within_last: against == EndArea::First,
        };
        cuts.extend(cut_to_rounded_end(self.cutter, name, hand, opts, warnings));
        let (end_cap, tip) = match split {
            Some(_) => (CapKind::Flat, None),
            None => (CapKind::dome(), axis.points.last().copied()),
        };
        let plan = Plan {
            name,
            cuts,
            start_cap: CapKind::Open,
            end_cap,
            tip,
            end_unchecked: split.is_some(),
            shoulders: Shoulders::default(),
        };
        (plan, split)
    }

    /// A leg: evenly to the ankle, finely below it to the sole.
    fn leg(&self, name: PartName, axis: &PartAxis, step: Real, warnings: &mut Vec<String>) -> Plan {
        let (opts, h, len, up) = (self.opts, self.seg.height, axis.length(), self.seg.frame.up);
        let ankle_kind = if name == PartName::LeftLeg {
            LandmarkKind::LeftAnkle
        } else {
            LandmarkKind::RightAnkle
        };
        let orig = self.seg0.part(name).map(PartAxis::length).unwrap_or(len);
        let ankle = landmark(self.seg, ankle_kind)
            .map(|a| fraction_of(axis, a))
            .unwrap_or(orig / len)
            .min(orig / len);
        let t0 = fraction_at_level(axis, up, self.leg_top, false);
        let upper = (ankle - 0.02 * h / len).max(t0);
        let mut cuts = cut_all(
            self.cutter,
            name,
            &fractions(t0, upper, step),
            opts,
            Shoulders::default(),
            warnings,
        );
        cuts.pop();
        // Below the ankle: horizontal outlines of the foot until they
        // shrink where the sole curves up (heel, toes).
        let foot = ReconstructOptions {
            end_area_fraction: opts.sole_area_fraction,
            ..*opts
        };
        let outlines = RoundedEnd {
            t0: upper,
            until: 1.0,
            watch_from: ankle,
            step: opts.foot_spacing * h / len,
            against: EndArea::Largest,
            within_last: true,
        };
        cuts.extend(cut_to_rounded_end(
            self.cutter,
            name,
            outlines,
            &foot,
            warnings,
        ));
        // The sole: a shallow dome from the last outline down to the foot's
        // own bottom below its centre (a foot lifted off the floor, a bent
        // knee's, ends above it), along the outline's normal: the outlines'
        // centres shift from heel to toe, so the end tangent leans forward
        // or back and a dome along it runs sideways, not down.
        let sole = cuts.last().map(|c| {
            let o = c.fit.curve.frame.origin;
            let level = sole_level(self.cutter.body(), &c.fit.curve, up, self.floor);
            o - up * (o.dot(up) - level)
        });
        Plan {
            name,
            cuts,
            start_cap: CapKind::Open,
            end_cap: CapKind::Dome {
                relative_height: 0.0,
                fullness: 1.0,
                axis: DomeAxis::Normal,
            },
            tip: sole,
            end_unchecked: false,
            shoulders: Shoulders::default(),
        }
    }
}

/// Drops an arm's first `k` cuts, with a warning saying `why`, unless
/// that is none or half of them or more (then the rule, not the arm, is
/// wrong).
fn drop_first(
    cuts: &mut Vec<Cut>,
    k: usize,
    name: PartName,
    why: &str,
    warnings: &mut Vec<String>,
) {
    if k > 0 && k < cuts.len() / 2 {
        warnings.push(format!("{name}: first {k} section(s) dropped ({why})"));
        cuts.drain(..k);
    }
}
