//! The `tessera` command-line tool. Each subcommand lives in its own module under `src/cli/`.

use clap::{Parser, Subcommand};

mod cli;

/// Catmull-Clark subdivision surfaces through real Vulkan tessellation stages.
#[derive(Parser)]
#[command(name = "tessera", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
}

/// Prints the library's warnings and errors (e.g. Vulkan validation messages) to stderr: the
/// library logs through the `log` crate and never prints itself.
struct StderrLogger;

impl log::Log for StderrLogger {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            eprintln!("{}", record.args());
        }
    }

    fn flush(&self) {}
}

fn main() -> std::process::ExitCode {
    if log::set_logger(&StderrLogger).is_ok() {
        log::set_max_level(log::LevelFilter::Warn);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(args) => cli::info::run(args),
        Command::Limit(args) => cli::limit::run(args),
        Command::Render(args) => cli::render::run(args),
        Command::Sample(args) => cli::sample::run(args),
        Command::Bench(args) => cli::bench::run(args),
        Command::Error(args) => cli::error::run(args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
