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
mod gallery;
mod heatmap;
pub mod names;
mod output;
mod render;
mod report;
pub mod rows;
#[cfg(feature = "viewer")]
mod view;
mod view_args;

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
    #[command(
        after_help = "Examples:\n  gnomon setup --scene demo --view street --technique lispsm\n  gnomon setup --scene-file assets/scenes/courtyard.toml --view lamp --technique cube --json"
    )]
    Setup(Box<args::SetupArgs>),
    /// Render a scene with a shadow-map technique (and optionally its light mask and the
    /// shadow map as the light sees it).
    #[command(
        after_help = "Examples:\n  gnomon render --view street --technique cascades --mask mask.png --out street.png\n  gnomon render --mesh bunny.off --technique volumes --out bunny.png"
    )]
    Render(Box<render::RenderArgs>),
    /// Write a scene's world-space triangles as Wavefront OBJ.
    #[command(
        after_help = "Examples:\n  gnomon export --scene demo --obj demo.obj\n  gnomon export --scene-file assets/scenes/courtyard.toml --obj courtyard.obj"
    )]
    Export(render::ExportArgs),
    /// Render a scene (the built-in demo unless --scene, --mesh or --scene-file says
    /// otherwise) from its named views with every technique, side by side in an HTML page.
    #[command(
        after_help = "Examples:\n  gnomon demo\n  gnomon demo --scene-file assets/scenes/courtyard.toml --out courtyard-demo"
    )]
    Demo(Box<demo::DemoArgs>),
    /// Perspective aliasing dp/ds along the view axis of every technique, measured from its
    /// matrices in the LiSPSM paper's ideal configuration (table, JSON, plot); the papers'
    /// warps, without the warp limit.
    #[command(
        after_help = "Examples:\n  gnomon analyze --zn 1 --zf 100 --plot curves.svg\n  gnomon analyze --zn 1 --zf 100 --cascades 4 --json"
    )]
    Analyze(Box<analyze::AnalyzeArgs>),
    /// Every technique against the exact shadow volumes over named views (of one scene, or of
    /// every scene file of a --suite): image grids, wrong pixels, sampling error percentiles
    /// and times (Markdown and JSON).
    #[command(
        after_help = "Examples:\n  gnomon compare --views street,low_sun --techniques focused,lispsm,cascades\n  gnomon compare --suite assets/suite --techniques focused,lispsm"
    )]
    Compare(Box<compare::CompareArgs>),
    /// Time techniques on the same scene and views (frames interleaved), with each one's
    /// ratio to the focused shadow map.
    #[command(
        after_help = "Examples:\n  gnomon bench --techniques focused,lispsm,volumes\n  gnomon bench --techniques psm,sppsm --baseline psm"
    )]
    Bench(Box<bench::BenchArgs>),
    /// How much shadows swim and shimmer while the camera or the sun moves: false flicker
    /// and edge swim on fixed surface points along a path.
    #[command(
        after_help = "Examples:\n  gnomon flicker --view street --path dolly --frames 30\n  gnomon flicker --view street --path pan --techniques cascades-stable,cascades-lispsm"
    )]
    Flicker(Box<flicker::FlickerArgs>),
    /// An interactive window: fly through the scene, drag the sun, change the technique and
    /// its parameters, copy the render command of what you see.
    #[command(
        after_help = "Examples:\n  gnomon view --view overview --technique lispsm\n  gnomon view --view street --technique cascades --split focused"
    )]
    View(Box<view_args::ViewCommandArgs>),
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

impl From<gnomon_tools::UsageError> for CliError {
    fn from(e: gnomon_tools::UsageError) -> Self {
        CliError::usage(e.0)
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
            // The library names the failure; what to install is the command line's to say.
            gnomon_render::RenderError::NoAdapter(_) => Self::runtime(format!(
                "{e}; on a machine without a GPU driver install Mesa's software Vulkan driver \
                 (apt-get install -y mesa-vulkan-drivers) or its GL driver (apt-get install -y \
                 libegl-mesa0 libgl1-mesa-dri, WGPU_BACKEND=gl)"
            )),
            _ => Self::runtime(e.to_string()),
        }
    }
}

/// `gnomon view`, where this build has the window.
#[cfg(feature = "viewer")]
fn run_view(args: &view_args::ViewCommandArgs) -> Result<(), CliError> {
    view::run(args)
}

/// `gnomon view` in a build without the window: the window's stack (winit, egui) is an opt-in
/// feature so that the first build, for `demo`, stays short.
#[cfg(not(feature = "viewer"))]
fn run_view(_args: &view_args::ViewCommandArgs) -> Result<(), CliError> {
    Err(CliError::usage(
        "this gnomon was built without its window: rebuild with `--features viewer` \
         (cargo run --release -p gnomon-cli --features viewer -- view ..., or \
         cargo install --path crates/gnomon-cli --features viewer)",
    ))
}

/// Mesa's Vulkan device-select layer prints an error about `XDG_RUNTIME_DIR` twice on every
/// headless run; `NODEVICE_SELECT=1` keeps the layer out, but only if set before the Vulkan
/// loader starts, and setting it in-process needs unsafe code. So a command that opens a GPU
/// runs itself once more with it set, unless the user has set it either way. `None`: go on
/// here.
fn rerun_without_device_select(command: &Command) -> Option<ExitCode> {
    const VAR: &str = "NODEVICE_SELECT";
    let opens_gpu = match command {
        Command::Setup(_) | Command::Export(_) | Command::Analyze(_) => false,
        // Without the window, `view` only says how to get it.
        Command::View(_) => cfg!(feature = "viewer"),
        _ => true,
    };
    if !opens_gpu || std::env::var_os(VAR).is_some() {
        return None;
    }
    let exe = std::env::current_exe().ok()?;
    let status = std::process::Command::new(exe)
        .args(std::env::args_os().skip(1))
        .env(VAR, "1")
        .status()
        .ok()?;
    // A child ended by a signal has no code: report a failure at run time.
    Some(ExitCode::from(
        status
            .code()
            .and_then(|c| u8::try_from(c).ok())
            .unwrap_or(1),
    ))
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
    if let Some(code) = rerun_without_device_select(&cli.command) {
        return code;
    }
    let result = match cli.command {
        Command::Setup(a) => args::run_setup(&a),
        Command::Render(a) => render::run(&a),
        Command::Export(a) => render::export(&a),
        Command::Demo(a) => demo::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::Analyze(a) => analyze::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Flicker(a) => flicker::run(&a),
        Command::View(a) => run_view(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError { message, code }) => {
            eprintln!("error: {}", message.replace('\n', " "));
            ExitCode::from(code)
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::{CommandFactory, Parser};

    use super::Cli;

    /// Every subcommand's `--help` ends with two examples, and each parses as written.
    #[test]
    fn every_help_ends_with_two_examples_that_parse() {
        let cli = Cli::command();
        for sub in cli.get_subcommands() {
            let help = sub
                .get_after_help()
                .map(|h| h.to_string())
                .unwrap_or_default();
            let examples: Vec<&str> = help
                .lines()
                .skip_while(|l| *l != "Examples:")
                .skip(1)
                .map(str::trim)
                .collect();
            assert_eq!(examples.len(), 2, "{}: {help}", sub.get_name());
            for example in examples {
                let words: Vec<&str> = example.split_whitespace().collect();
                assert_eq!(words[..2], ["gnomon", sub.get_name()], "{example}");
                if let Err(e) = Cli::try_parse_from(&words) {
                    panic!("{example}: {e}");
                }
            }
        }
    }
}
