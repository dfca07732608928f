//! One closed skin: the boundary of the union of a model's pieces as a
//! single watertight, manifold, consistently oriented mesh.
//!
//! Every piece (a tessellated part or transition, consistently oriented,
//! sharing its vertices) has its open ends closed by fans
//! ([`crate::surface::skin::closed_piece`]), which makes it a closed surface; the
//! closed pieces and the cavities (pockets of skin inside a part, facing
//! into the pocket) make one soup whose winding number is at least 1
//! exactly inside the union of the pieces less the cavities. Its boundary
//! is found by the robust engine of
//! [manifold-rust](https://crates.io/crates/manifold-rust) (a mesh
//! arrangement on exact rational arithmetic, Zhou et al. 2016), which
//! accepts pieces that intersect themselves, as tessellated parts do where
//! sections of different directions meet (a leg's and its foot's; on the
//! built-in body 7 of its 10 pieces), and decides coincident faces (two
//! pieces ending on one plane) exactly. The exact engine (the C++ Manifold's
//! algorithm) needs operands free of self-intersections: on those pieces
//! it left 13 shells and 909 intersecting triangle pairs. The result's
//! triangles face outwards and share their vertices, so every edge is in
//! exactly two triangles.
//!
//! Only the triangles near the crossings change, so the soup is first
//! rebuilt locally ([`crate::surface::local_skin`]: the engine's exact
//! intersection graph of that neighbourhood alone, everything else kept or
//! dropped by patches, decided by ray winding numbers); the whole-soup
//! rebuild ([`whole_soup_skin`]) runs when that fails its own check.
//!
//! The exact crossing points, rounded to floating point, leave degenerate
//! triangles: specks of shells, micro-edges and caps (a vertex on the
//! opposite edge). They are tidied away: specks dropped, micro-edges
//! collapsed, caps flipped into their neighbours (the surface unchanged).
//! Manifold's own clean-up on import (`RemoveDegenerates`) removed every
//! zero-area triangle of the corpus skins too, but split five of 52 into
//! extra shells and crossed one: not used.
//!
//! [`check_closed`] is an independent check of such a mesh (edges,
//! components, orientation, triangle–triangle intersections over a box
//! hierarchy), used by the tests and the diagnostics.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::Mesh;
use crate::geom::union_find::root;
use crate::spatial::distance::MeshDistance;
use manifold_rust::manifold::Manifold;
use manifold_rust::types::{Error as ManifoldError, MeshGL64, WindingRule};
use thiserror::Error;

/// Why a closed skin could not be made.
#[derive(Debug, Error, PartialEq)]
pub enum ClosedSkinError {
    /// A piece's open ends do not form loops (two boundary edges leave one
    /// vertex, or its orientation is inconsistent), so it encloses nothing.
    #[error("piece {piece}: its open ends do not form loops, so it cannot be closed")]
    Unclosable { piece: usize },
    /// The mesh boolean refused the closed pieces or failed (its status).
    #[error("the mesh boolean failed on the closed pieces ({why})")]
    Boolean { why: String },
    /// Nothing to unite.
    #[error("no pieces to unite")]
    Empty,
}

/// The boundary of the union of `solids` less `cavities` (see the module
/// doc): `solids` are the pieces facing outwards, `cavities` the pockets
/// facing into themselves (as a body's `tessellate_pieces`
/// gives them). Shells enclosing less than [`SPECK`] of the largest one's
/// volume are left out, and so are voids no cavity lines (gaps between
/// the pieces, filled: [`without_gaps`]). Rebuilt locally where that
/// passes its own check, else from the whole soup (module doc).
pub fn closed_skin(solids: &[Mesh], cavities: &[Mesh]) -> Result<Mesh, ClosedSkinError> {
    let (soup, piece) = closed_soup(solids, cavities)?;
    let skin = match crate::surface::local_skin::local_closed_skin(&soup, &piece) {
        Some(skin) => tidied(skin),
        None => whole_soup_skin(&soup)?,
    };
    Ok(without_gaps(skin, cavities))
}

