//! `gnomon view`: the interactive viewer ([`gnomon_viewer`]) over this crate's options. The
//! panel's controls are made from the clap definitions of [`DrawArgs`] (no second list), the
//! camera and light come from the same [`ViewArgs`] and [`LightArgs`] as `render`'s, and
//! "copy as command" prints the `gnomon render` command of the frame ([`render_command`]).

use clap::{Args, FromArgMatches};
use glam::DVec3;
use gnomon::{Light, ShadowTechnique, ViewSamples};
use gnomon_render::{COLOR_FORMAT, Renderer, SKY, SceneTarget, ShadowedLight};
use gnomon_scene::{NamedView, ViewLight};
use gnomon_viewer::rig::{CameraRig, SunRig};
use gnomon_viewer::script::Script;
use gnomon_viewer::{
    FrameInfo, FrameReport, Model, Rigs, ViewTarget, ViewerError, ViewerOptions, egui,
};

use crate::CliError;
use crate::args::{LightArgs, LoadedScene, ViewArgs, options_read_by, timed_setup};
use crate::names::Drawn;
use crate::render::DrawArgs;
pub use crate::view_args::ViewCommandArgs;

/// Runs `gnomon view`: everything checked before the window opens.
pub fn run(args: &ViewCommandArgs) -> Result<(), CliError> {
    if let Some(path) = &args.screenshot {
        crate::output::check_outputs(&[("--screenshot", path.as_path(), &["png"])])?;
    }
    if args.frames == Some(0) {
        return Err(CliError::usage("--frames must be at least 1"));
    }
    let script = read_script(args)?;
    let loaded = args.scene.load()?;
    // The bounds as drawn, and with the ground a receiver only for projective shadows, which
    // the panel can pick at any time.
    let scene = crate::rows::RowScene::new(&loaded.scene, true)?;
    let camera = args.view.drawn_camera(&loaded.views, args.size)?;
    let light = args.light.main_light(&args.view, &loaded.views, "view")?;
    let view_light = start_light(&args.light, &args.view, &loaded.views)?;
    check_drawable(args, &loaded, (&camera, &light), scene.bounds())?;
    let rigs = start_rigs(args, &loaded.views, &view_light)?;
    let options = ViewerOptions {
        title: format!("gnomon view: {}", loaded.name),
        size: args.size,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        no_ui: args.no_ui,
        script,
    };
    let panel = OptionPanel::new(&args.draw);
    let shadow_map = args.draw.shadow_map;
    let view_args = args.view.clone();
    let draw = args.draw.clone();
    let split = args.split;
    let result = gnomon_viewer::run(options, move |gpu| {
        let max = gpu.max_texture_size();
        if shadow_map > max {
            return Err(format!(
                "--shadow-map {shadow_map} exceeds this GPU's largest texture, {max} on a side ({})",
                gpu.describe()
            ));
        }
        let renderer = Renderer::new(gpu, &loaded.scene).map_err(|e| e.to_string())?;
        let model = ViewModel {
            loaded,
            scene,
            view: view_args,
            light: view_light,
            start: rigs,
            draw,
            panel,
            samples: None,
            next_technique: None,
            overlay: Overlay::Shaded,
            measure: true,
            measured: None,
            light_view: None,
            thumbnail: None,
            enlarged: false,
            bookmarks: Vec::new(),
            split: split.map(|technique| Split {
                technique,
                divider: 0.5,
            }),
            split_target: None,
            receiver: None,
        };
        Ok((renderer, model))
    });
    result.map_err(|e| match e {
        ViewerError::Window(m) => CliError::runtime(m),
        ViewerError::Model(m) => CliError::usage(m),
    })
}

/// `--script`'s scripted inputs (none without it).
fn read_script(args: &ViewCommandArgs) -> Result<Script, CliError> {
    let Some(path) = &args.script else {
        return Ok(Script::default());
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::usage(format!("cannot read --script {}: {e}", path.display())))?;
    Script::parse(&text).map_err(|e| CliError::usage(format!("{}: {e}", path.display())))
}

/// What the window will draw first, checked before it opens: the technique's parameters
/// and setup, planar shadows' receiver, or the volumes' stencil mode.
fn check_drawable(
    args: &ViewCommandArgs,
    loaded: &LoadedScene,
    (camera, light): (&gnomon::Camera, &Light),
    bounds: &gnomon::SceneBounds,
) -> Result<(), CliError> {
    if let Some(technique) = args.draw.technique.map_technique() {
        let technique = args.draw.params.apply(technique);
        args.draw.params.check_used_by(&[technique])?;
        timed_setup(
            &technique,
            camera,
            light,
            bounds,
            args.draw.shadow_map,
            None,
        )?;
    } else if args.draw.technique == Drawn::Planar {
        crate::render::planar_receiver(&loaded.scene, args.draw.receiver_plane)?;
    } else {
        args.draw.stencil_mode(gnomon_render::StencilMode::ZFail)?;
    }
    args.draw.check_read()?;
    args.draw
        .soft
        .check_area_light(std::slice::from_ref(light))?;
    Ok(())
}

/// The camera's rig (and the sun's, for a directional light) from the options or the named
/// view.
fn start_rigs(
    args: &ViewCommandArgs,
    views: &[NamedView],
    view_light: &ViewLight,
) -> Result<Rigs, CliError> {
    let named = args.view.named(views)?.cloned();
    let up = args
        .view
        .up
        .or(named.as_ref().map(|v| v.up))
        .unwrap_or(DVec3::Y);
    let eye = args.view.eye.or(named.as_ref().map(|v| v.eye));
    let target = args.view.target.or(named.as_ref().map(|v| v.target));
    let (Some(eye), Some(target)) = (eye, target) else {
        return Err(CliError::usage(
            "give --eye and --target, or a named --view",
        ));
    };
    Ok(Rigs {
        camera: CameraRig::new(eye, target, up),
        sun: match view_light {
            ViewLight::Directional { direction } => Some(SunRig::new(*direction, up)),
            _ => None,
        },
    })
}

