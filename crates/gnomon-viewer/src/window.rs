//! The window: winit's event loop, the surface, input, the egui panel, the offscreen 3D view
//! and its blit, screenshots.

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use gnomon_render::{Gpu, Renderer};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::rig::FlyKeys;
use crate::script::{DragButton, Input, Key};
use crate::{FrameInfo, FrameReport, Model, Rigs, ViewTarget, ViewerError, ViewerOptions};

/// Mouse look and orbit: degrees per pixel of drag.
const TURN_DEGREES_PER_PIXEL: f64 = 0.25;
/// The sun under a middle drag: degrees per pixel.
const SUN_DEGREES_PER_PIXEL: f64 = 0.25;
/// The sun under the arrow keys: degrees per second.
const SUN_DEGREES_PER_SECOND: f64 = 30.0;
/// A scripted run's time step: every frame advances the same time whatever the frame rate.
const SCRIPTED_STEP_SECONDS: f64 = 1.0 / 30.0;
/// The panel's default width in points.
const PANEL_WIDTH: f32 = 330.0;

/// The help overlay (F1).
const HELP: &str = "\
Fly: W A S D, Q down, E up, shift for speed; right drag: look
Orbit: left drag around the target; wheel: zoom toward it
Sun: middle drag, or the arrow keys (directional light)
C: print and copy the gnomon render command of this frame
F1: this help   F12: screenshot (PNG in the working directory)   Esc: quit";