/// `skin` without the voids no cavity lines: a shell facing inwards (negative
/// volume) bounds empty space enclosed by the solid, which between pieces
/// is a gap their closing fans leave (on a corpus body, 306 cm³ inside a
/// shoulder), not skin; only a cavity's pocket is. A void is kept when at
/// least half its triangles lie on a cavity (their centroids within
/// [`ON_CAVITY`] × the skin's size of one).
fn without_gaps(skin: Mesh, cavities: &[Mesh]) -> Mesh {
    let (labels, shells) = shell_labels(&skin);
    if shells.iter().all(|s| s.1 >= 0.0) {
        return skin;
    }
    // Per void, how many of its triangles lie on a cavity, of how many.
    let mut on = vec![(0usize, 0usize); shells.len()];
    let voids: Vec<usize> = (0..skin.triangles.len())
        .filter(|&t| shells[labels[t] as usize].1 < 0.0)
        .collect();
    let lining = crate::geom::mesh::concatenate(cavities).0;
    if !lining.triangles.is_empty() {
        let centroids: Vec<Point3> = voids
            .iter()
            .map(|&t| {
                let [a, b, c] = skin.triangle(t);
                (a + b + c) / 3.0
            })
            .collect();
        let size = skin.bounds().map_or(0.0, |b| (b.max - b.min).norm());
        let d = MeshDistance::new(&lining).distances(&centroids);
        for (&t, d) in voids.iter().zip(d) {
            on[labels[t] as usize].0 += usize::from(d <= ON_CAVITY * size);
        }
    }
    for &t in &voids {
        on[labels[t] as usize].1 += 1;
    }
    let lined: Vec<bool> = (0..shells.len())
        .map(|k| shells[k].1 >= 0.0 || 2 * on[k].0 >= on[k].1)
        .collect();
    crate::surface::skin::kept(&skin, |t| lined[labels[t] as usize])
}

/// How near a void's triangle lies to a cavity to be its lining, as a
/// fraction of the skin's size (the boolean's rounding is far under it).
const ON_CAVITY: Real = 1e-6;

/// The closed pieces (solids closed with [`BULGE`] or as far as the open
/// ends meeting theirs, [`crate::surface::skin::closed_pieces`]; cavities
/// flat) as one soup, and each triangle's piece.
pub fn closed_soup(
    solids: &[Mesh],
    cavities: &[Mesh],
) -> Result<(Mesh, Vec<u32>), ClosedSkinError> {
    let closed: Vec<Result<Mesh, ClosedSkinError>> = closed_solids(solids)
        .into_iter()
        .chain(
            cavities
                .iter()
                .map(|m| crate::surface::skin::closed_piece(m, 0.0)),
        )
        .enumerate()
        .map(|(k, m)| m.ok_or(ClosedSkinError::Unclosable { piece: k }))
        .collect();
    let closed = closed.into_iter().collect::<Result<Vec<Mesh>, _>>()?;
    let (soup, ranges) = crate::geom::mesh::concatenate(&closed);
    if soup.triangles.is_empty() {
        return Err(ClosedSkinError::Empty);
    }
    let mut piece = vec![0u32; soup.triangles.len()];
    for (k, r) in ranges.into_iter().enumerate() {
        piece[r].fill(k as u32);
    }
    Ok((soup, piece))
}

/// The closed skin of a soup of closed pieces by one rebuild of the whole
/// soup: the fallback of the local rebuild
/// ([`crate::surface::local_skin`]), and its reference.
pub fn whole_soup_skin(soup: &Mesh) -> Result<Mesh, ClosedSkinError> {
    // The robust engine: the pieces intersect themselves where a part's
    // sections of different directions meet (a leg's and its foot's), which
    // the exact engine does not accept. Winding number >= 1 is solid: a
    // cavity, facing into itself, takes its pocket out.
    let imported = Manifold::from_mesh_gl64_robust(&mesh_gl(soup));
    let skin = imported.rebuild_solid(WindingRule::Positive);
    match skin.status() {
        ManifoldError::NoError => Ok(tidied(from_mesh_gl(&skin.get_mesh_gl64(-1)))),
        e => Err(ClosedSkinError::Boolean {
            why: format!("{e:?}"),
        }),
    }
}

/// `m` as the boolean's mesh (positions only).
fn mesh_gl(m: &Mesh) -> MeshGL64 {
    MeshGL64 {
        num_prop: 3,
        vert_properties: m.positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
        tri_verts: m.triangles.iter().flatten().map(|&v| v as u64).collect(),
        ..MeshGL64::default()
    }
}