/// The light the viewer starts from, as given (a named view's, or the options' raw values),
/// so that the printed command gives it bit for bit.
fn start_light(
    light: &LightArgs,
    view: &ViewArgs,
    views: &[NamedView],
) -> Result<ViewLight, CliError> {
    let v = |a: &[f64]| DVec3::new(a[0], a[1], a[2]);
    Ok(match (light.light_dir, light.spot, light.point) {
        (Some(direction), _, _) => ViewLight::Directional { direction },
        (_, Some(s), _) => ViewLight::Spot {
            position: v(&s[0..3]),
            direction: v(&s[3..6]),
            half_angle_degrees: s[6],
            range: s[7],
        },
        (_, _, Some(p)) => ViewLight::Point {
            position: v(&p[0..3]),
            range: p[3],
        },
        _ => match view.named(views)? {
            Some(named) => named.light,
            None => {
                return Err(CliError::usage(
                    "give one of --light-dir, --spot and --point, or a named --view",
                ));
            }
        },
    })
}

/// What `gnomon view` draws.
struct ViewModel {
    loaded: LoadedScene,
    /// The scene's bounds as each technique draws it (projective: the ground a receiver).
    scene: crate::rows::RowScene,
    /// The lens options (the rigs give eye, target and up).
    view: ViewArgs,
    /// The light as it started (a sun's direction comes from the rig).
    light: ViewLight,
    start: Rigs,
    draw: DrawArgs,
    panel: OptionPanel,
    /// The view samples of a still frame, kept while camera and light stay.
    samples: Option<(String, ViewSamples)>,
    /// The last frame's technique (as the panel set it) and the technique its setup hands
    /// the next frame: adaptive cascades keep their count across frames within a margin
    /// ([`gnomon::Technique::for_next_frame`]).
    next_technique: Option<(gnomon::Technique, gnomon::Technique)>,
    /// What the 3D view shows.
    overlay: Overlay,
    /// Whether a frame at rest is measured once (GPU time per pass, the maps as the light
    /// sees them, sampling error).
    measure: bool,
    /// The last measured frame.
    measured: Option<Measured>,
    /// The maps as the light sees them, waiting to become a panel texture.
    light_view: Option<gnomon_render::LightView>,
    thumbnail: Option<egui::TextureHandle>,
    enlarged: bool,
    /// Camera positions saved by the user, by name.
    bookmarks: Vec<(String, Rigs, ViewLight)>,
    /// A second technique right of a divider.
    split: Option<Split>,
    /// The planar shadows' receiver, for the `--receiver-plane` it was made from.
    receiver: Option<(Option<[f64; 4]>, gnomon::planar::PlanarReceiver)>,
    split_target: Option<(wgpu::Texture, wgpu::TextureView)>,
}

/// Split screen: `technique` (default parameters, the left's map, filter and bias) right of
/// `divider` (a fraction of the view's width).
#[derive(Debug, Clone, Copy)]
struct Split {
    technique: Drawn,
    divider: f32,
}

/// What the 3D view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Overlay {
    /// The shaded, shadowed scene (what `render` draws).
    Shaded,
    /// The sampling error: pixels per texel along the worst direction (`render
    /// --error-map`'s heat map).
    ErrorMap,
    /// Against the exact shadow volumes of the same frame: false shadow in red, missed
    /// shadow in blue.
    Wrong,
}

impl Overlay {
    const ALL: [(Overlay, &'static str); 3] = [
        (Overlay::Shaded, "shaded"),
        (Overlay::ErrorMap, "error map (texels per pixel)"),
        (Overlay::Wrong, "wrong against exact volumes"),
    ];
}

/// A frame drawn headless once (a readback) for what the panel shows.
struct Measured {
    key: String,
    timings: gnomon_render::Timings,
    /// Undersampling p99 over the lit pixels facing the light.
    undersampling_p99: Option<f64>,
    /// False and missed shadow as shares of the pixels (wrong overlay only).
    wrong: Option<(f64, f64)>,
}

/// False shadow (the map shadows, the volumes light) and missed shadow, as colours.
const FALSE_SHADOW: [u8; 4] = [230, 40, 40, 255];
const MISSED_SHADOW: [u8; 4] = [40, 90, 240, 255];

/// The shaded `color` with the pixels where the map's `mask` and the exact volumes'
/// `exact` disagree painted (255 lit, 0 shadowed, anything else no geometry), and the shares
/// of false and missed shadow.
fn wrong_image(color: &[u8], mask: &[u8], exact: &[u8]) -> (Vec<u8>, (f64, f64)) {
    let mut out = color.to_vec();
    let (mut false_shadow, mut missed) = (0usize, 0usize);
    for (i, (m, e)) in mask.iter().zip(exact).enumerate() {
        let paint = match (m, e) {
            (0, 255) => {
                false_shadow += 1;
                FALSE_SHADOW
            }
            (255, 0) => {
                missed += 1;
                MISSED_SHADOW
            }
            _ => continue,
        };
        out[i * 4..i * 4 + 4].copy_from_slice(&paint);
    }
    let n = mask.len().max(1) as f64;
    (out, (false_shadow as f64 / n, missed as f64 / n))
}

impl ViewModel {
    /// The frame's named view: the rigs' camera and light with `camera`'s lens (the rigs'
    /// camera, [`ViewModel::camera`]).
    fn named_view(&self, rigs: &Rigs, camera: &gnomon::Camera) -> NamedView {
        let lens = camera.lens();
        let light = match (self.light, rigs.sun) {
            (ViewLight::Directional { .. }, Some(sun)) => ViewLight::Directional {
                direction: sun.direction,
            },
            (light, _) => light,
        };
        NamedView {
            name: "viewer".into(),
            description: String::new(),
            eye: rigs.camera.eye,
            target: rigs.camera.target,
            up: rigs.camera.up,
            fov_y_degrees: lens.fov_y_degrees,
            near: lens.near,
            far: lens.far,
            light,
            more_lights: Vec::new(),
        }
    }

