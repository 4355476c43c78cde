//! `gnomon view`'s options, parsed whether or not this build has the window (the `viewer`
//! feature), so that `gnomon view --help` always answers and a build without the window says
//! how to get it.

use std::path::PathBuf;

use clap::Args;

use crate::args::{LightArgs, SceneArgs, ViewArgs};
use crate::names::Drawn;
use crate::render::{DrawArgs, parse_size};

/// `gnomon view`.
#[derive(Debug, Clone, Args)]
pub struct ViewCommandArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub light: LightArgs,
    #[command(flatten)]
    pub draw: DrawArgs,
    /// The window's size, WIDTHxHEIGHT (the 3D view is the window beside the panel; with
    /// --no-ui all of it).
    #[arg(long, default_value = "1280x720", allow_hyphen_values = true, value_parser = parse_size)]
    pub size: (u32, u32),
    /// Draw this many frames, then exit, printing the `gnomon render` command of the last
    /// frame on stdout (for scripted runs and tests).
    #[arg(long)]
    pub frames: Option<u64>,
    /// With --frames: write the last frame's 3D view here (PNG).
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Hide the panel: the 3D view fills the window.
    #[arg(long)]
    pub no_ui: bool,
    /// Replay input from this file, indexed by frame: one JSON object a line, e.g.
    /// {"frame": 3, "key": "W", "down": true}, {"frame": 5, "drag": [dx, dy], "button":
    /// "right"} (left: orbit, right: look, middle: the sun), {"frame": 9, "scroll": 2}.
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// Split screen: this technique (default parameters) right of the middle, the
    /// --technique left (also in the panel, with a movable divider).
    #[arg(long, value_parser = crate::names::drawn_arg)]
    pub split: Option<Drawn>,
}
