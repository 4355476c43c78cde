//! `gnomon`: the command-line tool, as a library so that other front ends (the viewer) share
//! its one definition of every option ([`args`]) and its one registry of what can be drawn
//! ([`names`]); the `gnomon` binary calls [`main`].
//!
//! Subcommands: `setup` (print the shadow-map matrices for a camera, light and scene),
//! `render` (draw it), `export` (the scene as OBJ), `demo` (a scene from its named views
//! with every technique), `bench` (frame times side by side), `analyze`
//! (perspective aliasing of every technique from its matrices), `compare` (every
//! technique against the exact shadow volumes), `flicker` and `view` (the interactive
//! viewer). Bad input
//! gives a one-line error on stderr and exit code 2.

#![forbid(unsafe_code)]

mod analyze;
pub mod args;
mod bench;
mod compare;
mod demo;
mod flicker;
mod heatmap;
pub mod names;
mod output;
mod render;
mod report;
pub mod rows;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// gnomon: shadow-map techniques, made robust and measured against exact shadows.
#[derive(Debug, Parser)]
#[command(name = "gnomon", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Compute the shadow maps for a camera, a light and a scene, and print them.
    Setup(Box<args::SetupArgs>),
    /// Render a scene with a shadow-map technique (and optionally its light mask and the
    /// shadow map as the light sees it).
    Render(Box<render::RenderArgs>),
    /// Write a scene's world-space triangles as Wavefront OBJ.
    Export(render::ExportArgs),
    /// Render a scene (the built-in demo unless --scene, --mesh or --scene-file says
    /// otherwise) from its named views with every technique, side by side in an HTML page.
    Demo(Box<demo::DemoArgs>),
    /// Perspective aliasing dp/ds along the view axis of every technique, measured from its
    /// matrices in the LiSPSM paper's ideal configuration (table, JSON, plot); the papers'
    /// warps, without the warp limit.
    Analyze(Box<analyze::AnalyzeArgs>),
    /// Every technique against the exact shadow volumes over named views (of one scene, or of
    /// every scene file of a --suite): image grids, wrong pixels, sampling error percentiles
    /// and times (Markdown and JSON).
    Compare(Box<compare::CompareArgs>),
    /// Time techniques on the same scene and views (frames interleaved), with each one's
    /// ratio to the focused shadow map.
    Bench(Box<bench::BenchArgs>),
    /// How much shadows swim and shimmer while the camera or the sun moves: false flicker
    /// and edge swim on fixed surface points along a path.
    Flicker(Box<flicker::FlickerArgs>),
    /// An interactive window: fly through the scene, drag the sun, change the technique and
    /// its parameters, copy the render command of what you see.
    View(Box<view::ViewCommandArgs>),
}

/// An error, printed on one line: exit code 2 for bad input, 1 for a failure at run time
/// (no GPU adapter, a file that cannot be written).
#[derive(Debug)]
pub struct CliError {
    /// What went wrong.
    pub message: String,
    /// The process's exit code.
    pub code: u8,
}

impl CliError {
    /// Bad input: exit code 2.
    pub fn usage(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            code: 2,
        }
    }

    /// A failure at run time: exit code 1.
    pub fn runtime(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            code: 1,
        }
    }
}

impl From<gnomon::SetupError> for CliError {
    fn from(e: gnomon::SetupError) -> Self {
        Self::usage(e.to_string())
    }
}

impl From<gnomon_render::RenderError> for CliError {
    fn from(e: gnomon_render::RenderError) -> Self {
        match e {
            gnomon_render::RenderError::Invalid(_) => Self::usage(e.to_string()),
            _ => Self::runtime(e.to_string()),
        }
    }
}

/// Runs the command line: parses the arguments, runs the subcommand, prints an error on one
/// line and returns the exit code (2 for bad input, 1 for a failure at run time).
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                let _ = e.print();
                return ExitCode::from(2);
            }
            // clap's message spans several lines (the message, then tips and usage after a
            // blank line); keep the message, on one line.
            let text = e.to_string();
            let message: Vec<&str> = text
                .lines()
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            eprintln!("{}", message.join(" "));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Setup(a) => args::run_setup(&a),
        Command::Render(a) => render::run(&a),
        Command::Export(a) => render::export(&a),
        Command::Demo(a) => demo::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::Analyze(a) => analyze::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Flicker(a) => flicker::run(&a),
        Command::View(a) => view::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError { message, code }) => {
            eprintln!("error: {}", message.replace('\n', " "));
            ExitCode::from(code)
        }
    }
}