    /// The camera of `rigs`: `render`'s camera from the same options.
    fn camera(&self, rigs: &Rigs, aspect: f64) -> Result<gnomon::Camera, CliError> {
        let mut view = self.view.clone();
        view.eye = Some(rigs.camera.eye);
        view.target = Some(rigs.camera.target);
        view.up = Some(rigs.camera.up);
        view.camera_with_aspect(&self.loaded.views, aspect)
    }

    /// Draws `draw`'s technique into `target`; the `primary` (left) one also measures and
    /// shows the overlays.
    #[allow(clippy::too_many_arguments)]
    fn draw_frame(
        &mut self,
        draw: &DrawArgs,
        primary: bool,
        renderer: &mut Renderer,
        encoder: &mut wgpu::CommandEncoder,
        target: &ViewTarget<'_>,
        rigs: &Rigs,
        info: &FrameInfo,
    ) -> Result<FrameReport, CliError> {
        let (width, height) = info.size;
        let camera = self.camera(rigs, width as f64 / height as f64)?;
        let view = self.named_view(rigs, &camera);
        let light: Light = view.light.light()?;
        let settings = draw.settings(info.size);
        let technique = match draw.technique {
            Drawn::Volumes(_) | Drawn::Planar => {
                let lit = (&camera, &light, &settings);
                return self.draw_exact(draw, renderer, encoder, target, lit, info);
            }
            drawn => draw
                .params
                .apply(drawn.map_technique().expect("a map technique")),
        };
        // What the pixels see, measured once the view rests (a readback) and kept while it
        // does; a moving view's setup casts its samples from the boxes.
        let key = format!("{camera:?} {light:?}");
        let fresh = self.samples.as_ref().is_some_and(|(k, _)| *k == key);
        if !fresh && (info.still || info.exact) {
            self.samples = Some((key.clone(), renderer.view_samples(&camera, &light)?));
        }
        let samples = self
            .samples
            .as_ref()
            .filter(|(k, _)| *k == key)
            .map(|(_, s)| s);
        let bounds = self.scene.prepare(
            renderer,
            draw.technique.map_read() == gnomon_render::MapRead::Coverage,
        )?;
        let stateful = match self.next_technique {
            Some((last, next)) if last == technique => next,
            _ => technique,
        };
        let (setup, setup_us) =
            timed_setup(&stateful, &camera, &light, bounds, draw.shadow_map, samples)?;
        self.next_technique = Some((technique, stateful.for_next_frame(&setup)));
        if draw.tint && setup.maps.len() < 2 {
            return Err(crate::render::tint_needs_two_maps(&technique));
        }
        let measured_from_boxes = samples.is_none();
        let setups = [setup];
        let lights = [light];
        let pairs = ShadowedLight::pairs(&lights, &setups);
        // A headless frame (a readback: overlays every frame, the panel's measures once at
        // rest), before this frame's own passes, which prepare the records again.
        let measure = primary
            && info.panel
            && self.measure
            && info.still
            && self.measured.as_ref().is_none_or(|m| m.key != key);
        if (primary && self.overlay != Overlay::Shaded) || measure {
            let lit = (&camera, pairs.as_slice(), &settings);
            if let Some(image) = self.measure_frame(renderer, lit, key, measure, info.size)? {
                write_view(renderer, target, &image, info.size);
                let notes = vec![format!(
                    "{}: {} maps",
                    technique.name(),
                    setups[0].maps.len()
                )];
                return Ok(FrameReport { setup_us, notes });
            }
        }
        renderer.prepare(&camera, &pairs, &settings)?;
        renderer.encode_shadow_maps(encoder);
        renderer.encode_scene(
            encoder,
            &SceneTarget {
                view: target.view,
                format: COLOR_FORMAT,
                width,
                height,
                sample_count: 1,
                resolve_target: None,
                clear: Some(SKY),
            },
        )?;
        let notes = map_notes(renderer, &technique, &setups[0], measured_from_boxes);
        Ok(FrameReport { setup_us, notes })
    }

