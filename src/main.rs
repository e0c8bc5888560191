//! The `tessera` command-line tool. Each subcommand lives in its own module under `src/cli/`.

use clap::{Parser, Subcommand};

mod cli;

/// Catmull-Clark subdivision surfaces through real Vulkan tessellation stages.
#[derive(Parser)]
#[command(name = "tessera", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// More diagnostics on stderr (repeat for more).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    /// Only errors on stderr.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Print counts and classification of a control mesh; non-zero exit on invalid input.
    Info(cli::info::InfoArgs),
    /// Evaluate the exact Catmull-Clark limit surface on a grid per face.
    Limit(cli::limit::LimitArgs),
    /// Render a mesh offscreen through the Vulkan tessellation pipeline to a PNG. Regular faces
    /// are GPU B-spline patches, irregular triangles/quads GPU Gregory patches (--scheme); other
    /// faces are drawn from the CPU limit reference.
    Render(cli::render::RenderArgs),
    /// Capture every TES invocation (face, u, v, position, normal) of the GPU pipeline.
    Sample(cli::sample::SampleArgs),
    /// Median GPU time per frame at several tessellation levels.
    Bench(cli::bench::BenchArgs),
    /// Accuracy of a patch scheme against the exact limit surface.
    Error(cli::error::ErrorArgs),
    /// Every scheme on one mesh: one table (patches, CPU faces, distance and normal error
    /// against the exact limit, GPU ms and memory, watertightness, normal jumps) and an optional
    /// contact sheet of error maps on one colour scale.
    Compare(cli::compare::CompareArgs),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    cli::logger::install(cli.verbose, cli.quiet);
    let result = match cli.command {
        Command::Info(args) => cli::info::run(args),
        Command::Limit(args) => cli::limit::run(args),
        Command::Render(args) => cli::render::run(args),
        Command::Sample(args) => cli::sample::run(args),
        Command::Bench(args) => cli::bench::run(args),
        Command::Error(args) => cli::error::run(args),
        Command::Compare(args) => cli::compare::run(args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