/// The boolean's mesh as ours.
fn from_mesh_gl(g: &MeshGL64) -> Mesh {
    let n = g.num_prop.max(3) as usize;
    Mesh {
        positions: g
            .vert_properties
            .chunks_exact(n)
            .map(|p| Point3::new(p[0], p[1], p[2]))
            .collect(),
        normals: None,
        triangles: g
            .tri_verts
            .chunks_exact(3)
            .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
            .collect(),
    }
}

/// What [`check_closed`] finds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ClosedCheck {
    /// Undirected edges in other than exactly two triangles.
    pub bad_edges: usize,
    /// Edges whose two triangles run them the same way (orientation flips).
    pub misoriented_edges: usize,
    /// Connected components (triangles joined through shared vertices).
    pub components: usize,
    /// Each component's triangles and enclosed volume, largest volume
    /// first (a void's volume is negative).
    pub shells: Vec<(usize, Real)>,
    /// Pairs of triangles sharing no vertex that intersect, and pairs
    /// sharing one vertex that meet elsewhere too.
    pub intersecting_pairs: usize,
    /// Enclosed volume (positive when the triangles face outwards).
    pub volume: Real,
}

impl ClosedCheck {
    /// One closed, consistently oriented, self-intersection-free shell.
    pub fn is_closed_manifold(&self) -> bool {
        self.bad_edges == 0
            && self.misoriented_edges == 0
            && self.components == 1
            && self.intersecting_pairs == 0
            && self.volume > 0.0
    }
}

/// Checks `m` independently of how it was made: every edge in exactly two
/// triangles run once each way, the components through shared edges, and
/// every pair of triangles tested for intersection (a box hierarchy finds
/// the pairs whose boxes overlap; triangles sharing an edge are adjacent,
/// not intersecting, and those sharing one vertex only must meet nowhere
/// else).
pub fn check_closed(m: &Mesh) -> ClosedCheck {
    let (bad_edges, misoriented_edges) = m.edge_faults();
    let shells = shells(m);
    ClosedCheck {
        bad_edges,
        misoriented_edges,
        components: shells.len(),
        shells,
        intersecting_pairs: crate::spatial::tri_intersect::intersecting_pairs(m),
        volume: m.signed_volume(),
    }
}

/// The connected components of `m`'s triangles through shared vertices:
/// each one's triangle count and signed volume, largest volume first.
fn shells(m: &Mesh) -> Vec<(usize, Real)> {
    let (_, mut out) = shell_labels(m);
    out.sort_by(|p, q| q.1.total_cmp(&p.1).then(q.0.cmp(&p.0)));
    out
}

/// Each triangle's component (through shared vertices) and, per
/// component, its triangle count and signed volume.
fn shell_labels(m: &Mesh) -> (Vec<u32>, Vec<(usize, Real)>) {
    let mut parent: Vec<u32> = (0..m.positions.len() as u32).collect();
    for t in &m.triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            if a != b {
                parent[a as usize] = b;
            }
        }
    }
    let mut index = vec![u32::MAX; m.positions.len()];
    let mut shells: Vec<(usize, Real)> = Vec::new();
    let labels = m
        .triangles
        .iter()
        .map(|t| {
            let r = root(&mut parent, t[0]) as usize;
            if index[r] == u32::MAX {
                index[r] = shells.len() as u32;
                shells.push((0, 0.0));
            }
            let [a, b, c] = t.map(|v| m.positions[v as usize]);
            let s = &mut shells[index[r] as usize];
            s.0 += 1;
            s.1 += a.dot(b.cross(c)) / 6.0;
            index[r]
        })
        .collect();
    (labels, shells)
}

/// A rebuilt skin without its specks and slivers, whichever path made it.
fn tidied(m: Mesh) -> Mesh {
    let mut m = without_slivers(without_specks(m));
    // A flip can leave its neighbour a cap in turn.
    for _ in 0..CAP_PASSES {
        match without_caps(&m) {
            Some(flipped) => m = flipped,
            None => break,
        }
    }
    m
}

/// The most passes of [`without_caps`].
const CAP_PASSES: usize = 3;