    /// The exact techniques (the volumes, their soft shadows, planar shadows), drawn into
    /// the view.
    fn draw_exact(
        &mut self,
        draw: &DrawArgs,
        renderer: &mut Renderer,
        encoder: &mut wgpu::CommandEncoder,
        target: &ViewTarget<'_>,
        (camera, light, settings): (&gnomon::Camera, &Light, &gnomon_render::RenderSettings),
        info: &FrameInfo,
    ) -> Result<FrameReport, CliError> {
        self.scene.restore(renderer)?;
        let lights = std::slice::from_ref(light);
        let (timings, stats) = match draw.technique {
            Drawn::Volumes(named) => {
                let mode = draw.stencil_mode(named)?;
                let scene_box = self.scene.bounds().scene_box();
                if let Some(clusters) = draw.soft.area_clusters(lights, &scene_box)? {
                    // Soft shadows: the cluster's frames averaged on the CPU.
                    let soft = renderer.render_soft_volumes(camera, &clusters, settings, mode)?;
                    write_view(renderer, target, &soft.frame.color, info.size);
                    let t = soft.frame.timings;
                    return Ok(FrameReport {
                        setup_us: 0.0,
                        notes: vec![format!(
                            "soft volumes: {} samples, {} volume triangles, {:.1} ms",
                            clusters[0].len(),
                            soft.triangles,
                            t.shadow_pass_ms + t.main_pass_ms
                        )],
                    });
                }
                renderer.draw_volumes_lit_by(camera, lights, settings, mode)?
            }
            _ => {
                let receiver = self.planar_receiver(draw.receiver_plane)?;
                renderer.draw_planar_lit_by(camera, lights, receiver, settings)?
            }
        };
        let Some(color) = renderer.frame_color() else {
            return Err(CliError::runtime("the exact frame has no colour target"));
        };
        encoder.copy_texture_to_texture(
            color.as_image_copy(),
            target.texture.as_image_copy(),
            color.size(),
        );
        let geometry = if draw.technique == Drawn::Planar {
            "flattened"
        } else {
            "volume"
        };
        Ok(FrameReport {
            setup_us: 0.0,
            notes: vec![
                format!(
                    "{}: {} {geometry} triangles",
                    draw.technique.name(),
                    stats.triangles,
                ),
                format!(
                    "stencil {:.2} ms, shading {:.2} ms ({})",
                    timings.shadow_pass_ms,
                    timings.main_pass_ms,
                    timings.source.name()
                ),
            ],
        })
    }

    /// Planar shadows' receiver, made again only when the receiver plane changes.
    fn planar_receiver(
        &mut self,
        plane: Option<[f64; 4]>,
    ) -> Result<&gnomon::planar::PlanarReceiver, CliError> {
        if self
            .receiver
            .as_ref()
            .is_none_or(|(kept, _)| *kept != plane)
        {
            let receiver = crate::render::planar_receiver(&self.loaded.scene, plane)?;
            self.receiver = Some((plane, receiver));
        }
        let (_, receiver) = self.receiver.as_ref().expect("made above");
        Ok(receiver)
    }

    /// A measured headless frame: the panel's figures once at rest (`measure`), and the
    /// overlay's image where the view shows one.
    fn measure_frame(
        &mut self,
        renderer: &mut Renderer,
        (camera, pairs, settings): (
            &gnomon::Camera,
            &[ShadowedLight<'_>],
            &gnomon_render::RenderSettings,
        ),
        key: String,
        measure: bool,
        (width, height): (u32, u32),
    ) -> Result<Option<Vec<u8>>, CliError> {
        let frame = renderer.render_lights(
            camera,
            pairs,
            &gnomon_render::RenderSettings {
                light_view: measure,
                metrics: true,
                ..*settings
            },
        )?;
        let metrics = frame.metrics.as_ref().expect("asked for");
        let p99 = crate::heatmap::percentiles(metrics, &metrics.undersampling)["p99"].as_f64();
        let mut measured = Measured {
            key,
            timings: frame.timings,
            undersampling_p99: p99,
            wrong: None,
        };
        let image = match self.overlay {
            Overlay::Shaded => None,
            Overlay::ErrorMap => Some(crate::heatmap::draw(metrics, width, height)),
            Overlay::Wrong => {
                // The exact shadows of the scene as it is (its ground casting).
                self.scene.restore(renderer)?;
                let exact = renderer.render_volumes_lit_by(
                    camera,
                    std::slice::from_ref(pairs[0].light),
                    settings,
                    gnomon_render::StencilMode::ZFail,
                )?;
                let (image, shares) = wrong_image(&frame.color, &frame.mask, &exact.frame.mask);
                measured.wrong = Some(shares);
                Some(image)
            }
        };
        if measure {
            self.light_view = frame.light_view;
        }
        if measure || self.measured.is_none() {
            self.measured = Some(measured);
        } else if let (Some(m), Some(shares)) = (&mut self.measured, measured.wrong) {
            m.wrong = Some(shares);
        }
        Ok(image)
    }
}

/// The panel's notes on a map frame: its maps, casters drawn, samples, fallbacks and the
/// setup's diagnostics.
fn map_notes(
    renderer: &Renderer,
    technique: &gnomon::Technique,
    setup: &gnomon::ShadowSetup,
    samples_from_boxes: bool,
) -> Vec<String> {
    let drawn: Vec<String> = renderer
        .casters_drawn()
        .iter()
        .map(|n| n.to_string())
        .collect();
    let mut notes = vec![
        format!(
            "{}: {} map{}, casters drawn {}",
            technique.name(),
            setup.maps.len(),
            if setup.maps.len() == 1 { "" } else { "s" },
            drawn.join(" + ")
        ),
        if samples_from_boxes {
            "view samples: from the boxes (the view moves)".to_string()
        } else {
            "view samples: measured".to_string()
        },
    ];
    let d = &setup.diagnostics;
    let fallbacks: Vec<&str> = d.fallbacks.iter().map(|f| f.name()).collect();
    if !fallbacks.is_empty() {
        notes.push(format!("fallbacks: {}", fallbacks.join(", ")));
    }
    notes.push(format!(
        "gamma {:.1} deg, receivers {}, casters {} ({} culled), B {} vertices{}{}",
        d.gamma_degrees,
        d.visible_receivers,
        d.relevant_casters,
        d.culled_casters,
        d.focus_body_vertices,
        d.warp_strength
            .map(|w| format!(", warp strength {w:.2}"))
            .unwrap_or_default(),
        if d.cube_faces_skipped > 0 {
            format!(", {} cube faces skipped", d.cube_faces_skipped)
        } else {
            String::new()
        }
    ));
    notes
}

/// Writes an RGBA image of `size` into the view's texture (before the frame's passes run).
fn write_view(renderer: &Renderer, target: &ViewTarget<'_>, rgba: &[u8], size: (u32, u32)) {
    renderer.gpu().queue.write_texture(
        target.texture.as_image_copy(),
        rgba,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size.0 * 4),
            rows_per_image: Some(size.1),
        },
        target.texture.size(),
    );
}