/// Opens the window and runs the viewer until it is closed, Esc is pressed or
/// `options.frames` frames are drawn. `make` builds the renderer and the model on the
/// window's device.
pub fn run<M, F>(options: ViewerOptions, make: F) -> Result<(), ViewerError>
where
    M: Model,
    F: FnOnce(Gpu) -> Result<(Renderer, M), String>,
{
    let event_loop = EventLoop::new().map_err(|e| {
        ViewerError::Window(format!(
            "cannot open a window ({e}); without a display, run it under xvfb-run"
        ))
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        options,
        make: Some(make),
        running: None,
        result: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| ViewerError::Window(format!("the window's event loop failed: {e}")))?;
    app.result
}

struct App<M, F> {
    options: ViewerOptions,
    make: Option<F>,
    running: Option<Running<M>>,
    result: Result<(), ViewerError>,
}

/// The offscreen 3D view and its place in the window.
struct Offscreen {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
    origin: (u32, u32),
}

struct Running<M> {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    device: wgpu::Device,
    queue: wgpu::Queue,
    renderer: Renderer,
    model: M,
    rigs: Rigs,
    previous_rigs: Option<Rigs>,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    blit: Blit,
    offscreen: Option<Offscreen>,
    held: HashSet<Key>,
    dragging: Option<DragButton>,
    cursor: Option<(f64, f64)>,
    frame: u64,
    /// When the first frame ended (the frames per second of a scripted run count from it).
    second_frame_at: Option<Instant>,
    last_frame_at: Instant,
    fps: Fps,
    report: FrameReport,
    error: Option<String>,
    help: bool,
    pending_screenshot: Option<PathBuf>,
    quit: bool,
}

/// Frames per second over the last second.
struct Fps {
    window_start: Instant,
    frames: u32,
    value: f64,
    frame_ms: f64,
}

impl Fps {
    fn tick(&mut self, frame_ms: f64) {
        self.frames += 1;
        self.frame_ms = frame_ms;
        let elapsed = self.window_start.elapsed().as_secs_f64();
        if elapsed >= 1.0 {
            self.value = self.frames as f64 / elapsed;
            self.frames = 0;
            self.window_start = Instant::now();
        }
    }
}

impl<M: Model, F: FnOnce(Gpu) -> Result<(Renderer, M), String>> ApplicationHandler for App<M, F> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        let Some(make) = self.make.take() else {
            return;
        };
        match start(event_loop, &self.options, make) {
            Ok(running) => self.running = Some(running),
            Err(e) => {
                self.result = Err(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(running) = self.running.as_mut() else {
            return;
        };
        let consumed = running
            .egui_state
            .on_window_event(&running.window, &event)
            .consumed;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => running.resize(size.width, size.height),
            WindowEvent::KeyboardInput { event, .. } => {
                let down = event.state == ElementState::Pressed;
                // Releases always reach the rigs (no key stays held when egui took focus).
                if let (PhysicalKey::Code(code), false) = (event.physical_key, consumed && down)
                    && let Some(key) = key_of(code)
                    && !event.repeat
                {
                    running.apply(Input::Key { key, down });
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let button = match button {
                    MouseButton::Left => Some(DragButton::Left),
                    MouseButton::Right => Some(DragButton::Right),
                    MouseButton::Middle => Some(DragButton::Middle),
                    _ => None,
                };
                match state {
                    ElementState::Pressed if !consumed => running.dragging = button,
                    ElementState::Released if running.dragging == button => {
                        running.dragging = None;
                    }
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (Some(button), Some(before)) = (running.dragging, running.cursor) {
                    running.apply(Input::Drag {
                        delta: [now.0 - before.0, now.1 - before.1],
                        button,
                    });
                }
                running.cursor = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 50.0,
                };
                running.apply(Input::Scroll(steps));
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = running.redraw(&self.options) {
                    self.result = Err(e);
                    event_loop.exit();
                    return;
                }
                let done = self.options.frames.is_some_and(|n| running.frame >= n);
                if done || running.quit {
                    if let Err(e) = running.finish(&self.options) {
                        self.result = Err(e);
                    }
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(running) = &self.running {
            running.window.request_redraw();
        }
    }
}

/// The viewer's key for a physical key.
fn key_of(code: KeyCode) -> Option<Key> {
    Some(match code {
        KeyCode::KeyW => Key::W,
        KeyCode::KeyA => Key::A,
        KeyCode::KeyS => Key::S,
        KeyCode::KeyD => Key::D,
        KeyCode::KeyQ => Key::Q,
        KeyCode::KeyE => Key::E,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => Key::Shift,
        KeyCode::ArrowLeft => Key::Left,
        KeyCode::ArrowRight => Key::Right,
        KeyCode::ArrowUp => Key::Up,
        KeyCode::ArrowDown => Key::Down,
        KeyCode::KeyC => Key::C,
        KeyCode::F1 => Key::F1,
        KeyCode::F12 => Key::F12,
        KeyCode::Escape => Key::Escape,
        _ => return None,
    })
}

/// The window, its surface on a device that can present to it, the renderer and the model.
fn start<M: Model>(
    event_loop: &ActiveEventLoop,
    options: &ViewerOptions,
    make: impl FnOnce(Gpu) -> Result<(Renderer, M), String>,
) -> Result<Running<M>, ViewerError> {
    let window_error =
        |what: &str, e: &dyn std::fmt::Display| ViewerError::Window(format!("{what}: {e}"));
    let attributes = Window::default_attributes()
        .with_title(options.title.clone())
        .with_inner_size(winit::dpi::PhysicalSize::new(
            options.size.0,
            options.size.1,
        ));
    let window = Arc::new(
        event_loop
            .create_window(attributes)
            .map_err(|e| window_error("cannot open a window", &e))?,
    );
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
        Box::new(event_loop.owned_display_handle()),
    ));
    let surface = instance
        .create_surface(window.clone())
        .map_err(|e| window_error("cannot draw into the window", &e))?;
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        compatible_surface: Some(&surface),
        ..Default::default()
    }))
    .map_err(|e| window_error("no GPU adapter can draw into the window", &e))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("gnomon viewer"),
        required_features: adapter.features() & gnomon_render::OPTIONAL_FEATURES,
        required_limits: wgpu::Limits::default().using_resolution(adapter.limits()),
        ..Default::default()
    }))
    .map_err(|e| window_error("cannot open the GPU", &e))?;
    let size = window.inner_size();
    let mut config = surface
        .get_default_config(&adapter, size.width.max(1), size.height.max(1))
        .ok_or_else(|| ViewerError::Window("the GPU cannot present to this window".into()))?;
    let capabilities = surface.get_capabilities(&adapter);
    if let Some(srgb) = capabilities.formats.iter().find(|f| f.is_srgb()) {
        config.format = *srgb;
    }
    config.present_mode = wgpu::PresentMode::AutoNoVsync;
    surface.configure(&device, &config);
    let gpu = Gpu::from_device(device.clone(), queue.clone(), adapter.get_info());
    let (renderer, model) = make(gpu).map_err(ViewerError::Model)?;
    let egui_ctx = egui::Context::default();
    let egui_state = egui_winit::State::new(
        egui_ctx,
        egui::ViewportId::ROOT,
        &window,
        Some(window.scale_factor() as f32),
        None,
        Some(device.limits().max_texture_dimension_2d as usize),
    );
    let egui_renderer = egui_wgpu::Renderer::new(
        &device,
        config.format,
        egui_wgpu::RendererOptions::default(),
    );
    let blit = Blit::new(&device, config.format);
    let rigs = model.rigs();
    Ok(Running {
        window,
        surface,
        config,
        device,
        queue,
        renderer,
        model,
        rigs,
        previous_rigs: None,
        egui_state,
        egui_renderer,
        blit,
        offscreen: None,
        held: HashSet::new(),
        dragging: None,
        cursor: None,
        frame: 0,
        second_frame_at: None,
        last_frame_at: Instant::now(),
        fps: Fps {
            window_start: Instant::now(),
            frames: 0,
            value: 0.0,
            frame_ms: 0.0,
        },
        report: FrameReport::default(),
        error: None,
        help: false,
        pending_screenshot: None,
        quit: false,
    })
}