/// `m` with its caps flipped away: a cap is a triangle of (near) zero
/// area whose edges are not short, one vertex lying on the opposite edge
/// (within [`CAP`] times that edge's length), which the exact
/// arrangement leaves where a crossing point falls on an edge and a
/// short-edge collapse does not reach. Its longest edge is flipped to join
/// that vertex to the neighbour's opposite one, which splits the
/// neighbour at it: the same surface, without the cap. A flip that would
/// make an edge that exists already is skipped. `None` when nothing was
/// flipped, or the result is not closed and consistently oriented.
fn without_caps(m: &Mesh) -> Option<Mesh> {
    let p = |v: u32| m.positions[v as usize];
    let is_cap = |t: &[u32; 3]| -> Option<usize> {
        let e = |k: usize| (p(t[(k + 1) % 3]) - p(t[k])).norm();
        let k = (0..3).max_by(|&a, &b| e(a).total_cmp(&e(b)))?;
        let short = (0..3).map(e).fold(Real::INFINITY, Real::min);
        let area2 = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).norm();
        // A needle (an edge of no length) stays a needle when flipped.
        let long = e(k);
        (short > CAP * long && area2 < CAP * long * long).then_some(k)
    };
    let mut triangles = m.triangles.clone();
    let mut owner: std::collections::HashMap<(u32, u32), usize> = triangles
        .iter()
        .enumerate()
        .flat_map(|(i, t)| (0..3).map(move |k| ((t[k], t[(k + 1) % 3]), i)))
        .collect();
    let mut flipped = false;
    for i in 0..triangles.len() {
        let Some(k) = is_cap(&triangles[i]) else {
            continue;
        };
        let t = triangles[i];
        let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        let Some(&j) = owner.get(&(b, a)) else {
            continue;
        };
        let u = triangles[j];
        let Some(&d) = u.iter().find(|&&v| v != a && v != b) else {
            continue;
        };
        if d == c || owner.contains_key(&(c, d)) || owner.contains_key(&(d, c)) {
            continue;
        }
        // (a, b, c) and (b, a, d) become (a, d, c) and (d, b, c).
        for key in [(a, b), (b, c), (c, a), (b, a), (a, d), (d, b)] {
            owner.remove(&key);
        }
        triangles[i] = [a, d, c];
        triangles[j] = [d, b, c];
        for (n, t) in [(i, triangles[i]), (j, triangles[j])] {
            for k in 0..3 {
                owner.insert((t[k], t[(k + 1) % 3]), n);
            }
        }
        flipped = true;
    }
    let out = Mesh {
        positions: m.positions.clone(),
        normals: None,
        triangles,
    };
    (flipped && out.edge_faults() == (0, 0)).then_some(out)
}

/// A triangle whose doubled area is under this fraction of its longest
/// edge squared is a cap ([`without_caps`]): its third vertex within a
/// millionth of that edge's length from it.
pub const CAP: Real = 1e-6;

/// `m` without its specks: shells enclosing less than [`SPECK`] of the
/// largest one's volume (either way round). The arrangement leaves a few
/// where two pieces' surfaces nearly coincide (on the shared base body
/// eleven voids of four triangles, each under 1e-11 m³).
fn without_specks(m: Mesh) -> Mesh {
    let (labels, shells) = shell_labels(&m);
    let largest = shells.iter().map(|s| s.1.abs()).fold(0.0, Real::max);
    if shells.iter().all(|s| s.1.abs() >= SPECK * largest) {
        return m;
    }
    crate::surface::skin::kept(&m, |t| {
        shells[labels[t] as usize].1.abs() >= SPECK * largest
    })
}

