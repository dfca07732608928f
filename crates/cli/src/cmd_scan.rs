//! `trigbody scan MESH -o SCAN.ply`: a virtual multi-view scan of a mesh.

use crate::exit::{bad, print};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use trigbody_core::Real;
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_io::{write_point_cloud_as, Format, ReadOptions, WriteOptions};

/// Arguments of `trigbody scan`. Each option maps onto a field of
/// `ScannerOptions`.
#[derive(Debug, Args)]
pub struct ScanArgs {
    /// The body mesh (OBJ, PLY, STL).
    pub mesh: PathBuf,
    /// Where to write the points with normals (.ply, .xyz, .csv).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Random seed: the same seed gives the same scan.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of points (at most 20 million: 1 GB of points and normals).
    #[arg(long, default_value_t = 200_000, value_parser = crate::bounds::count_in(1usize, 20_000_000))]
    pub points: usize,
    /// Cameras per ring.
    #[arg(long, default_value_t = 8, value_parser = crate::bounds::count_in(1usize, 360))]
    pub azimuths: usize,
    /// Rings of cameras (heights).
    #[arg(long, default_value_t = 3, value_parser = crate::bounds::count_in(1usize, 100))]
    pub heights: usize,
    /// Noise along the normal, as a fraction of the body's height.
    #[arg(long, default_value_t = 1.0 / 1700.0, value_parser = crate::bounds::real_in(0.0, 0.1))]
    pub noise_normal: Real,
    /// Noise across the normal, as a fraction of the body's height.
    #[arg(long, default_value_t = 1.0 / 3400.0, value_parser = crate::bounds::real_in(0.0, 0.1))]
    pub noise_tangent: Real,
    /// Largest angle of incidence (degrees) still captured.
    #[arg(long, default_value_t = 75.0)]
    pub max_incidence: Real,
    /// Replace OUTPUT if it exists (`--overwrite` is the older spelling).
    #[arg(long, alias = "overwrite")]
    pub force: bool,
}

pub fn run(args: ScanArgs) -> Result<()> {
    let name = args.mesh.display().to_string();
    let ext = crate::output::output_extension(&args.output, "ply");
    let format = Format::from_path(&std::path::Path::new("scan").with_extension(&ext))
        .filter(|f| *f != Format::Stl)
        .ok_or_else(|| {
            bad(format!(
                "{}: unknown point format; use a .ply, .xyz, .csv, .txt or .obj file name",
                args.output.display()
            ))
        })?;
    let mesh = crate::input_file::read_mesh(&args.mesh, &ReadOptions::default())?;
    let opts = ScannerOptions {
        points: args.points,
        seed: args.seed,
        azimuths: args.azimuths,
        heights: args.heights,
        noise_normal: args.noise_normal,
        noise_tangent: args.noise_tangent,
        max_incidence_deg: args.max_incidence,
        ..Default::default()
    };
    let scan = virtual_scan(&mesh, &opts).map_err(|e| bad(format!("{name}: {e}")))?;
    let wopts = WriteOptions {
        overwrite: args.force,
        ..Default::default()
    };
    crate::output::refuse_input(&args.output, &[&args.mesh])?;
    write_point_cloud_as(&args.output, &scan.cloud, format, &wopts).map_err(bad)?;
    print(&format!(
        "{name}: {} points from {} cameras (seed {}), {:.1} % of the surface seen; written to {}\n",
        scan.cloud.positions.len(),
        scan.cameras.len(),
        args.seed,
        100.0 * scan.seen_fraction,
        args.output.display()
    ))
}
