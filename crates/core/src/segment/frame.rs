//! The body's frame (module docs, step 6): heights above the floor, the
//! front from the feet, and what the landmark stages share.

use crate::anatomy::{BodyGeometry, Landmark};
use crate::geom::math::{Point3, Real, Vec3};
use crate::segment::branches::Trunk;
use crate::segment::geodesic::Surface;
use crate::segment::graph::Graph;
use crate::segment::{PartAxis, SegmentError, SegmentOptions};
use std::sync::OnceLock;

/// Heights along `up` above the floor (the low end of the sliced range),
/// for `n` slices `step` apart over the body's height `extent`.
pub(super) struct Levels {
    pub(super) n: usize,
    pub(super) up: Vec3,
    pub(super) floor: Real,
    pub(super) extent: Real,
    pub(super) step: Real,
}

impl Levels {
    /// The height above the soles of slice `slice`: slice k sits at
    /// (k + ½) step.
    pub(super) fn height_of(&self, slice: usize) -> Real {
        (slice as Real + 0.5) * self.step
    }

    /// A point's height above the floor (`p·up − floor`) as a fraction of
    /// the body's height.
    pub(super) fn hfrac(&self, p: Point3) -> Real {
        (p.dot(self.up) - self.floor) / self.extent
    }

    /// `p` moved along `up` to height `h` above the floor.
    pub(super) fn at_height(&self, p: Point3, h: Real) -> Point3 {
        p + self.up * (self.floor + h - p.dot(self.up))
    }
}

/// The direction the body faces: `given` made horizontal, else from the
/// feet and, when they disagree, the hips (module docs, step 6).
pub(super) fn find_front(
    g: &Graph,
    trunk: &Trunk,
    lv: &Levels,
    given: Option<Vec3>,
    warnings: &mut Vec<String>,
) -> Result<Vec3, SegmentError> {
    let (up, n, extent) = (lv.up, lv.n, lv.extent);
    if let Some(f) = given {
        return (f - up * f.dot(up))
            .normalized()
            .ok_or(SegmentError::BadOption {
                name: "front",
                why: "must be finite, non-zero and not parallel to up",
            });
    }
    // Per leg: the area centroid of its foot's loops 1-3 % of the
    // height above the floor minus that of its loops 6-9 % above
    // it; the two legs' unit directions are averaged (one leg at a
    // time, so a slightly tilted axis that cuts one foot lower than
    // the other does not pull the answer sideways). A foot's loops
    // are every loop at those heights nearer (across `up`) to its
    // leg than to the other leg, not only its own branch: a scan
    // that sees a foot's top but not its sole shows heel and toes
    // as separate loops near the floor, and the heel's branch
    // alone pointed the body backwards.
    let band = |nodes: &[usize], lo: Real, hi: Real| {
        let (mut s, mut w) = (Vec3::ZERO, 0.0);
        for &a in nodes {
            let f = (g.nodes[a].slice as Real + 0.5) / n as Real;
            if f >= lo && f < hi {
                s += g.nodes[a].centroid * g.nodes[a].area;
                w += g.nodes[a].area;
            }
        }
        (w > 0.0).then(|| s / w)
    };
    let all: Vec<usize> = (0..g.nodes.len()).collect();
    let across = |p: Point3| p - up * p.dot(up);
    let refs = [&trunk.leg_chains[0], &trunk.leg_chains[1]].map(|c| {
        let nodes = g.chain_nodes(c);
        band(&nodes, 0.06, 0.09).or_else(|| nodes.first().map(|&a| g.nodes[a].centroid))
    });
    let leg_dir = |mine: usize| {
        let (Some(me), Some(other)) = (refs[mine], refs[1 - mine]) else {
            return Vec3::ZERO;
        };
        let foot: Vec<usize> = all
            .iter()
            .copied()
            .filter(|&a| {
                let c = across(g.nodes[a].centroid);
                (c - across(me)).norm() < (c - across(other)).norm()
            })
            .collect();
        match (band(&foot, 0.01, 0.03), band(&foot, 0.06, 0.09)) {
            (Some(a), Some(b)) => {
                let d = a - b;
                d - up * d.dot(up)
            }
            _ => Vec3::ZERO,
        }
    };
    // Feet that agree (within 60°) give the front as the mean of their
    // unit directions. Feet that disagree (one lifted, bent back, turned
    // out) give only its sign: the front is then square to the line through
    // the legs' top loops, side by side below the crotch in any standing
    // pose, towards the feet's sum (a foot on the floor outweighs a lifted
    // one).
    let (da, db) = (leg_dir(0), leg_dir(1));
    let (ua, ub) = (da.normalized(), db.normalized());
    let agree = matches!((ua, ub), (Some(a), Some(b)) if a.dot(b) >= 0.5);
    let top_of = |c: &[usize]| g.chain_nodes(c).last().map(|&a| g.nodes[a].centroid);
    let hips = match (top_of(&trunk.leg_chains[0]), top_of(&trunk.leg_chains[1])) {
        (Some(a), Some(b)) => across(a - b).normalized(),
        _ => None,
    };
    let dir = match hips {
        Some(h) if !agree => {
            let f = up.cross(h);
            f * (0.5 * (da + db).dot(f))
        }
        _ => {
            (ua.unwrap_or(Vec3::ZERO) + ub.unwrap_or(Vec3::ZERO)) * (0.25 * (da.norm() + db.norm()))
        }
    };
    if dir.norm() < 0.005 * extent {
        warnings.push(format!(
                "front direction weakly determined: the feet reach only {:.2} % of the height in front of the ankles",
                100.0 * dir.norm() / extent
            ));
    }
    Ok(dir.normalized().unwrap_or_else(|| up.any_perpendicular()))
}

/// What the landmark and axis stages share: the input, the slice graph
/// and the body's frame.
pub(super) struct Landmarking<'a> {
    pub(super) body: BodyGeometry<'a>,
    pub(super) opts: &'a SegmentOptions,
    /// A cloud's point spacing (`None` for a mesh).
    pub(super) spacing: Option<Real>,
    pub(super) g: &'a Graph,
    pub(super) lv: Levels,
    /// The slices' plane coordinates.
    pub(super) e1: Vec3,
    pub(super) e2: Vec3,
    pub(super) front: Vec3,
    pub(super) left: Vec3,
    /// A mesh's surface walked from the crotch, once an arm is looked for
    /// on it.
    pub(super) surface: OnceLock<Option<Surface<'a>>>,
}

/// What the stages have found so far, in the order they found it.
#[derive(Default)]
pub(super) struct Found {
    pub(super) landmarks: Vec<Landmark>,
    pub(super) parts: Vec<PartAxis>,
    pub(super) warnings: Vec<String>,
}
