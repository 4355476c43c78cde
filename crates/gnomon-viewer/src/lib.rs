//! gnomon's interactive viewer: a winit window that draws a [`Model`] through gnomon's
//! renderer into an offscreen view (blitted to the window, since a surface texture may not
//! be copied from), an egui panel beside it, a fly and orbit camera ([`rig::CameraRig`]), a
//! sun dragged across the sky ([`rig::SunRig`]), scripted input indexed by frame
//! ([`script::Script`]) and screenshots of the 3D view.
//!
//! The viewer knows nothing of gnomon's options: a [`Model`] (gnomon-cli's `gnomon view`)
//! turns the rigs into a camera and lights, sets up and draws the frame, fills the panel from
//! its option definitions and says which `gnomon render` command reproduces the frame.

#![forbid(unsafe_code)]

pub mod rig;
pub mod script;
mod window;

use std::path::PathBuf;

pub use egui;
pub use window::run;

use gnomon_render::Renderer;

use rig::{CameraRig, SunRig};
use script::Script;

/// How the viewer runs.
#[derive(Debug, Clone)]
pub struct ViewerOptions {
    /// The window's title.
    pub title: String,
    /// The window's inner size in pixels.
    pub size: (u32, u32),
    /// Render this many frames, then exit (with `screenshot`, writing the last frame's 3D
    /// view), printing the render command of the last frame on stdout.
    pub frames: Option<u64>,
    /// Where `frames` writes its screenshot (PNG).
    pub screenshot: Option<PathBuf>,
    /// Hide the panel: the 3D view fills the window.
    pub no_ui: bool,
    /// Input replayed by frame.
    pub script: Script,
}

/// What input moves: the camera, and the sun where the light is directional.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rigs {
    /// The camera.
    pub camera: CameraRig,
    /// The sun (`None`: the light is a spot or a point and stays).
    pub sun: Option<SunRig>,
}

/// What the viewer tells a [`Model`] about the frame it draws.
#[derive(Debug, Clone, Copy)]
pub struct FrameInfo {
    /// The 3D view's size in pixels.
    pub size: (u32, u32),
    /// The frame's number, from 0.
    pub frame: u64,
    /// Whether the rigs are where they were the frame before (what a frame sees can then be
    /// measured once and kept).
    pub still: bool,
    /// Whether this frame is written to a screenshot (it must be exactly what its render
    /// command draws).
    pub exact: bool,
    /// Whether the panel shows (what only it shows need not be measured otherwise).
    pub panel: bool,
}

/// Where a [`Model`] draws the frame's 3D view.
pub struct ViewTarget<'a> {
    /// The view's texture: [`gnomon_render::COLOR_FORMAT`], `info.size`, render attachment
    /// and copy destination.
    pub texture: &'a wgpu::Texture,
    /// A view of it.
    pub view: &'a wgpu::TextureView,
}

/// A texture a [`Model`] can draw a 3D view into: [`gnomon_render::COLOR_FORMAT`], `size`,
/// render attachment, sampled by the blit, copy source and destination; and a view of it.
pub fn view_texture(
    device: &wgpu::Device,
    size: (u32, u32),
    label: &str,
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: gnomon_render::COLOR_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    (texture, view)
}

/// What a frame cost, for the panel.
#[derive(Debug, Clone, Default)]
pub struct FrameReport {
    /// The shadow setup's time in microseconds (summed over the lights).
    pub setup_us: f64,
    /// Lines for the panel: diagnostics, fallbacks, counts.
    pub notes: Vec<String>,
}

/// What the viewer draws: gnomon's `view` command implements it over its option definitions.
pub trait Model {
    /// Where the camera and the sun start.
    fn rigs(&self) -> Rigs;

    /// Sets up the frame's shadows for `rigs` and records its passes into `encoder`, the
    /// main pass into `target`; an error is shown in the panel (or ends a scripted run) and
    /// the previous frame stays.
    fn draw(
        &mut self,
        renderer: &mut Renderer,
        encoder: &mut wgpu::CommandEncoder,
        target: &ViewTarget<'_>,
        rigs: &Rigs,
        info: &FrameInfo,
    ) -> Result<FrameReport, String>;

    /// The panel's controls (technique and its parameters, light, filtering); may move the
    /// rigs (sliders).
    fn panel(&mut self, ui: &mut egui::Ui, rigs: &mut Rigs);

    /// The `gnomon render` command that draws this frame: the rigs' camera and light, the
    /// model's technique and options, a 3D view of `size`.
    fn command(&self, rigs: &Rigs, size: (u32, u32)) -> String;
}

/// How the viewer ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ViewerError {
    /// The window, surface or device could not be made (exit code 1).
    Window(String),
    /// The model refused its start or a scripted frame (exit code 2 where it is bad input).
    Model(String),
}

impl std::fmt::Display for ViewerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Window(m) | Self::Model(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ViewerError {}
