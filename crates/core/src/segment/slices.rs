//! Slicing along one axis, for meshes and clouds alike: each section's
//! loops as nodes of the slice graph (module docs, step 2).

use crate::anatomy::BodyGeometry;
use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::section::cloud::grid::Grid;
use crate::section::cloud::{CloudSlicer, ScanSectionOptions};
use crate::section::girth::convex_hull;
use crate::section::mesh::{polygon_area_centroid, MeshSlicer, SectionLoop};
use crate::segment::graph::Node;
use crate::segment::{HeightSort, SegmentError, SegmentOptions};

/// Sections normal to one axis, from a mesh or a cloud, as graph nodes.
pub(super) enum AxisSlicer<'a> {
    Mesh(MeshSlicer<'a>),
    Cloud(SlabComponents),
}

impl<'a> AxisSlicer<'a> {
    /// `spacing`: a cloud's point spacing when already known.
    pub(super) fn new(
        body: BodyGeometry<'a>,
        axis: Vec3,
        opts: &SegmentOptions,
        spacing: Option<Real>,
    ) -> Result<AxisSlicer<'a>, SegmentError> {
        Ok(match body {
            BodyGeometry::Mesh(m) => AxisSlicer::Mesh(MeshSlicer::new(m, axis, &opts.section)?),
            BodyGeometry::Cloud(c) => {
                // The spacing estimate of the scan sections, so that both
                // agree on what a cell is.
                let spacing = match spacing {
                    Some(s) => s,
                    None => CloudSlicer::new(c, axis)?.spacing(),
                };
                let graph = ScanSectionOptions {
                    cell_size: Some(opts.scan.cell_size.unwrap_or(spacing) * opts.graph_cell),
                    closing_radius: opts.graph_closing,
                    ..opts.scan
                };
                AxisSlicer::Cloud(SlabComponents::new(&c.positions, axis, spacing, &graph)?)
            }
        })
    }

    /// [`AxisSlicer::new`] with the spacing estimated here, and for a
    /// cloud the estimate's sort by height (indices and heights,
    /// [`CloudSlicer`]'s) with the unit axis of those heights.
    pub(super) fn new_sorted(
        body: BodyGeometry<'a>,
        axis: Vec3,
        opts: &SegmentOptions,
    ) -> Result<(AxisSlicer<'a>, Option<(Vec3, HeightSort)>), SegmentError> {
        match body {
            BodyGeometry::Mesh(_) => Ok((AxisSlicer::new(body, axis, opts, None)?, None)),
            BodyGeometry::Cloud(c) => {
                let cloud = CloudSlicer::new(c, axis)?;
                let mut slicer = AxisSlicer::new(body, axis, opts, Some(cloud.spacing()))?;
                if let AxisSlicer::Cloud(s) = &mut slicer {
                    s.noise = Some(cloud.noise());
                }
                Ok((slicer, Some((cloud.axis(), cloud.into_sorted()))))
            }
        }
    }

    pub(super) fn range(&self) -> (Real, Real) {
        match self {
            AxisSlicer::Mesh(s) => s.range(),
            AxisSlicer::Cloud(s) => s.range(),
        }
    }

    pub(super) fn spacing(&self) -> Option<Real> {
        match self {
            AxisSlicer::Mesh(_) => None,
            AxisSlicer::Cloud(s) => Some(s.spacing),
        }
    }

    pub(super) fn noise(&self) -> Option<Real> {
        match self {
            AxisSlicer::Mesh(_) => None,
            AxisSlicer::Cloud(s) => s.noise,
        }
    }

    /// The section's loops at `offset` as nodes (slice index 0, set by the
    /// caller); none where the plane misses or the slab is too thin. A
    /// mesh's loop nested in another (a pocket of skin inside a part, such
    /// as a modelled mouth) is no branch of the body: left out.
    pub(super) fn nodes_at(&self, offset: Real, e1: Vec3, e2: Vec3) -> Vec<Node> {
        match self {
            AxisSlicer::Mesh(s) => s
                .section_at(offset)
                .map(|s| {
                    let nested = |l: &SectionLoop| {
                        s.loops
                            .iter()
                            .any(|o| o.area > l.area && o.contains(l.centroid))
                    };
                    s.loops
                        .iter()
                        .filter(|l| !nested(l))
                        .map(|l| Node::new(0, l, e1, e2))
                        .collect()
                })
                .unwrap_or_default(),
            AxisSlicer::Cloud(s) => s.nodes_at(offset, e1, e2),
        }
    }
}

/// Slabs of a point cloud reduced to what the slice graph needs: the
/// connected components of each slab's occupancy image (the construction
/// of [`CloudSlicer`]: cells of the point spacing, a morphological closing,
/// 8-connected components) with their filled area, area centroid and the
/// convex hull of their points. Ordering the points along each loop (what
/// the curve fit needs, and most of [`CloudSlicer::section_at`]'s time) is
/// skipped: the graph only asks where a part is and how big.
#[derive(Debug)]
pub(super) struct SlabComponents {
    axis: Vec3,
    /// Points and heights in bin order (sorted by bin, not within a bin).
    points: Vec<Point3>,
    heights: Vec<Real>,
    /// Bin `b` holds `points[bin_start[b]..bin_start[b + 1]]`.
    bin_start: Vec<usize>,
    bin_low: Real,
    bin_width: Real,
    range: (Real, Real),
    spacing: Real,
    /// The cloud's noise, when the slicer that estimated the spacing was
    /// built here ([`AxisSlicer::new_sorted`]).
    noise: Option<Real>,
    half_thickness: Real,
    cell: Real,
    closing: usize,
    min_points: usize,
    max_cells: usize,
}