impl ViewModel {
    /// The panel's view, light and measurement controls.
    fn scene_panel(&mut self, ui: &mut egui::Ui, rigs: &mut Rigs) {
        // Named views and bookmarks: the camera and light they give.
        let mut chosen: Option<(Rigs, ViewLight, Option<String>)> = None;
        ui.horizontal(|ui| {
            egui::ComboBox::from_label("view")
                .selected_text(self.view.view.clone().unwrap_or_else(|| "(options)".into()))
                .show_ui(ui, |ui| {
                    for v in &self.loaded.views {
                        if ui.selectable_label(false, &v.name).clicked() {
                            let sun = match v.light {
                                ViewLight::Directional { direction } => {
                                    Some(SunRig::new(direction, v.up))
                                }
                                _ => None,
                            };
                            let rigs = Rigs {
                                camera: CameraRig::new(v.eye, v.target, v.up),
                                sun,
                            };
                            chosen = Some((rigs, v.light, Some(v.name.clone())));
                        }
                    }
                    for (name, rigs, light) in &self.bookmarks {
                        if ui.selectable_label(false, name).clicked() {
                            chosen = Some((*rigs, *light, self.view.view.clone()));
                        }
                    }
                });
            if ui.button("Bookmark").clicked() {
                let name = format!("bookmark {}", self.bookmarks.len() + 1);
                self.bookmarks.push((name, *rigs, self.light));
            }
        });
        if let Some((new, light, name)) = chosen {
            *rigs = new;
            self.light = light;
            if name != self.view.view {
                // A named view's lens; the options' lens stays with a bookmark.
                self.view = ViewArgs {
                    view: name,
                    eye: None,
                    target: None,
                    up: None,
                    fov: None,
                    near: None,
                    far: None,
                    aspect: None,
                };
            }
        }
        match (&mut self.light, &mut rigs.sun) {
            (ViewLight::Directional { .. }, Some(sun)) => {
                ui.label("Sun (middle drag, arrow keys)");
                let (mut azimuth, mut elevation) = (sun.azimuth_degrees(), sun.elevation_degrees());
                let a = ui.add(egui::Slider::new(&mut azimuth, -180.0..=180.0).text("azimuth"));
                let e = ui.add(egui::Slider::new(&mut elevation, -89.9..=89.9).text("elevation"));
                if a.changed() || e.changed() {
                    sun.set(azimuth, elevation);
                }
            }
            (
                ViewLight::Spot {
                    position,
                    direction,
                    ..
                },
                _,
            ) => {
                ui.label("Spot light: position, aim");
                drag_vec3(ui, position, 0.5);
                drag_vec3(ui, direction, 0.01);
            }
            (ViewLight::Point { position, .. }, _) => {
                ui.label("Point light: position");
                drag_vec3(ui, position, 0.5);
            }
            _ => {}
        }
        ui.separator();
    }

    /// The panel's split screen, overlay and measurement controls.
    fn measure_panel(&mut self, ui: &mut egui::Ui) {
        let mut split = self.split.is_some();
        ui.checkbox(&mut split, "split screen: a second technique on the right");
        match (split, &mut self.split) {
            (false, s) => *s = None,
            (true, None) => {
                self.split = Some(Split {
                    technique: Drawn::Volumes(gnomon_render::StencilMode::ZFail),
                    divider: 0.5,
                });
            }
            (true, Some(s)) => {
                egui::ComboBox::from_label("right")
                    .selected_text(s.technique.name())
                    .show_ui(ui, |ui| {
                        for name in crate::names::known(true).split(", ") {
                            if let Ok(drawn) = Drawn::parse(name) {
                                ui.selectable_value(&mut s.technique, drawn, name);
                            }
                        }
                    });
                ui.add(egui::Slider::new(&mut s.divider, 0.05..=0.95).text("divider"));
            }
        }
        egui::ComboBox::from_label("show")
            .selected_text(
                Overlay::ALL
                    .iter()
                    .find(|(o, _)| *o == self.overlay)
                    .map_or("", |(_, n)| n),
            )
            .show_ui(ui, |ui| {
                for (overlay, name) in Overlay::ALL {
                    ui.selectable_value(&mut self.overlay, overlay, name);
                }
            });
        if self.overlay != Overlay::Shaded {
            ui.label("(measured every frame: a readback each)");
        }
        ui.checkbox(
            &mut self.measure,
            "measure at rest (GPU times, maps, error)",
        );
        if let Some(m) = &self.measured {
            ui.label(format!(
                "GPU: shadow pass {:.2} ms, main pass {:.2} ms ({})",
                m.timings.shadow_pass_ms,
                m.timings.main_pass_ms,
                m.timings.source.name()
            ));
            if let Some(p99) = m.undersampling_p99 {
                ui.label(format!("undersampling p99: {p99:.2} pixels per texel"));
            }
            if let Some((f, missed)) = m.wrong {
                ui.label(format!(
                    "wrong: {:.3}% false shadow (red), {:.3}% missed (blue)",
                    f * 100.0,
                    missed * 100.0
                ));
            }
        }
        if let Some(view) = self.light_view.take() {
            let image = egui::ColorImage::from_rgba_unmultiplied(
                [view.width as usize, view.height as usize],
                &view.rgba,
            );
            self.thumbnail = Some(ui.ctx().load_texture(
                "light view",
                image,
                egui::TextureOptions::LINEAR,
            ));
        }
        if let Some(texture) = &self.thumbnail {
            ui.label("The maps as the light sees them (click to enlarge)");
            let [w, h] = texture.size();
            let height = 200.0f32;
            let size = egui::vec2(height * w as f32 / h as f32, height);
            let size = size * (ui.available_width() / size.x).min(1.0);
            let response =
                ui.add(egui::Image::new((texture.id(), size)).sense(egui::Sense::click()));
            if response.clicked() {
                self.enlarged = !self.enlarged;
            }
            if self.enlarged {
                let mut open = true;
                egui::Window::new("Shadow maps")
                    .open(&mut open)
                    .show(ui.ctx(), |ui| {
                        let side = 640.0f32;
                        let size = egui::vec2(side * w as f32 / h as f32, side);
                        ui.image((texture.id(), size));
                    });
                self.enlarged = open;
            }
        }
        ui.separator();
    }
}

