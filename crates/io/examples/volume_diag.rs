//! Where a model's volume differs from its input mesh's: both are sliced
//! by horizontal planes and filled on a raster (the model as the union of
//! its closed pieces), and the difference is integrated by height band and
//! by which pieces cover it (a diagnostic).
//!
//! ```text
//! cargo run --release -p trigbody-io --example volume_diag BODY [CELL_MM]
//! ```
//!
//! Prints `measure_body`'s volume (parts and bands, minus the arm–torso
//! overlap) and each piece's against its fine tessellation's; the raster's
//! mesh volume, sum of pieces and union; the volume covered by each set of
//! pieces inside and outside the mesh; the largest model-only volumes by
//! 2 cm band and piece; the mesh's pockets (holes of its horizontal
//! sections); and per 2 cm band the model's and the mesh's volume. With
//! `SECTIONS=1`, each horizontal part's fitted sections against their mesh
//! loops (area of the curve, of a refit through the vertices, of a smooth
//! curve through them, and of a refit of the same order through the
//! polygon resampled evenly); with `LOOPS=h1,h2,…` (metres above the
//! soles) the mesh's loops at those heights. `CELL_MM` defaults to 1.

use std::collections::BTreeMap;
use trigbody_core::internals::measure::volume::volume_area_extent;
use trigbody_core::BodyGeometry;
use trigbody_core::{measure_body, ModelMeasureOptions};
use trigbody_core::{reconstruct, Body, ReconstructOptions};
use trigbody_core::{tessellate_part, Mesh, Real, TessellationOptions, Vec3};
use trigbody_io::{read_mesh, ReadOptions};

type Tri = [Vec3; 3];

/// The mesh's triangles in `(front, left, up)` coordinates, its open
/// boundary loops closed by fans to their centroids.
fn closed_triangles(m: &Mesh, to_local: &impl Fn(Vec3) -> Vec3) -> (Vec<Tri>, usize) {
    // Weld equal positions.
    let mut ids = std::collections::HashMap::new();
    let mut pos = Vec::new();
    let remap: Vec<u32> = m
        .positions
        .iter()
        .map(|p| {
            let key = [p.x, p.y, p.z].map(|c| (c * 1e8).round() as i64);
            *ids.entry(key).or_insert_with(|| {
                pos.push(to_local(*p));
                (pos.len() - 1) as u32
            })
        })
        .collect();
    let tris: Vec<[u32; 3]> = m
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect();
    let mut directed = std::collections::HashSet::new();
    for t in &tris {
        for k in 0..3 {
            directed.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut next = std::collections::HashMap::new();
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) {
            next.insert(a, b);
        }
    }
    let mut out: Vec<Tri> = tris.iter().map(|t| t.map(|i| pos[i as usize])).collect();
    let mut loops = 0;
    let mut seen = std::collections::HashSet::new();
    let starts: Vec<u32> = next.keys().copied().collect();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut lp = vec![s];
        seen.insert(s);
        let mut v = s;
        while let Some(&w) = next.get(&v) {
            if w == s || !seen.insert(w) {
                break;
            }
            lp.push(w);
            v = w;
        }
        loops += 1;
        let c = lp
            .iter()
            .fold(Vec3::new(0.0, 0.0, 0.0), |acc, &i| acc + pos[i as usize])
            * (1.0 / lp.len() as Real);
        for k in 0..lp.len() {
            let (a, b) = (pos[lp[k] as usize], pos[lp[(k + 1) % lp.len()] as usize]);
            out.push([b, a, c]);
        }
    }
    (out, loops)
}

fn volume(t: &[Tri]) -> Real {
    t.iter().map(|t| t[0].dot(t[1].cross(t[2]))).sum::<Real>() / 6.0
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("volume_diag: {e}");
            std::process::ExitCode::from(2)
        }
    }
}