/// `m` with its edges shorter than [`SLIVER`] times its size collapsed:
/// the exact arrangement's crossing points, rounded to floating point,
/// leave micro-triangles (edges of 1e-7 m, areas of 1e-16 m²) where two
/// pieces' surfaces nearly coincide (head and torso ending on one plane),
/// and a rounded micro-triangle can cross its neighbour. Each short edge
/// is collapsed onto one end, the two triangles on it going, where the
/// two ends share no neighbour but those triangles' third vertices (the
/// link condition: the surface stays a manifold). `m` as given when
/// nothing is that short, or when the result is not closed and
/// consistently oriented.
fn without_slivers(m: Mesh) -> Mesh {
    let Some(b) = m.bounds() else {
        return m;
    };
    let limit = SLIVER * (b.max - b.min).norm();
    let length = |t: &[u32; 3], k: usize| {
        m.positions[t[k] as usize].distance(m.positions[t[(k + 1) % 3] as usize])
    };
    let short: Vec<(u32, u32)> = m
        .triangles
        .iter()
        .flat_map(|t| {
            (0..3)
                .filter(move |&k| length(t, k) < limit)
                .map(move |k| (t[k], t[(k + 1) % 3]))
        })
        .filter(|(a, b)| a < b)
        .collect();
    if short.is_empty() {
        return m;
    }
    let mut triangles = m.triangles.clone();
    let mut alive = vec![true; triangles.len()];
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); m.positions.len()];
    for (i, t) in triangles.iter().enumerate() {
        for &v in t {
            around[v as usize].push(i);
        }
    }
    for (a, b) in short {
        let live = |v: u32, alive: &[bool], around: &[Vec<usize>]| -> Vec<usize> {
            around[v as usize]
                .iter()
                .copied()
                .filter(|&i| alive[i])
                .collect()
        };
        let (ta, tb) = (live(a, &alive, &around), live(b, &alive, &around));
        let on_edge: Vec<usize> = ta.iter().copied().filter(|i| tb.contains(i)).collect();
        if on_edge.len() != 2 {
            continue; // already collapsed away, or not a manifold edge
        }
        let ring = |ts: &[usize]| -> std::collections::BTreeSet<u32> {
            ts.iter().flat_map(|&i| triangles[i]).collect()
        };
        let (ra, rb) = (ring(&ta), ring(&tb));
        let mut common: Vec<u32> = ra
            .intersection(&rb)
            .copied()
            .filter(|&v| v != a && v != b)
            .collect();
        let mut opposite: Vec<u32> = on_edge
            .iter()
            .flat_map(|&i| triangles[i])
            .filter(|&v| v != a && v != b)
            .collect();
        common.sort_unstable();
        opposite.sort_unstable();
        if common != opposite {
            continue;
        }
        for &i in &on_edge {
            alive[i] = false;
        }
        for i in ta {
            if alive[i] {
                for v in triangles[i].iter_mut() {
                    if *v == a {
                        *v = b;
                    }
                }
                around[b as usize].push(i);
            }
        }
    }
    let collapsed = crate::surface::skin::kept(
        &Mesh {
            positions: m.positions.clone(),
            normals: None,
            triangles,
        },
        |i| alive[i],
    );
    if collapsed.triangles.is_empty() || collapsed.edge_faults() != (0, 0) {
        return m;
    }
    collapsed
}

/// An edge of the closed skin shorter than this fraction of the model's
/// size is collapsed (`without_slivers`): a micrometre on a 2 m body,
/// far below any tessellation's edges.
pub const SLIVER: Real = 5e-7;

/// How far a solid piece's open end is closed out of its plane, as a
/// fraction of the end's mean radius ([`crate::surface::skin::closed_piece`]): a
/// shallow cone, so that pieces ending on one plane (head and torso at the
/// neck) overlap; without it, at `trigbody mesh`'s default tessellation the
/// head came out as a shell of its own, touching the torso. Every open end
/// of a model lies inside another piece, where the cone adds nothing; one
/// that other open ends meet reaches as far as they do
/// ([`crate::surface::skin::closed_pieces`]).
pub const BULGE: Real = 0.05;

/// The solid pieces closed together ([`crate::surface::skin::closed_pieces`]).
fn closed_solids(solids: &[Mesh]) -> Vec<Option<Mesh>> {
    crate::surface::skin::closed_pieces(solids, BULGE)
}

/// The smallest shell kept, as a fraction of the largest one's volume.
pub const SPECK: Real = 1e-6;