impl<M: Model> Running<M> {
    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
    }

    /// One input: keys held or pressed, a drag, the wheel.
    fn apply(&mut self, input: Input) {
        match input {
            Input::Key { key, down } => {
                if down {
                    self.held.insert(key);
                    match key {
                        Key::C => {
                            let command = self.command();
                            println!("{command}");
                            self.egui_state.egui_ctx().copy_text(command);
                        }
                        Key::F1 => self.help = !self.help,
                        Key::F12 => {
                            self.pending_screenshot =
                                Some(PathBuf::from(format!("gnomon-view-{}.png", self.frame)));
                        }
                        Key::Escape => self.quit = true,
                        _ => {}
                    }
                } else {
                    self.held.remove(&key);
                }
            }
            Input::Drag { delta, button } => {
                let (dx, dy) = (delta[0], delta[1]);
                match button {
                    DragButton::Right => self
                        .rigs
                        .camera
                        .look(dx * TURN_DEGREES_PER_PIXEL, -dy * TURN_DEGREES_PER_PIXEL),
                    DragButton::Left => self
                        .rigs
                        .camera
                        .orbit(-dx * TURN_DEGREES_PER_PIXEL, dy * TURN_DEGREES_PER_PIXEL),
                    DragButton::Middle => {
                        if let Some(sun) = &mut self.rigs.sun {
                            sun.turn(dx * SUN_DEGREES_PER_PIXEL, -dy * SUN_DEGREES_PER_PIXEL);
                        }
                    }
                }
            }
            Input::Scroll(steps) => self.rigs.camera.zoom(steps),
        }
    }

    /// The held keys' motion over `dt` seconds.
    fn move_by_held_keys(&mut self, dt: f64) {
        let held = |k| self.held.contains(&k);
        let keys = FlyKeys {
            forward: held(Key::W),
            back: held(Key::S),
            left: held(Key::A),
            right: held(Key::D),
            up: held(Key::E),
            down: held(Key::Q),
            fast: held(Key::Shift),
        };
        self.rigs.camera.fly(keys, dt);
        let axis = |plus, minus| f64::from(u8::from(held(plus))) - f64::from(u8::from(held(minus)));
        let (azimuth, elevation) = (axis(Key::Right, Key::Left), axis(Key::Up, Key::Down));
        if let Some(sun) = &mut self.rigs.sun {
            let step = SUN_DEGREES_PER_SECOND * dt;
            sun.turn(azimuth * step, elevation * step);
        }
    }

    /// The 3D view's size in pixels.
    fn view_size(&self) -> (u32, u32) {
        self.offscreen
            .as_ref()
            .map_or((self.config.width, self.config.height), |o| {
                (o.texture.width(), o.texture.height())
            })
    }

    fn command(&self) -> String {
        self.model.command(&self.rigs, self.view_size())
    }

    /// The panel and the help window, and the actions their buttons ask for; the full output
    /// and where the 3D view starts (logical points).
    fn run_panel(
        &mut self,
        ctx: &egui::Context,
        options: &ViewerOptions,
    ) -> (egui::FullOutput, f32) {
        let raw = self.egui_state.take_egui_input(&self.window);
        let mut view_left = 0.0f32;
        let mut copy = false;
        let mut screenshot = false;
        let stats = format!(
            "{:.1} frames/s, {:.1} ms a frame, setup {:.1} us",
            self.fps.value, self.fps.frame_ms, self.report.setup_us
        );
        let full = ctx.run_ui(raw, |ui| {
            if !options.no_ui {
                let panel = egui::Panel::left("gnomon panel")
                    .default_size(PANEL_WIDTH)
                    .show(ui, |ui| {
                        egui::ScrollArea::vertical().show(ui, |ui| {
                            ui.heading("gnomon");
                            ui.label(&stats);
                            for note in &self.report.notes {
                                ui.label(note);
                            }
                            if let Some(error) = &self.error {
                                ui.colored_label(egui::Color32::from_rgb(220, 60, 60), error);
                            }
                            ui.horizontal(|ui| {
                                copy = ui.button("Copy as command (C)").clicked();
                                screenshot = ui.button("Screenshot (F12)").clicked();
                            });
                            ui.separator();
                            self.model.panel(ui, &mut self.rigs);
                        });
                    });
                view_left = panel.response.rect.right();
            }
            if self.help {
                egui::Window::new("Help (F1)")
                    .collapsible(false)
                    .show(ui.ctx(), |ui| ui.label(HELP));
            }
        });
        if copy {
            self.apply(Input::Key {
                key: Key::C,
                down: true,
            });
            self.held.remove(&Key::C);
        }
        if screenshot {
            self.pending_screenshot =
                Some(PathBuf::from(format!("gnomon-view-{}.png", self.frame)));
        }
        self.egui_state
            .handle_platform_output(&self.window, full.platform_output.clone());
        (full, view_left)
    }

    /// One frame: scripted input, the panel, the model's passes into the offscreen view, the
    /// blit and the panel onto the window.
    fn redraw(&mut self, options: &ViewerOptions) -> Result<(), ViewerError> {
        let scripted = options.frames.is_some() || options.script.last_frame() > 0;
        let now = Instant::now();
        let elapsed = now.duration_since(self.last_frame_at).as_secs_f64();
        self.last_frame_at = now;
        let dt = if scripted {
            SCRIPTED_STEP_SECONDS
        } else {
            elapsed.min(0.25)
        };
        let inputs: Vec<Input> = options.script.at(self.frame).collect();
        for input in inputs {
            self.apply(input);
        }
        self.move_by_held_keys(dt);

        // The panel (it may move the rigs and change the model's options).
        let ctx = self.egui_state.egui_ctx().clone();
        let (mut full, view_left) = self.run_panel(&ctx, options);

        // The 3D view: the window right of the panel.
        let ppp = full.pixels_per_point;
        let left = ((view_left * ppp).ceil() as u32).min(self.config.width.saturating_sub(1));
        let size = (self.config.width - left, self.config.height);
        self.ensure_offscreen(left, size);
        let last = options.frames.is_some_and(|n| self.frame + 1 >= n);
        let exact = self.pending_screenshot.is_some() || last;
        let still = self.previous_rigs == Some(self.rigs);
        self.previous_rigs = Some(self.rigs);
        let info = FrameInfo {
            size,
            frame: self.frame,
            still,
            exact,
            panel: !options.no_ui,
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("viewer frame"),
            });
        let offscreen = self.offscreen.as_ref().expect("made above");
        let target = ViewTarget {
            texture: &offscreen.texture,
            view: &offscreen.view,
        };
        match self
            .model
            .draw(&mut self.renderer, &mut encoder, &target, &self.rigs, &info)
        {
            Ok(report) => {
                self.report = report;
                self.error = None;
            }
            Err(e) if scripted => return Err(ViewerError::Model(e)),
            Err(e) => self.error = Some(e),
        }

        // egui's textures first: they change whether or not the window takes this frame.
        let mut textures = std::mem::take(&mut full.textures_delta);
        for (id, deltas) in &textures.set {
            for delta in deltas {
                self.egui_renderer
                    .update_texture(&self.device, &self.queue, *id, delta);
            }
        }
        textures.set.clear();
        let jobs = ctx.tessellate(std::mem::take(&mut full.shapes), ppp);
        let presented = self.present(encoder, offscreen_size(&self.offscreen), &jobs, ppp);
        for id in &textures.free {
            self.egui_renderer.free_texture(id);
        }
        textures.free.clear();
        presented?;
        if let Some(path) = self.pending_screenshot.take() {
            self.write_screenshot(&path)?;
            eprintln!("wrote {}", path.display());
        }
        self.frame += 1;
        if self.frame == 1 {
            self.second_frame_at = Some(Instant::now());
        }
        self.fps.tick(now.elapsed().as_secs_f64() * 1e3);
        Ok(())
    }

    /// The frame onto the window: the view texel for texel, then the panel; skipped (the
    /// passes still submitted) where the surface gives no texture this time.
    fn present(
        &mut self,
        mut encoder: wgpu::CommandEncoder,
        size: (u32, u32),
        jobs: &[egui::ClippedPrimitive],
        ppp: f32,
    ) -> Result<(), ViewerError> {
        let surface_texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            other => {
                if matches!(
                    other,
                    wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost
                ) {
                    self.surface.configure(&self.device, &self.config);
                }
                self.queue.submit([encoder.finish()]);
                return Ok(());
            }
        };
        let surface_view = surface_texture
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let offscreen = self.offscreen.as_ref().expect("made before");
        self.blit
            .encode(&mut encoder, &surface_view, offscreen, size);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        let mut buffers = self.egui_renderer.update_buffers(
            &self.device,
            &self.queue,
            &mut encoder,
            jobs,
            &screen,
        );
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &surface_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            self.egui_renderer
                .render(&mut pass.forget_lifetime(), jobs, &screen);
        }
        buffers.push(encoder.finish());
        self.queue.submit(buffers);
        self.window.pre_present_notify();
        self.queue.present(surface_texture);
        Ok(())
    }

    /// A scripted run's end: its screenshot and the command of its last frame.
    fn finish(&mut self, options: &ViewerOptions) -> Result<(), ViewerError> {
        if options.frames.is_none() {
            return Ok(());
        }
        // Frames per second after the first (which compiles the shaders).
        if let Some(started) = self.second_frame_at
            && self.frame > 1
        {
            let seconds = started.elapsed().as_secs_f64();
            eprintln!(
                "{} frames of {}x{} in {:.2} s after the first: {:.1} frames/s",
                self.frame - 1,
                self.view_size().0,
                self.view_size().1,
                seconds,
                (self.frame - 1) as f64 / seconds
            );
        }
        if let Some(path) = &options.screenshot {
            self.write_screenshot(path)?;
            eprintln!("wrote {}", path.display());
        }
        println!("{}", self.command());
        Ok(())
    }

    /// The 3D view of the last frame as a PNG.
    fn write_screenshot(&mut self, path: &std::path::Path) -> Result<(), ViewerError> {
        let offscreen = self.offscreen.as_ref().expect("drawn before");
        let (w, h) = (offscreen.texture.width(), offscreen.texture.height());
        let bytes = self
            .renderer
            .read_texture(&offscreen.texture, 4)
            .map_err(|e| ViewerError::Window(format!("cannot read the view back: {e}")))?;
        image::save_buffer(path, &bytes, w, h, image::ColorType::Rgba8)
            .map_err(|e| ViewerError::Window(format!("cannot write {}: {e}", path.display())))
    }

    /// The offscreen view of `size` at `left` in the window (remade when its size changes).
    fn ensure_offscreen(&mut self, left: u32, size: (u32, u32)) {
        if let Some(o) = &mut self.offscreen
            && (o.texture.width(), o.texture.height()) == size
        {
            if o.origin.0 != left {
                o.origin = (left, 0);
                self.blit.write_origin(&self.queue, o.origin);
            }
            return;
        }
        let (texture, view) = crate::view_texture(&self.device, size, "viewer 3D view");
        let bind_group = self.blit.bind_group(&self.device, &view);
        let origin = (left, 0);
        self.blit.write_origin(&self.queue, origin);
        self.offscreen = Some(Offscreen {
            texture,
            view,
            bind_group,
            origin,
        });
    }
}