fn run() -> Result<(), String> {
    let Some(path) = std::env::args().nth(1) else {
        return Err("usage: volume_diag BODY [CELL_MM]".into());
    };
    let cell: Real = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0)
        * 1e-3;
    let mesh = read_mesh(&path, &ReadOptions::default()).map_err(|e| format!("{path}: {e}"))?;
    let (body, _) = reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default())
        .map_err(|e| format!("{path}: {e}"))?;
    let f = body.frame;
    let to_local = |p: Vec3| Vec3::new(p.dot(f.front), p.dot(f.left), p.dot(f.up));
    let topts = TessellationOptions {
        around: 512,
        along: 24,
        cap_rings: 64,
        target_edge: None,
    };
    // Pieces: parts, then transitions.
    let mut pieces: Vec<(String, Vec<Tri>)> = Vec::new();
    let one = |b: &Body| volume_area_extent(b).0;
    let mut mm_vol = Vec::new();
    for p in &body.parts {
        let m = tessellate_part(&p.part, &topts).map_err(|e| e.to_string())?;
        let (t, loops) = closed_triangles(&m, &to_local);
        let mut b = body.clone();
        b.parts = vec![p.clone()];
        b.transitions.clear();
        mm_vol.push(one(&b));
        eprintln!("{:?}: {} triangles, {loops} loops closed", p.name, t.len());
        pieces.push((format!("{:?}", p.name), t));
    }
    for tr in &body.transitions {
        let m = tr.transition.tessellate(512, 64);
        let (t, loops) = closed_triangles(&m, &to_local);
        let mut b = body.clone();
        b.parts.clear();
        b.transitions = vec![tr.clone()];
        mm_vol.push(one(&b));
        eprintln!(
            "{:?}->{:?}: {} triangles, {loops} loops closed",
            tr.from,
            tr.to,
            t.len()
        );
        pieces.push((format!("{:?}>{:?}", tr.from, tr.to), t));
    }
    let (mesh_tris, mesh_loops) = closed_triangles(&mesh, &to_local);
    if mesh_loops != 0 {
        return Err(format!(
            "{path}: the input is not closed ({mesh_loops} holes)"
        ));
    }
    let v_mesh = volume(&mesh_tris).abs();
    let (v_sum, _, (low, high)) = volume_area_extent(&body);
    let mm = measure_body(&body, &ModelMeasureOptions::default()).map_err(|e| e.to_string())?;
    let h = high - low;
    println!("# {path}: H {h:.4} m, mesh volume {:.2} cm³", 1e6 * v_mesh);
    println!(
        "measure_model: parts+bands {:.1} cm³, minus overlap {:.1} cm³ = {:.1} cm³ ({:+.3} %)",
        1e6 * v_sum,
        1e6 * (v_sum - mm.volume.model),
        1e6 * mm.volume.model,
        100.0 * (mm.volume.model / v_mesh - 1.0)
    );
    println!("piece               measure_model   tessellation (cm³)");
    for (k, (n, t)) in pieces.iter().enumerate() {
        println!(
            "{n:<20} {:>12.1} {:>12.1}",
            1e6 * mm_vol[k],
            1e6 * volume(t).abs()
        );
    }
    // Raster.
    let mut lo = Vec3::new(Real::INFINITY, Real::INFINITY, Real::INFINITY);
    let mut hi = -lo;
    for t in pieces
        .iter()
        .flat_map(|p| p.1.iter())
        .chain(mesh_tris.iter())
    {
        for p in t {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
    }
    let na = ((hi.x - lo.x) / cell).ceil() as usize + 1;
    let nb = ((hi.y - lo.y) / cell).ceil() as usize + 1;
    let nz = ((hi.z - lo.z) / cell).ceil() as usize + 1;
    let zc = |k: usize| lo.z + (k as Real + 0.5) * cell;
    // Per slice, the triangles spanning it.
    let bucket = |tris: &[Tri]| {
        let mut b: Vec<Vec<u32>> = vec![Vec::new(); nz];
        for (i, t) in tris.iter().enumerate() {
            let (z0, z1) = (
                t[0].z.min(t[1].z).min(t[2].z),
                t[0].z.max(t[1].z).max(t[2].z),
            );
            let k0 = (((z0 - lo.z) / cell - 0.5).floor().max(0.0)) as usize;
            let k1 = ((((z1 - lo.z) / cell - 0.5).ceil()) as usize).min(nz - 1);
            for bk in b.iter_mut().take(k1 + 1).skip(k0) {
                bk.push(i as u32);
            }
        }
        b
    };
    let mut all: Vec<(&[Tri], Vec<Vec<u32>>)> =
        pieces.iter().map(|p| (&p.1[..], bucket(&p.1))).collect();
    all.push((&mesh_tris[..], bucket(&mesh_tris)));
    let np = pieces.len();
    let cv = cell * cell * cell;
    let mut grid = vec![0u16; na * nb];
    // (mask, in mesh) → volume; per 2 cm band: (model, mesh, model-only, mesh-only).
    let mut by_mask: BTreeMap<(u16, bool), Real> = BTreeMap::new();
    // (band, mask) → model-only volume.
    let mut band_mask: BTreeMap<(usize, u16), Real> = BTreeMap::new();
    let band = 0.02;
    let nbands = (h / band).ceil() as usize + 2;
    let mut bands = vec![[0.0; 4]; nbands];
    let mut xs: Vec<Vec<Real>> = vec![Vec::new(); nb];
    for k in 0..nz {
        let z = zc(k);
        grid.iter_mut().for_each(|g| *g = 0);
        for (pi, (tris, bk)) in all.iter().enumerate() {
            xs.iter_mut().for_each(|x| x.clear());
            for &ti in &bk[k] {
                let t = &tris[ti as usize];
                let mut ends = Vec::with_capacity(2);
                for e in 0..3 {
                    let (p, q) = (t[e], t[(e + 1) % 3]);
                    if (p.z <= z) != (q.z <= z) {
                        let s = (z - p.z) / (q.z - p.z);
                        ends.push((p.x + s * (q.x - p.x), p.y + s * (q.y - p.y)));
                    }
                }
                if ends.len() != 2 {
                    continue;
                }
                let ((a0, b0), (a1, b1)) = (ends[0], ends[1]);
                // Rows whose centre b_j lies in [min b, max b).
                let (bl, bh) = (b0.min(b1), b0.max(b1));
                let j0 = ((bl - lo.y) / cell - 0.5).ceil().max(0.0) as usize;
                let mut j = j0;
                while j < nb {
                    let bj = lo.y + (j as Real + 0.5) * cell;
                    if bj >= bh {
                        break;
                    }
                    if bj >= bl {
                        let s = (bj - b0) / (b1 - b0);
                        xs[j].push(a0 + s * (a1 - a0));
                    }
                    j += 1;
                }
            }
            let bit = 1u16 << pi;
            for (j, x) in xs.iter_mut().enumerate() {
                if x.is_empty() {
                    continue;
                }
                x.sort_by(|a, b| a.total_cmp(b));
                for pair in x.chunks(2) {
                    if pair.len() < 2 {
                        continue;
                    }
                    let i0 = ((pair[0] - lo.x) / cell - 0.5).ceil().max(0.0) as usize;
                    let i1 = (((pair[1] - lo.x) / cell - 0.5).ceil().max(0.0) as usize).min(na);
                    for i in i0..i1 {
                        grid[j * na + i] |= bit;
                    }
                }
            }
        }
        let bi = (((z - low) / band).floor().max(0.0) as usize).min(nbands - 1);
        let mesh_bit = 1u16 << np;
        for &g in &grid {
            if g == 0 {
                continue;
            }
            let inside = g & mesh_bit != 0;
            let mask = g & !mesh_bit;
            *by_mask.entry((mask, inside)).or_default() += cv;
            let b = &mut bands[bi];
            if mask != 0 {
                b[0] += cv;
            }
            if inside {
                b[1] += cv;
            }
            if mask != 0 && !inside {
                b[2] += cv;
                *band_mask.entry((bi, mask)).or_default() += cv;
            }
            if mask == 0 && inside {
                b[3] += cv;
            }
        }
    }
    let union: Real = by_mask.iter().filter(|e| e.0 .0 != 0).map(|e| e.1).sum();
    let sum: Real = by_mask
        .iter()
        .map(|e| e.0 .0.count_ones() as Real * e.1)
        .sum();
    let mesh_r: Real = by_mask.iter().filter(|e| e.0 .1).map(|e| e.1).sum();
    println!(
        "raster {:.1} mm: mesh {:.1} cm³ (exact {:.1}), model sum {:.1}, union {:.1} ({:+.3} % of mesh), overlap {:.1}",
        1e3 * cell,
        1e6 * mesh_r,
        1e6 * v_mesh,
        1e6 * sum,
        1e6 * union,
        100.0 * (union / mesh_r - 1.0),
        1e6 * (sum - union)
    );
    let names = |m: u16| {
        (0..np)
            .filter(|i| m & (1 << i) != 0)
            .map(|i| pieces[i].0.as_str())
            .collect::<Vec<_>>()
            .join("+")
    };
    println!("cover                                  model-only  both     (cm³)");
    let mut masks: Vec<u16> = by_mask.keys().map(|k| k.0).collect();
    masks.dedup();
    for m in masks {
        let out = by_mask.get(&(m, false)).copied().unwrap_or(0.0);
        let inn = by_mask.get(&(m, true)).copied().unwrap_or(0.0);
        let label = if m == 0 {
            "(mesh only)".to_string()
        } else {
            names(m)
        };
        println!("{label:<38} {:>9.1} {:>9.1}", 1e6 * out, 1e6 * inn);
    }
    let mut top: Vec<_> = band_mask.iter().collect();
    top.sort_by(|a, b| b.1.total_cmp(a.1));
    println!("largest model-only (band, cover): cm³");
    for ((bi, m), v) in top.iter().take(25) {
        println!(
            "{:>5.2}-{:<5.2} {:<30} {:>7.1}",
            *bi as Real * band,
            (*bi + 1) as Real * band,
            names(*m),
            1e6 * **v
        );
    }
    {
        // The mesh's pockets seen by horizontal planes: loops lying inside
        // an odd number of others are holes of the section (the mouth's
        // cavity), which one curve per section cannot leave out.
        use trigbody_core::internals::section::mesh::{MeshSlicer, SectionOptions};
        let slicer =
            MeshSlicer::new(&mesh, f.up, &SectionOptions::default()).map_err(|e| e.to_string())?;
        let (a, b) = slicer.range();
        let dz = 0.5e-3;
        let mut pockets: BTreeMap<i64, Real> = BTreeMap::new();
        let mut total = 0.0;
        let mut z = a + 0.5 * dz;
        while z < b {
            if let Ok(s) = slicer.section_at(z) {
                for (i, l) in s.loops.iter().enumerate() {
                    let depth = s
                        .loops
                        .iter()
                        .enumerate()
                        .filter(|(j, o)| *j != i && o.area > l.area && o.contains(l.points[0]))
                        .count();
                    if depth % 2 == 1 {
                        total += l.area * dz;
                        *pockets.entry(((z - a) / 0.02).floor() as i64).or_default() += l.area * dz;
                    }
                }
            }
            z += dz;
        }
        let list: Vec<String> = pockets
            .iter()
            .filter(|e| *e.1 > 1e-6)
            .map(|(k, v)| {
                format!(
                    "{:.2}-{:.2} m {:.1}",
                    *k as Real * 0.02,
                    (*k + 1) as Real * 0.02,
                    1e6 * v
                )
            })
            .collect();
        println!(
            "mesh pockets (holes of horizontal sections): {:.1} cm³ ({:.3} % of the mesh): {}",
            1e6 * total,
            100.0 * total / v_mesh,
            list.join(", ")
        );
    }
    if std::env::var("SECTIONS").is_ok() {
        use trigbody_core::internals::section::mesh::{section_mesh, Plane, SectionOptions};
        // Each horizontal part's fitted sections against the mesh loop they
        // were fitted to: area of the curve vs the polygon's.
        for p in &body.parts {
            let (mut da, mut aa, mut nv, mut k) = (0.0, 0.0, 0usize, 0usize);
            let mut fits = [0.0; 5];
            for c in p.part.curves() {
                let sc = c.world_series();
                let n = 2048;
                let pts: Vec<Vec3> = (0..n)
                    .map(|i| sc.point(std::f64::consts::TAU * i as Real / n as Real))
                    .collect();
                let o =
                    pts.iter().fold(Vec3::new(0.0, 0.0, 0.0), |a, &b| a + b) * (1.0 / n as Real);
                let nrm = (pts[n / 4] - o).cross(pts[0] - o);
                let Some(nrm) = nrm.normalized() else {
                    continue;
                };
                if nrm.dot(f.up).abs() < 0.999 {
                    continue;
                }
                let area = (0..n)
                    .map(|i| (pts[i] - o).cross(pts[(i + 1) % n] - o).dot(f.up))
                    .sum::<Real>()
                    .abs()
                    / 2.0;
                let Ok(plane) = Plane::new(o, f.up) else {
                    continue;
                };
                let Ok(sec) = section_mesh(&mesh, &plane, &SectionOptions::default()) else {
                    continue;
                };
                let Some(li) = sec.select(o) else { continue };
                let lp = &sec.loops[li];
                if (lp.area / area - 1.0).abs() > 0.2 {
                    continue;
                }
                // Refit the loop: as reconstruct does (its vertices), at the
                // same order through the polygon resampled evenly, and at
                // the highest order through the resampled polygon.
                use trigbody_core::{fit_loop, FitOptions, OrderChoice};
                let fo = FitOptions {
                    reference: Some(f.front),
                    normal: Some(f.up),
                    allow_non_planar: true,
                    ..FitOptions::default()
                };
                let dense = trigbody_core::internals::section::mesh::resample_closed(
                    &lp.points,
                    512.max(lp.points.len()),
                );
                let carea = |c: &trigbody_core::TrigCurve| {
                    let sc = c.world_series();
                    let m = 2048;
                    let q: Vec<Vec3> = (0..m)
                        .map(|i| sc.point(std::f64::consts::TAU * i as Real / m as Real))
                        .collect();
                    (0..m)
                        .map(|i| (q[i] - o).cross(q[(i + 1) % m] - o).dot(f.up))
                        .sum::<Real>()
                        .abs()
                        / 2.0
                };
                if let Ok(v) = fit_loop(&lp.points, &fo) {
                    let same = FitOptions {
                        order: OrderChoice::Fixed(v.order),
                        ..fo
                    };
                    // A smooth curve through the vertices: each edge bulges
                    // by the circular segment of the mean discrete curvature
                    // of its ends, κ L³ / 12.
                    let q: Vec<Vec3> = lp.points.iter().map(|&p| to_local(p)).collect();
                    let n = q.len();
                    let kappa: Vec<Real> = (0..n)
                        .map(|i| {
                            let (a, b, c) = (q[(i + n - 1) % n], q[i], q[(i + 1) % n]);
                            let (u, w) = (b - a, c - b);
                            let turn = (u.x * w.y - u.y * w.x).atan2(u.x * w.x + u.y * w.y);
                            turn / (0.5 * (u.norm() + w.norm()))
                        })
                        .collect();
                    let sgn = if (0..n)
                        .map(|i| q[i].x * q[(i + 1) % n].y - q[(i + 1) % n].x * q[i].y)
                        .sum::<Real>()
                        > 0.0
                    {
                        1.0
                    } else {
                        -1.0
                    };
                    fits[4] += sgn
                        * (0..n)
                            .map(|i| {
                                let l = (q[(i + 1) % n] - q[i]).norm();
                                0.5 * (kappa[i] + kappa[(i + 1) % n]) * l * l * l / 12.0
                            })
                            .sum::<Real>();
                    if let Ok(d) = fit_loop(&dense, &same) {
                        fits[0] += carea(&v.curve) - lp.area;
                        fits[1] += carea(&d.curve) - lp.area;
                        fits[2] += v.order as Real;
                        fits[3] += 1.0;
                    }
                }
                da += area - lp.area;
                aa += lp.area;
                nv += lp.points.len();
                k += 1;
            }
            if k > 0 {
                println!(
                    "{:?}: {k} horizontal sections, curve area vs mesh loop {:+.3} %, {:.0} loop points on average",
                    p.name,
                    100.0 * da / aa,
                    nv as Real / k as Real
                );
                println!(
                    "   refit: vertices {:+.3} %, (a smooth curve through them {:+.3} %), same order through the dense polygon {:+.3} % (mean order {:.1})",
                    100.0 * fits[0] / aa,
                    100.0 * fits[4] / aa,
                    100.0 * fits[1] / aa,
                    fits[2] / fits[3]
                );
            }
        }
    }
    if let Ok(levels) = std::env::var("LOOPS") {
        use trigbody_core::internals::section::mesh::{section_mesh, Plane, SectionOptions};
        for l in levels.split(',').filter_map(|x| x.parse::<Real>().ok()) {
            let o = f.origin + f.up * (low - f.origin.dot(f.up) + l);
            let plane = Plane::new(o, f.up).map_err(|e| e.to_string())?;
            let s = section_mesh(&mesh, &plane, &SectionOptions::default())
                .map_err(|e| e.to_string())?;
            let areas: Vec<String> = s
                .loops
                .iter()
                .map(|lp| {
                    let c = to_local(lp.centroid);
                    format!("{:.1} cm² at ({:+.3},{:+.3})", 1e4 * lp.area, c.x, c.y)
                })
                .collect();
            println!("mesh loops at {l:.3} m: {}", areas.join("; "));
            for (i, a) in s.loops.iter().enumerate() {
                for (j, b) in s.loops.iter().enumerate() {
                    if i != j && b.contains(a.points[0]) {
                        println!("  loop {i} ({:.1} cm²) lies inside loop {j}", 1e4 * a.area);
                    }
                }
            }
        }
    }
    println!("band (m above soles)  model   mesh   diff  model-only mesh-only (cm³)");
    for (i, b) in bands.iter().enumerate() {
        if b[0] == 0.0 && b[1] == 0.0 {
            continue;
        }
        println!(
            "{:>5.2}-{:<5.2}  {:>8.1} {:>8.1} {:>7.1} {:>7.1} {:>7.1}",
            i as Real * band,
            (i + 1) as Real * band,
            1e6 * b[0],
            1e6 * b[1],
            1e6 * (b[0] - b[1]),
            1e6 * b[2],
            1e6 * b[3]
        );
    }
    Ok(())
}
