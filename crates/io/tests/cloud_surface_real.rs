//! Ground truth for the distance to a scan's surface
//! (`trigbody_core::internals::spatial::cloud_surface`): the built-in body's mesh measured
//! against its own 200 000-point virtual scan. The mesh is the surface the
//! scan samples, so what a distance to the scan says about it is the
//! distance's own error: the nearest-point distance gives the point
//! spacing, the distance to the surface must give the scanner's noise or
//! less. Printed with `--nocapture`.

use trigbody_core::internals::spatial::cloud_surface::CloudSurface;
use trigbody_core::internals::spatial::distance::sample_surface;
use trigbody_core::internals::spatial::point_grid::PointGrid;
use trigbody_core::Real;
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_io::{read_mesh, ReadOptions};

fn rms(d: &[Real]) -> Real {
    (d.iter().map(|d| d * d).sum::<Real>() / d.len().max(1) as Real).sqrt()
}

fn p95(d: &[Real]) -> Real {
    let mut d = d.to_vec();
    d.sort_by(Real::total_cmp);
    d[(0.95 * (d.len() - 1) as Real).round() as usize]
}

/// 60 000 samples of the mesh against its virtual scan (σ = 1 mm along
/// the normal, 0.5 mm along the surface, H/1700 and H/3400): on the
/// samples within 5 mm of a scan point (the others lie over the scan's
/// holes), the nearest-point RMS is the sampling's floor (about 1.9 mm),
/// the distance to the scan's surface under the normal noise (1 mm), with
/// the scan's normals and with normals estimated from the points alike.
#[test]
fn the_mesh_is_on_its_own_scans_surface() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).unwrap();
    let scan = virtual_scan(&mesh, &ScannerOptions::default()).unwrap();
    let cloud = &scan.cloud;
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), p| {
            (l.min(p.dot(scan.up)), h.max(p.dot(scan.up)))
        });
    let height = hi - lo;
    let mm = 1000.0; // the body is in metres
    let spacing = (mesh.surface_area() / cloud.positions.len() as Real).sqrt();
    let grid = PointGrid::new(&cloud.positions, 0.01 * height);
    let samples = sample_surface(&mesh, 60_000);
    let nearest = grid.distances(&samples);
    let with = CloudSurface::new(&grid, cloud.normals.as_deref(), spacing).distances(&samples);
    let without = CloudSurface::new(&grid, None, spacing).distances(&samples);
    let seen: Vec<usize> = (0..samples.len())
        .filter(|&i| nearest[i] * mm <= 5.0)
        .collect();
    let pick = |d: &[Real]| seen.iter().map(|&i| d[i] * mm).collect::<Vec<Real>>();
    let (near, with_n, without_n) = (pick(&nearest), pick(&with), pick(&without));
    println!(
        "mesh samples within 5 mm of the scan: {} of {}; spacing {:.2} mm",
        seen.len(),
        samples.len(),
        spacing * mm
    );
    for (name, d) in [
        ("nearest point", &near),
        ("surface (scan normals)", &with_n),
        ("surface (estimated normals)", &without_n),
    ] {
        println!("  {name:<28} rms {:.3} mm, p95 {:.3} mm", rms(d), p95(d));
    }
    let sigma = mm * height / 1700.0;
    assert!(rms(&near) > 1.5 && rms(&near) < 2.3, "{}", rms(&near));
    for d in [&with_n, &without_n] {
        assert!(rms(d) < 0.6 * sigma, "{} vs σ {sigma}", rms(d));
        assert!(rms(d) < 0.35 * rms(&near), "{} {}", rms(d), rms(&near));
    }
    // Over the holes the distance stays the hole's size: it never falls
    // below the nearest-point distance by more than a few spacings (a disk
    // radius and the point's noise), nor rises above it.
    let worst_drop = (0..samples.len())
        .map(|i| nearest[i] - with[i].min(without[i]))
        .fold(0.0, Real::max);
    assert!((0..samples.len()).all(|i| with[i] <= nearest[i] && without[i] <= nearest[i]));
    println!(
        "  largest drop below the nearest-point distance {:.2} mm",
        worst_drop * mm
    );
    assert!(worst_drop < 3.0 * spacing, "{worst_drop}");
}