/// Copies the columns of `from` from `x` on over `to`.
fn copy_right_of(
    encoder: &mut wgpu::CommandEncoder,
    from: &wgpu::Texture,
    to: &wgpu::Texture,
    x: u32,
) {
    let size = to.size();
    let at = |texture| wgpu::TexelCopyTextureInfo {
        texture,
        mip_level: 0,
        origin: wgpu::Origin3d { x, y: 0, z: 0 },
        aspect: wgpu::TextureAspect::All,
    };
    encoder.copy_texture_to_texture(
        at(from),
        at(to),
        wgpu::Extent3d {
            width: size.width - x,
            height: size.height,
            depth_or_array_layers: 1,
        },
    );
}

/// Two white columns of `texture` from `x` on.
fn draw_divider(gpu: &gnomon_render::Gpu, texture: &wgpu::Texture, x: u32) {
    let height = texture.size().height;
    let white = vec![255u8; 2 * 4 * height as usize];
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x, y: 0, z: 0 },
            aspect: wgpu::TextureAspect::All,
        },
        &white,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8),
            rows_per_image: Some(height),
        },
        wgpu::Extent3d {
            width: 2,
            height,
            depth_or_array_layers: 1,
        },
    );
}

/// Three drag values for a vector.
fn drag_vec3(ui: &mut egui::Ui, v: &mut DVec3, speed: f64) {
    ui.horizontal(|ui| {
        ui.add(egui::DragValue::new(&mut v.x).speed(speed));
        ui.add(egui::DragValue::new(&mut v.y).speed(speed));
        ui.add(egui::DragValue::new(&mut v.z).speed(speed));
    });
}

impl Model for ViewModel {
    fn rigs(&self) -> Rigs {
        self.start
    }

    fn draw(
        &mut self,
        renderer: &mut Renderer,
        encoder: &mut wgpu::CommandEncoder,
        target: &ViewTarget<'_>,
        rigs: &Rigs,
        info: &FrameInfo,
    ) -> Result<FrameReport, String> {
        let draw = self.draw.clone();
        let mut report = self
            .draw_frame(&draw, true, renderer, encoder, target, rigs, info)
            .map_err(|e| e.message)?;
        let Some(split) = self.split else {
            return Ok(report);
        };
        // The right of the divider: the second technique, drawn after the first's passes are
        // submitted (each prepares the frame's records), then copied over the first's.
        let gpu = renderer.gpu().clone();
        let first = std::mem::replace(
            encoder,
            gpu.device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("viewer split"),
                }),
        );
        gpu.queue.submit([first.finish()]);
        let size = target.texture.size();
        if self
            .split_target
            .as_ref()
            .is_none_or(|(t, _)| t.size() != size)
        {
            let (texture, view) = gnomon_viewer::view_texture(
                &gpu.device,
                (size.width, size.height),
                "viewer split view",
            );
            self.split_target = Some((texture, view));
        }
        let (texture, view) = self.split_target.take().expect("made above");
        let second = DrawArgs {
            technique: split.technique,
            params: crate::args::TechniqueParams::default(),
            tint: false,
            ..self.draw.clone()
        };
        let drawn = self.draw_frame(
            &second,
            false,
            renderer,
            encoder,
            &ViewTarget {
                texture: &texture,
                view: &view,
            },
            rigs,
            info,
        );
        let x = ((split.divider * size.width as f32).round() as u32).min(size.width - 1);
        if drawn.is_ok() {
            copy_right_of(encoder, &texture, target.texture, x);
        }
        self.split_target = Some((texture, view));
        // The divider: two white columns left of the copy (after the left's passes, which
        // were submitted; the copy does not reach them).
        if x >= 2 {
            draw_divider(&gpu, target.texture, x - 2);
        }
        match drawn {
            Ok(right) => {
                report.setup_us += right.setup_us;
                report
                    .notes
                    .extend(right.notes.into_iter().map(|n| format!("right: {n}")));
            }
            Err(e) => report.notes.push(format!("right: {}", e.message)),
        }
        Ok(report)
    }

    fn panel(&mut self, ui: &mut egui::Ui, rigs: &mut Rigs) {
        self.scene_panel(ui, rigs);
        if let Some(draw) = self.panel.show(ui) {
            self.draw = draw;
        }
        ui.separator();
        self.measure_panel(ui);
    }

    fn command(&self, rigs: &Rigs, size: (u32, u32)) -> String {
        let aspect = size.0 as f64 / size.1 as f64;
        let view = match self.camera(rigs, aspect) {
            Ok(camera) => self.named_view(rigs, &camera),
            Err(e) => return format!("# no command: {}", e.message),
        };
        let technique = self
            .draw
            .technique
            .map_technique()
            .map(|t| self.draw.params.apply(t));
        let mut extra = self.draw.non_default_flags();
        if let Some(aspect) = self.view.aspect {
            extra += &format!(" --aspect {aspect}");
        }
        if let Drawn::Volumes(mode) = self.draw.technique
            && self.draw.stencil.is_none()
            && let Some(name) = crate::render::stencil_name(mode)
        {
            extra += &format!(" --stencil {name}");
        }
        crate::args::render_command(
            &self.loaded.options,
            &view,
            (technique.as_ref(), self.draw.technique.name()),
            &self.draw.params,
            self.draw.shadow_map,
            size,
            &extra,
        )
    }
}