impl SlabComponents {
    pub(super) fn new(
        points: &[Point3],
        axis: Vec3,
        spacing: Real,
        o: &ScanSectionOptions,
    ) -> Result<SlabComponents, SegmentError> {
        let axis = axis.normalized().ok_or(SegmentError::BadOption {
            name: "up",
            why: "must be a finite non-zero vector",
        })?;
        let len = |v: Option<Real>, name: &'static str| match v {
            None => Ok(spacing),
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            Some(_) => Err(SegmentError::BadOption {
                name,
                why: "must be finite and positive",
            }),
        };
        // Bucket (counting) sort by height into bins of about a quarter
        // of the point spacing: linear time, and a slab is a run of bins
        // (points of its two end bins are checked one by one).
        let heights: Vec<Real> = points.iter().map(|p| p.dot(axis)).collect();
        let (lo, hi) = heights
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), &h| {
                (a.min(h), b.max(h))
            });
        let bins =
            (((hi - lo) / (0.25 * spacing)).ceil() as usize).clamp(1, 4 * points.len().max(1));
        let width = ((hi - lo) / bins as Real).max(Real::MIN_POSITIVE);
        let bin_of = |h: Real| (((h - lo) / width) as usize).min(bins - 1);
        // Each point's bin and the bins' counts, each bin's points'
        // indices (in index order), then the points and heights gathered
        // in that order, side by side on two cores (written in sequence,
        // no zero-filled arrays first).
        let mut start = vec![0usize; bins + 1];
        let bin: Vec<usize> = heights
            .iter()
            .map(|&h| {
                let b = bin_of(h);
                start[b + 1] += 1;
                b
            })
            .collect();
        for b in 0..bins {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; points.len()];
        for (i, &b) in bin.iter().enumerate() {
            order[fill[b]] = i as u32;
            fill[b] += 1;
        }
        let (sorted_points, sorted_heights): (Vec<Point3>, Vec<Real>) = crate::geom::parallel::join(
            || order.iter().map(|&i| points[i as usize]).collect(),
            || order.iter().map(|&i| heights[i as usize]).collect(),
        );
        Ok(SlabComponents {
            axis,
            heights: sorted_heights,
            points: sorted_points,
            bin_start: start,
            bin_low: lo,
            bin_width: width,
            range: (lo, hi),
            spacing,
            noise: None,
            half_thickness: len(o.half_thickness, "scan.half_thickness")?,
            cell: len(o.cell_size, "scan.cell_size")?,
            closing: o.closing_radius,
            min_points: o.min_component_points.max(3),
            max_cells: o.max_cells.max(64),
        })
    }

    fn range(&self) -> (Real, Real) {
        self.range
    }

    fn nodes_at(&self, offset: Real, e1: Vec3, e2: Vec3) -> Vec<Node> {
        let t = self.half_thickness;
        let bins = self.bin_start.len() - 1;
        let bin = |h: Real| ((h - self.bin_low) / self.bin_width).floor();
        let (b0, b1) = (bin(offset - t), bin(offset + t));
        if !(b0.is_finite() && b1.is_finite()) || b1 < 0.0 || b0 >= bins as Real {
            return Vec::new();
        }
        let (b0, b1) = ((b0.max(0.0)) as usize, (b1 as usize).min(bins - 1));
        let range = self.bin_start[b0]..self.bin_start[b1 + 1];
        let pts: Vec<Point2> = range
            .filter(|&i| (self.heights[i] - offset).abs() <= t)
            .map(|i| {
                let p = self.points[i];
                Vec2::new(p.dot(e1), p.dot(e2))
            })
            .collect();
        if pts.len() < self.min_points {
            return Vec::new();
        }
        let (mut min, mut max) = (pts[0], pts[0]);
        for p in &pts {
            min = Vec2::new(min.x.min(p.x), min.y.min(p.y));
            max = Vec2::new(max.x.max(p.x), max.y.max(p.y));
        }
        let r = self.closing;
        let margin = r + 2;
        let mut g = self.cell;
        let dims = |g: Real| {
            (
                ((max.x - min.x) / g + 2.0 * margin as Real).ceil() as usize + 1,
                ((max.y - min.y) / g + 2.0 * margin as Real).ceil() as usize + 1,
            )
        };
        while {
            let (w, h) = dims(g);
            w.saturating_mul(h) > self.max_cells
        } {
            g *= 1.5;
        }
        let (w, h) = dims(g);
        let grid = Grid::below(min, margin, g, w, h);
        let mut img = vec![false; w * h];
        let cells: Vec<usize> = pts.iter().map(|&p| grid.cell(p)).collect();
        for &c in &cells {
            img[c] = true;
        }
        let (label, ncomp) = grid.components(&grid.close(&img, r));
        let mut comp_points: Vec<Vec<Point2>> = vec![Vec::new(); ncomp];
        for (k, &c) in cells.iter().enumerate() {
            if let Some(v) = comp_points.get_mut(label[c] as usize) {
                v.push(pts[k]);
            }
        }
        let mut out = Vec::new();
        for id in 0..ncomp {
            if comp_points[id].len() < self.min_points {
                continue;
            }
            // Area and centroid of the convex hull of the points: a ring
            // broken by a scanner hole has no inside to fill, but its hull
            // is still the section's outline (over-counting only the
            // concavities).
            let hull = convex_hull(&comp_points[id]);
            let Some((area, c2)) = polygon_area_centroid(&hull) else {
                continue;
            };
            let area = area.abs();
            out.push(Node::from_parts(
                0,
                self.axis * offset + e1 * c2.x + e2 * c2.y,
                c2,
                area,
                hull,
            ));
        }
        out
    }
}
