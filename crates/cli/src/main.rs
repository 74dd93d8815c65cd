//! The `algesurf` command-line tool.
#![forbid(unsafe_code)]

mod convert;
mod info;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Smooth piecewise-polynomial surfaces in Bernstein–Bézier form.
#[derive(Parser, Debug)]
#[command(name = "algesurf", version, about, long_about = None, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Describe a mesh: counts, components, genus, validation findings and the repairs
    /// `convert --repair` would make.
    Info(info::InfoArgs),
    /// Convert a mesh between OBJ, PLY, STL, OFF, glTF and GLB, optionally repairing it.
    Convert(convert::ConvertArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Info(a) => info::run(a),
        Command::Convert(a) => convert::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("algesurf: error: {e}");
            ExitCode::FAILURE
        }
    }
}