/// The panel's controls over [`DrawArgs`], made from its clap definitions: a checkbox per
/// flag, a list per option with possible values (the technique's from [`crate::names`]), a
/// text field per other option; each edit parses the whole set again, as the command line
/// would, and shows its error instead of applying it.
struct OptionPanel {
    command: clap::Command,
    /// The technique parameters' own definitions, to parse the panel's parameter fields
    /// alone.
    params_command: clap::Command,
    fields: Vec<Field>,
    error: Option<String>,
}

struct Field {
    id: String,
    long: String,
    help: String,
    kind: FieldKind,
    /// A technique parameter (`TechniqueParams`).
    is_param: bool,
}

enum FieldKind {
    Flag(bool),
    Choice(Vec<String>, String),
    Text(String),
}

impl OptionPanel {
    fn new(draw: &DrawArgs) -> Self {
        let command = DrawArgs::augment_args(clap::Command::new("view").no_binary_name(true));
        let params_command = crate::args::TechniqueParams::augment_args(
            clap::Command::new("params").no_binary_name(true),
        );
        let matches = command
            .clone()
            .try_get_matches_from(draw_tokens(draw))
            .expect("a parsed DrawArgs parses again");
        let fields = command
            .get_arguments()
            .filter_map(|arg| {
                let long = arg.get_long()?.to_string();
                let id = arg.get_id().to_string();
                let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
                let given = matches
                    .get_raw(&id)
                    .and_then(|mut v| v.next())
                    .map(|v| v.to_string_lossy().into_owned());
                let kind = if !arg.get_action().takes_values() {
                    FieldKind::Flag(matches.get_flag(&id))
                } else {
                    let values: Vec<String> = if id == "technique" {
                        crate::names::known(true)
                            .split(", ")
                            .map(str::to_string)
                            .collect()
                    } else {
                        arg.get_possible_values()
                            .iter()
                            .map(|v| v.get_name().to_string())
                            .collect()
                    };
                    let default = arg
                        .get_default_values()
                        .first()
                        .map(|v| v.to_string_lossy().into_owned());
                    let value = given.or(default).unwrap_or_default();
                    if values.is_empty() {
                        FieldKind::Text(value)
                    } else {
                        FieldKind::Choice(values, value)
                    }
                };
                let is_param = params_command
                    .get_arguments()
                    .any(|a| a.get_id() == id.as_str());
                Some(Field {
                    id,
                    long,
                    help,
                    kind,
                    is_param,
                })
            })
            .collect();
        Self {
            command,
            params_command,
            fields,
            error: None,
        }
    }

    /// `field` as a command-line token (`None`: an unset flag or an empty value).
    fn token(field: &Field) -> Option<String> {
        match &field.kind {
            FieldKind::Flag(true) => Some(format!("--{}", field.long)),
            FieldKind::Flag(false) => None,
            FieldKind::Choice(_, v) | FieldKind::Text(v) => {
                (!v.trim().is_empty()).then(|| format!("--{}={}", field.long, v.trim()))
            }
        }
    }

    /// Whether each field applies to the technique the panel names: its parameters where it
    /// reads them (as the panel's other parameters make it: a cascade's fit decides which fit
    /// parameters show), the map's options for map techniques, the counting for volumes.
    fn visible(&self) -> Vec<bool> {
        let technique = self.fields.iter().find_map(|f| match &f.kind {
            FieldKind::Choice(_, v) if f.id == "technique" => Drawn::parse(v).ok(),
            _ => None,
        });
        let read = technique.and_then(|d| d.map_technique()).map(|t| {
            let tokens = self
                .fields
                .iter()
                .filter(|f| f.is_param)
                .filter_map(Self::token);
            let applied = self
                .params_command
                .clone()
                .try_get_matches_from(tokens)
                .ok()
                .and_then(|m| crate::args::TechniqueParams::from_arg_matches(&m).ok())
                .map_or(t, |p| p.apply(t));
            options_read_by(&applied)
        });
        let pcss = self
            .fields
            .iter()
            .any(|f| f.id == "pcf" && matches!(&f.kind, FieldKind::Choice(_, v) if v == "pcss"));
        self.fields
            .iter()
            .map(|f| shown(f, technique.as_ref(), read.as_deref(), pcss))
            .collect()
    }

    /// The fields' values as a command line, those the technique does not read left out.
    fn tokens(&self) -> Vec<String> {
        self.fields
            .iter()
            .zip(self.visible())
            .filter(|(_, visible)| *visible)
            .filter_map(|(f, _)| Self::token(f))
            .collect()
    }

