//! The `trigbody` command line. Thin by design: argument parsing, progress,
//! printing and files; all geometry lives in the libraries.
//!
//! Exit codes: 0 success, 2 bad input or usage (message on stderr naming the
//! file, line or value), 1 internal failure; SIGINT, SIGTERM and SIGHUP end
//! the binary by that signal after removing unfinished outputs.
//!
//! This file is the root of the `trigbody` library, whose public items
//! are [`run`] and [`catch_signals`]: the binary (`src/bin/trigbody.rs`)
//! and the Python package's `python -m trigbody` both call `run`, so they
//! parse and run the same commands; only the binary takes over the
//! signals (in Python they stay the interpreter's).

mod batch_manifest;
mod body_input;
mod bounds;
mod cmd_batch;
mod cmd_corpus;
mod cmd_fit;
mod cmd_loft;
mod cmd_measure;
mod cmd_mesh;
mod cmd_plot_sections;
mod cmd_reconstruct;
mod cmd_render;
mod cmd_scan;
mod cmd_sections;
mod examples;
mod exit;
mod focus;
mod input_file;
mod output;
mod panels;
mod progress;
mod signals;

use clap::{Parser, Subcommand};

/// Compact, smooth human body models from trigonometric cross-section curves.
#[derive(Debug, Parser)]
#[command(name = "trigbody", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Fit a trigonometric curve to one closed loop of points.
    Fit(cmd_fit::FitArgs),
    /// Fit the bundled real cross-sections (torso, waist, neck, thigh, calf,
    /// upper arm) and compare each with the ellipse baseline.
    Examples(examples::ExamplesArgs),
    /// Skin cross-section curves into a part (a model file).
    Loft(cmd_loft::LoftArgs),
    /// Reconstruct a body model from a mesh or a scan (the built-in body
    /// without INPUT) and report its size and its distance to the input.
    Reconstruct(cmd_reconstruct::ReconstructArgs),
    /// Tessellate a model into a mesh (.glb, .obj, .ply, .stl).
    Mesh(cmd_mesh::MeshArgs),
    /// Draw a mesh or model shaded from several views side by side (PNG);
    /// --compare colours it by its distance to an input mesh.
    Render(cmd_render::RenderArgs),
    /// Measure a body: stature, girths, lengths, breadth, volume, area.
    Measure(cmd_measure::MeasureArgs),
    /// Plot a body's sections at the measurement levels: input points,
    /// trig fit and ellipse (the paper's Figures 1-2).
    PlotSections(cmd_plot_sections::PlotSectionsArgs),
    /// Cut a mesh or a scan with parallel planes and fit every loop.
    Sections(cmd_sections::SectionsArgs),
    /// Make a virtual multi-view scan (points with normals) of a mesh.
    Scan(cmd_scan::ScanArgs),
    /// Reconstruct every body of a folder with a manifest.json and judge
    /// each against its ground truth (surfaces both ways, joint centres).
    Corpus(cmd_corpus::CorpusArgs),
    /// Reconstruct many bodies in parallel: a model and report per input,
    /// a summary (JSON lines, CSV); failures are rows, not the end.
    Batch(cmd_batch::BatchArgs),
}

/// Makes SIGINT, SIGTERM and SIGHUP remove the outputs' unfinished
/// temporaries before the process ends by the signal (an existing output
/// is kept as it was); for a process that is the command line.
pub fn catch_signals() {
    signals::catch();
}

/// Runs the command line on `args` (the program name first) and returns
/// the exit code; the Python package's `python -m trigbody` calls it too.
pub fn run<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return code;
        }
    };
    let result = match cli.command {
        Command::Fit(args) => cmd_fit::run(args),
        Command::Examples(args) => examples::run(args),
        Command::Loft(args) => cmd_loft::run(args),
        Command::Reconstruct(args) => cmd_reconstruct::run(args),
        Command::Mesh(args) => cmd_mesh::run(args),
        Command::Render(args) => cmd_render::run(args),
        Command::Measure(args) => cmd_measure::run(args),
        Command::PlotSections(args) => cmd_plot_sections::run(args),
        Command::Sections(args) => cmd_sections::run(args),
        Command::Scan(args) => cmd_scan::run(args),
        Command::Corpus(args) => cmd_corpus::run(args),
        Command::Batch(args) => cmd_batch::run(args),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            crate::exit::diag(format_args!("trigbody: error: {e:#}"));
            exit::code_of(&e)
        }
    }
}