/// The volume of the union of `solids` less `cavities` (given as to
/// [`closed_skin`], each closed by [`crate::surface::skin::closed_piece`] with the
/// same [`BULGE`]), measured
/// without a boolean: rays along `up` through the centres of a square grid
/// of side `spacing` across it; along each ray every closed piece's
/// crossings give its winding number, and a point counts where some solid
/// winds around it and no cavity does. The midpoint rule: the volume of a
/// smooth solid within about `(spacing / size)^2`.
pub fn union_volume(solids: &[Mesh], cavities: &[Mesh], up: Vec3, spacing: Real) -> Real {
    let Some(up) = up.normalized() else {
        return 0.0;
    };
    let e1 = if up.x.abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let e1 = (e1 - up * e1.dot(up)).normalized().unwrap_or(e1);
    let e2 = up.cross(e1);
    // Every closed piece's triangles in (e1, e2, up) coordinates, with the
    // piece's index and whether it is a cavity.
    let mut tris: Vec<([Vec3; 3], u32, bool)> = Vec::new();
    let closed = closed_solids(solids).into_iter().map(|m| (m, false)).chain(
        cavities
            .iter()
            .map(|m| (crate::surface::skin::closed_piece(m, 0.0), true)),
    );
    for (k, (closed, cavity)) in closed.enumerate() {
        let Some(mut closed) = closed else {
            continue;
        };
        if cavity {
            closed.flip_orientation();
        }
        for t in 0..closed.triangles.len() {
            let local = closed
                .triangle(t)
                .map(|p| Vec3::new(p.dot(e1), p.dot(e2), p.dot(up)));
            tris.push((local, k as u32, cavity));
        }
    }
    let (lo, hi) = tris.iter().flat_map(|t| t.0).fold(
        (
            (Real::INFINITY, Real::INFINITY),
            (Real::NEG_INFINITY, Real::NEG_INFINITY),
        ),
        |(lo, hi), p| {
            (
                (lo.0.min(p.x), lo.1.min(p.y)),
                (hi.0.max(p.x), hi.1.max(p.y)),
            )
        },
    );
    if !(spacing > 0.0) || tris.is_empty() {
        return 0.0;
    }
    let nx = ((hi.0 - lo.0) / spacing).ceil() as usize + 1;
    let ny = ((hi.1 - lo.1) / spacing).ceil() as usize + 1;
    // The triangles over each cell of the grid (by their boxes).
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); nx * ny];
    let cell = |x: Real, y: Real| {
        (
            (((x - lo.0) / spacing) as usize).min(nx - 1),
            (((y - lo.1) / spacing) as usize).min(ny - 1),
        )
    };
    for (i, (t, _, _)) in tris.iter().enumerate() {
        let (x0, y0) = cell(
            t[0].x.min(t[1].x).min(t[2].x),
            t[0].y.min(t[1].y).min(t[2].y),
        );
        let (x1, y1) = cell(
            t[0].x.max(t[1].x).max(t[2].x),
            t[0].y.max(t[1].y).max(t[2].y),
        );
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                cells[cy * nx + cx].push(i as u32);
            }
        }
    }
    let pieces = solids.len() + cavities.len();
    let column = |c: &usize| -> Real {
        let (cx, cy) = (c % nx, c / nx);
        let (x, y) = (
            lo.0 + (cx as Real + 0.5) * spacing,
            lo.1 + (cy as Real + 0.5) * spacing,
        );
        // Crossings: height, piece, +1 entering (facing down), -1 leaving.
        let mut hits: Vec<(Real, u32, bool, i32)> = Vec::new();
        for &i in &cells[*c] {
            let (t, k, cavity) = &tris[i as usize];
            let [a, b, d] = *t;
            let area = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
            if area == 0.0 {
                continue;
            }
            let w0 = (b.x - x) * (d.y - y) - (b.y - y) * (d.x - x);
            let w1 = (d.x - x) * (a.y - y) - (d.y - y) * (a.x - x);
            let w2 = (a.x - x) * (b.y - y) - (a.y - y) * (b.x - x);
            let inside = if area > 0.0 {
                w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0
            } else {
                w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0
            };
            if inside {
                let z = (w0 * a.z + w1 * b.z + w2 * d.z) / area;
                // Facing up (counter-clockwise seen from above): leaving.
                hits.push((z, *k, *cavity, if area > 0.0 { -1 } else { 1 }));
            }
        }
        hits.sort_by(|p, q| p.0.total_cmp(&q.0));
        let mut winding = vec![0i32; pieces];
        let (mut solid_in, mut cavity_in) = (0i32, 0i32);
        let mut length = 0.0;
        let mut last = 0.0;
        for (z, k, cavity, step) in hits {
            if solid_in > 0 && cavity_in == 0 {
                length += z - last;
            }
            let w = &mut winding[k as usize];
            let was = *w > 0;
            *w += step;
            let now = *w > 0;
            let count = if cavity {
                &mut cavity_in
            } else {
                &mut solid_in
            };
            *count += now as i32 - was as i32;
            last = z;
        }
        length
    };
    let columns: Vec<usize> = (0..nx * ny).collect();
    let chunks: Vec<&[usize]> = columns.chunks(1024).collect();
    let total: Real =
        crate::geom::parallel::each_on_cores(&chunks, |ch| ch.iter().map(column).sum::<Real>())
            .into_iter()
            .sum();
    total * spacing * spacing
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes::{cuboid, cylinder};

    /// A tetrahedron whose face (a, b, d) is split at the midpoint c of
    /// ab into (a, c, d) and (c, b, d), closed by the cap (a, b, c): the
    /// cap is flipped into its neighbour across ab, which splits it at c.
    #[test]
    fn a_cap_is_flipped_away_and_the_surface_kept() {
        let (a, b, x, d) = (0u32, 1u32, 2u32, 3u32);
        let c = 4u32;
        let v = Vec3::new;
        let positions = vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.3, 1.0, 0.0),
            v(0.4, 0.3, 1.0),
            v(0.5, 0.0, 0.0),
        ];
        // The tetrahedron (a, b, x) down, the rest up and out.
        let tetra = [[a, x, b], [a, b, d], [b, x, d], [x, a, d]];
        let whole = Mesh {
            positions: positions.clone(),
            normals: None,
            triangles: tetra.to_vec(),
        };
        assert_eq!(whole.edge_faults(), (0, 0));
        // Face (a, b, d) split at c, with the cap.
        let split = Mesh {
            positions,
            normals: None,
            triangles: vec![
                [a, x, b],
                [a, c, d],
                [c, b, d],
                [a, b, c],
                [b, x, d],
                [x, a, d],
            ],
        };
        assert_eq!(split.edge_faults(), (0, 0));
        let area = |m: &Mesh, t: usize| {
            let [p, q, r] = m.triangle(t);
            (q - p).cross(r - p).norm()
        };
        assert!((0..split.triangles.len()).any(|t| area(&split, t) == 0.0));
        let fixed = without_caps(&split).expect("a cap flipped");
        assert_eq!(fixed.edge_faults(), (0, 0));
        assert_eq!(fixed.triangles.len(), split.triangles.len());
        assert!((0..fixed.triangles.len()).all(|t| area(&fixed, t) > 1e-3));
        let volume = |m: &Mesh| check_closed(m).volume;
        assert!((volume(&fixed) - volume(&whole)).abs() < 1e-12);
        // Nothing to flip.
        assert_eq!(without_caps(&whole), None);
    }

    /// Six walls overlapping at their edges enclose a gap: the closed skin
    /// is the outside alone, one shell; a pocket lined by a cavity stays.
    #[test]
    fn a_gap_between_pieces_is_filled_and_a_cavity_kept() {
        let v = Vec3::new;
        let walls = vec![
            cuboid(v(-1.0, -1.0, -1.0), v(-0.8, 1.0, 1.0)),
            cuboid(v(0.8, -1.0, -1.0), v(1.0, 1.0, 1.0)),
            cuboid(v(-0.9, -1.01, -0.99), v(0.9, -0.79, 0.99)),
            cuboid(v(-0.9, 0.79, -0.99), v(0.9, 1.01, 0.99)),
            cuboid(v(-0.91, -0.92, -1.02), v(0.91, 0.92, -0.78)),
            cuboid(v(-0.91, -0.92, 0.78), v(0.91, 0.92, 1.02)),
        ];
        for w in &walls {
            assert!(w.signed_volume() > 0.0);
        }
        let skin = closed_skin(&walls, &[]).expect("closed skin");
        let shells = shells(&skin);
        assert_eq!(shells.len(), 1, "{shells:?}");
        assert!(check_closed(&skin).is_closed_manifold());
        // Without the filling the soup's boolean keeps the gap's walls.
        let (soup, _) = closed_soup(&walls, &[]).unwrap();
        let whole = whole_soup_skin(&soup).unwrap();
        assert!(super::shells(&whole).iter().any(|s| s.1 < 0.0));
        // A box with a cavity inside it: the pocket is the cavity's lining.
        let mut pocket = cuboid(v(-0.3, -0.3, -0.3), v(0.3, 0.3, 0.3));
        pocket.flip_orientation();
        let solid = cuboid(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0));
        let skin = closed_skin(&[solid], &[pocket]).expect("closed skin");
        let shells = super::shells(&skin);
        assert_eq!(shells.len(), 2, "{shells:?}");
        assert!((skin.signed_volume() - (8.0 - 0.216)).abs() < 1e-9);
    }

    /// A tetrahedron whose edge 0-1 carries a vertex a nanometre from
    /// vertex 0: its two triangles on that edge are split into a
    /// micro-triangle and a whole one each. The collapse gives the
    /// tetrahedron back; without a short edge a mesh is returned as is.
    #[test]
    fn a_micro_edge_is_collapsed_and_the_skin_stays_closed() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let tetra = Mesh {
            positions: p.to_vec(),
            normals: None,
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        };
        assert_eq!(check_closed(&tetra).bad_edges, 0);
        let mut split = tetra.clone();
        split.positions.push(p[0] + (p[1] - p[0]) * 1e-9);
        split.triangles = vec![
            [0, 2, 4],
            [4, 2, 1],
            [0, 4, 3],
            [4, 1, 3],
            [0, 3, 2],
            [1, 2, 3],
        ];
        assert_eq!(split.edge_faults(), (0, 0));
        let mended = without_slivers(split.clone());
        assert_eq!(mended.triangles.len(), 4);
        assert_eq!(mended.edge_faults(), (0, 0));
        assert!((mended.signed_volume() - tetra.signed_volume()).abs() < 1e-9);
        assert_eq!(without_slivers(tetra.clone()), tetra);
    }

    /// Two upright cylinders crossing side by side (no faces in one
    /// plane), and a third lying across both.
    fn crossing() -> Vec<Mesh> {
        let mut lying = cylinder(Vec3::new(0.0, 0.0, -1.5), 0.4, 3.0, 24, 40);
        for p in &mut lying.positions {
            // A quarter turn about y (orientation kept).
            *p = Vec3::new(p.z, p.y, 1.0 - p.x);
        }
        vec![
            cylinder(Vec3::new(-0.5, 0.0, 0.0), 0.6, 2.0, 20, 48),
            cylinder(Vec3::new(0.5, 0.1, 0.13), 0.6, 2.1, 20, 48),
            lying,
        ]
    }

    #[test]
    fn local_path_matches_the_whole_soup() {
        let pieces = crossing();
        let (soup, piece) = closed_soup(&pieces, &[]).unwrap();
        let local =
            crate::surface::local_skin::local_closed_skin(&soup, &piece).expect("local path");
        let whole = whole_soup_skin(&soup).unwrap();
        let (lc, wc) = (check_closed(&local), check_closed(&whole));
        assert!(lc.is_closed_manifold(), "{lc:?}");
        assert!(wc.is_closed_manifold(), "{wc:?}");
        assert!((lc.volume / wc.volume - 1.0).abs() < 1e-9, "{lc:?} {wc:?}");
        // Less than the pieces' total: they overlap.
        let total: Real = pieces.iter().map(|m| m.signed_volume()).sum();
        assert!(lc.volume < total - 0.1, "{} {total}", lc.volume);
    }

    #[test]
    fn coincident_pieces_fall_back_to_the_whole_soup() {
        // Two copies of one cylinder: every ray from one grazes the other,
        // so the local path gives up and the whole-soup rebuild decides.
        let c = cylinder(Vec3::new(0.0, 0.0, 0.0), 0.5, 1.0, 8, 24);
        let pieces = [c.clone(), c.clone()];
        let (soup, piece) = closed_soup(&pieces, &[]).unwrap();
        assert!(crate::surface::local_skin::local_closed_skin(&soup, &piece).is_none());
        let skin = closed_skin(&pieces, &[]).unwrap();
        let check = check_closed(&skin);
        assert!(check.is_closed_manifold(), "{check:?}");
        assert!(
            (check.volume / c.signed_volume() - 1.0).abs() < 1e-9,
            "{check:?}"
        );
    }
}