    /// Draws the controls; the new options where an edit parsed.
    fn show(&mut self, ui: &mut egui::Ui) -> Option<DrawArgs> {
        let mut changed = false;
        let visible = self.visible();
        egui::Grid::new("options").num_columns(2).show(ui, |ui| {
            for (field, visible) in self.fields.iter_mut().zip(visible) {
                if !visible {
                    continue;
                }
                ui.label(format!("--{}", field.long))
                    .on_hover_text(&field.help);
                match &mut field.kind {
                    FieldKind::Flag(on) => {
                        changed |= ui.checkbox(on, "").on_hover_text(&field.help).changed();
                    }
                    FieldKind::Choice(values, value) => {
                        egui::ComboBox::from_id_salt(&field.id)
                            .selected_text(value.as_str())
                            .show_ui(ui, |ui| {
                                for v in values.iter() {
                                    changed |= ui.selectable_value(value, v.clone(), v).changed();
                                }
                            });
                    }
                    FieldKind::Text(text) => {
                        let response = ui.add(
                            egui::TextEdit::singleline(text)
                                .desired_width(120.0)
                                .hint_text("default"),
                        );
                        changed |=
                            response.lost_focus() || (response.changed() && !response.has_focus());
                        response.on_hover_text(&field.help);
                    }
                }
                ui.end_row();
            }
        });
        if let Some(error) = &self.error {
            ui.colored_label(egui::Color32::from_rgb(220, 60, 60), error);
        }
        if !changed {
            return None;
        }
        match self.parse() {
            Ok(draw) => {
                self.error = None;
                Some(draw)
            }
            Err(e) => {
                self.error = Some(e);
                None
            }
        }
    }

    /// The fields parsed as the command line parses them, then checked as `render` checks.
    fn parse(&self) -> Result<DrawArgs, String> {
        let matches = self
            .command
            .clone()
            .try_get_matches_from(self.tokens())
            .map_err(|e| e.to_string().lines().next().unwrap_or_default().to_string())?;
        let draw = DrawArgs::from_arg_matches(&matches).map_err(|e| e.to_string())?;
        if let Some(technique) = draw.technique.map_technique() {
            let technique = draw.params.apply(technique);
            draw.params.check_used_by(&[technique]).map_err(|e| e.0)?;
        }
        Ok(draw)
    }
}

/// Whether `field` applies to `technique`: a parameter where it is among `read` (the options
/// the map technique reads), the map's options for map techniques (the area light too where
/// they filter with PCSS), the counting and the area light for volumes, the receiver plane
/// for planar shadows.
fn shown(field: &Field, technique: Option<&Drawn>, read: Option<&[&str]>, pcss: bool) -> bool {
    let id = field.id.as_str();
    match technique {
        None => id == "technique",
        Some(Drawn::Volumes(_)) => {
            ["technique", "stencil", "area_light", "area_samples"].contains(&id)
        }
        Some(Drawn::Planar) => id == "technique" || id == "receiver_plane",
        Some(Drawn::Map(_)) if id == "area_light" => pcss,
        Some(Drawn::Map(_) | Drawn::Read(_)) => {
            if ["stencil", "receiver_plane", "area_light", "area_samples"].contains(&id) {
                false
            } else if field.is_param {
                read.is_some_and(|r| r.contains(&format!("--{}", field.long).as_str()))
            } else {
                true
            }
        }
    }
}

/// `draw` as the command-line tokens that give it.
fn draw_tokens(draw: &DrawArgs) -> Vec<String> {
    let mut line = format!(
        "--technique {} --shadow-map {}",
        draw.technique.name(),
        draw.shadow_map
    );
    for (_, flag) in draw.params.flags() {
        line += &format!(" {flag}");
    }
    line += &draw.non_default_flags();
    line.split_whitespace().map(str::to_string).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(line: &str) -> DrawArgs {
        let command = DrawArgs::augment_args(clap::Command::new("t").no_binary_name(true));
        let matches = command
            .try_get_matches_from(line.split_whitespace())
            .unwrap();
        DrawArgs::from_arg_matches(&matches).unwrap()
    }

    #[test]
    fn the_panel_gives_back_the_options_it_was_made_from() {
        for line in [
            "--technique lispsm --lispsm-n 3.5 --pcf 5x5 --bias-constant 0.02",
            "--technique cascades --cascades 3 --cascade-fit tsm --tsm-focus 0.5 --tint",
            "--technique volumes-z-pass",
            "--technique focused --shadow-map 1024 --normal-offset 2",
        ] {
            let draw = parsed(line);
            let panel = OptionPanel::new(&draw);
            let again = panel.parse().unwrap();
            assert_eq!(draw_tokens(&again), draw_tokens(&draw), "{line}");
        }
    }

    #[test]
    fn the_panel_shows_only_what_the_technique_reads() {
        let panel = OptionPanel::new(&parsed("--technique lispsm"));
        let visible: Vec<&str> = panel
            .fields
            .iter()
            .zip(panel.visible())
            .filter(|(_, v)| *v)
            .map(|(f, _)| f.long.as_str())
            .collect();
        assert!(visible.contains(&"lispsm-n"), "{visible:?}");
        assert!(visible.contains(&"pcf"));
        assert!(!visible.contains(&"tsm-xi"));
        assert!(!visible.contains(&"stencil"));
    }

    #[test]
    fn wrong_pixels_are_painted_and_counted() {
        let color = vec![10u8; 4 * 4];
        // Lit by both, false shadow, missed shadow, no geometry.
        let (image, (false_shadow, missed)) =
            wrong_image(&color, &[255, 0, 255, 128], &[255, 255, 0, 128]);
        assert_eq!(&image[0..4], &[10; 4]);
        assert_eq!(&image[4..8], &FALSE_SHADOW);
        assert_eq!(&image[8..12], &MISSED_SHADOW);
        assert_eq!(&image[12..16], &[10; 4]);
        assert_eq!((false_shadow, missed), (0.25, 0.25));
    }

    #[test]
    fn a_bad_edit_is_refused_with_the_command_lines_error() {
        let mut panel = OptionPanel::new(&parsed("--technique focused"));
        for field in &mut panel.fields {
            if let (FieldKind::Text(text), "shadow-map") = (&mut field.kind, field.long.as_str()) {
                *text = "lots".into();
            }
        }
        let error = panel.parse().unwrap_err();
        assert!(error.contains("shadow-map"), "{error}");
    }
}