/// The offscreen view's size (none yet: nothing).
fn offscreen_size(offscreen: &Option<Offscreen>) -> (u32, u32) {
    offscreen
        .as_ref()
        .map_or((0, 0), |o| (o.texture.width(), o.texture.height()))
}

/// The blit of the offscreen view onto the surface.
struct Blit {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    origin: wgpu::Buffer,
}

impl Blit {
    fn new(device: &wgpu::Device, surface_format: wgpu::TextureFormat) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewer blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewer blit"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewer blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let encode = if surface_format.is_srgb() { 0.0 } else { 1.0 };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("viewer blit"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_blit"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_blit"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &[("ENCODE_SRGB", encode)],
                    ..Default::default()
                },
                targets: &[Some(surface_format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let origin = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("viewer blit origin"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            pipeline,
            layout,
            origin,
        }
    }

    fn bind_group(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewer blit"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.origin.as_entire_binding(),
                },
            ],
        })
    }

    fn write_origin(&self, queue: &wgpu::Queue, origin: (u32, u32)) {
        let words = [origin.0, origin.1, 0, 0];
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        queue.write_buffer(&self.origin, 0, &bytes);
    }

    /// Clears the surface and copies the view into its rectangle.
    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        surface: &wgpu::TextureView,
        offscreen: &Offscreen,
        size: (u32, u32),
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("viewer blit"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: surface,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &offscreen.bind_group, &[]);
        pass.set_scissor_rect(offscreen.origin.0, offscreen.origin.1, size.0, size.1);
        pass.draw(0..3, 0..1);
    }
}
