//! `gnomon compare`: every technique against the exact shadow volumes, view by view: an image
//! grid (frame, mask errors, sampling error map) and a table per view (wrong pixels, the
//! sampling error's percentiles, setup and frame times), as Markdown and JSON.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use gnomon_render::{
    Filter, Frame, MaskErrors, PixelVerdict, RenderSettings, StencilMode, SureErrors,
};
use serde_json::{Value, json};

use crate::args::{SceneArgs, SuiteArgs, TechniqueParams, ViewListArgs};
use crate::render::{open_renderer, parse_size, write_png, write_text};
use crate::rows::light_setups;
use crate::{CliError, heatmap};

/// The largest frame side `compare` takes (its grids hold many frames).
const MAX_COMPARE_SIZE: u32 = 4096;
/// `gnomon compare`.
#[derive(Debug, Clone, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    // With --suite: a report per scene (compare: a folder of its name under --out; bench:
    // views named SCENE/VIEW) and a summary over the suite.
    #[command(flatten)]
    pub suite: SuiteArgs,
    #[command(flatten)]
    pub views: ViewListArgs,
    /// The shadow-map techniques: `all` (every map technique) or names, comma-separated, and
    /// `projective`, `object-id`, `id-depth` and `planar` (planar shadows on the ground); the exact shadow volumes are
    /// always drawn: they are the reference.
    #[arg(long, value_delimiter = ',', default_value = "all")]
    pub techniques: Vec<String>,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Shadow-map resolution in texels.
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// The maps' filter; with `--area-light R` each view also gets the soft shadows of its
    /// area lights as a cluster of --area-samples hard lights with exact volumes, and each
    /// row read by depth the penumbra error of its filter against them (the mean absolute
    /// difference of the shadow factor over the union of both penumbrae): PCSS's with
    /// `--pcf pcss`, the hard shadows' with another filter.
    #[command(flatten)]
    pub soft: crate::render::SoftArgs,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", allow_hyphen_values = true, value_parser = parse_size)]
    pub size: (u32, u32),
    /// Where to write the report (index.md, report.json, one grid image per view).
    #[arg(long, default_value = "gnomon-compare")]
    pub out: PathBuf,
}

/// What `compare` draws against the exact volumes: the map techniques' rows, and planar
/// shadows where asked.
struct Rows<'a> {
    techniques: &'a [crate::rows::Row],
    planar: bool,
}

/// Colours of the mask-error image.
const FALSE_SHADOW: [u8; 3] = [230, 30, 30];
const MISSED_SHADOW: [u8; 3] = [30, 110, 245];

/// Compares a map's mask with the exact one on the pixels with N.L > 0.1 (`n_dot_l`, the
/// view's), and draws the frame in grey with false shadow in red and missed shadow in blue.
fn mask_errors(map: &Frame, n_dot_l: &[f32], exact: &Frame) -> (MaskErrors, Vec<u8>) {
    mask_errors_of(&map.color, &map.mask, n_dot_l, &exact.mask)
}

/// [`mask_errors`] over a frame's colour and mask and the exact mask.
pub(crate) fn mask_errors_of(
    color: &[u8],
    mask: &[u8],
    n_dot_l: &[f32],
    exact: &[u8],
) -> (MaskErrors, Vec<u8>) {
    let mut errors = MaskErrors::default();
    let mut image = Vec::with_capacity(color.len());
    for (i, rgba) in color.chunks_exact(4).enumerate() {
        let grey = (0.3 * rgba[0] as f64 + 0.59 * rgba[1] as f64 + 0.11 * rgba[2] as f64) as u8;
        let verdict = PixelVerdict::of(mask[i], exact[i], n_dot_l[i]);
        errors.add(verdict);
        let rgb = match verdict {
            PixelVerdict::FalseShadow => FALSE_SHADOW,
            PixelVerdict::MissedShadow => MISSED_SHADOW,
            _ => [grey / 2 + 64; 3],
        };
        image.extend_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
    }
    (errors, image)
}

/// One row of a scene's summary: the technique, its mean and worst wrong-pixel share over
/// the views, its mean undersampling p99, mean penumbra error (PCSS), mean setup (us) and
/// frame (ms).
pub(crate) struct SummaryRow {
    label: String,
    wrong: Vec<f64>,
    p99: Vec<f64>,
    penumbra: Vec<f64>,
    setup_us: Vec<f64>,
    frame_ms: Vec<f64>,
}

/// `x` with two decimals, or `-` where it is not a number (a row without maps has no
/// sampling error).
fn two_places(x: f64) -> String {
    if x.is_nan() {
        "-".into()
    } else {
        format!("{x:.2}")
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Runs `gnomon compare`.
pub fn run(args: &CompareArgs) -> Result<(), CliError> {
    let started = Instant::now();
    // Planar shadows are a row of their own (no maps); the rest are map techniques.
    let planar = args
        .techniques
        .iter()
        .any(|t| t.trim() == crate::names::PLANAR);
    let names: Vec<String> = args
        .techniques
        .iter()
        .filter(|t| t.trim() != crate::names::PLANAR)
        .cloned()
        .collect();
    let techniques = crate::rows::rows(&names, &args.params, args.shadow_map, true)?;
    if techniques.is_empty() && !planar {
        return Err(CliError::usage("nothing to compare"));
    }
    if args.soft.pcss() && args.soft.area_light.is_none() {
        return Err(CliError::usage(
            "--pcf pcss softens by the lights' size: give --area-light R (degrees for a sun, \
             whose is 0.27; world units for spot and point lights)",
        ));
    }
    let rows = Rows {
        techniques: &techniques,
        planar,
    };
    // A view's grid holds three frames per technique and the volumes: larger frames make
    // grids too large to hold and write.
    if args.size.0 > MAX_COMPARE_SIZE || args.size.1 > MAX_COMPARE_SIZE {
        return Err(CliError::usage(format!(
            "--size {}x{}: compare's grids take frames of at most {MAX_COMPARE_SIZE} on a side",
            args.size.0, args.size.1
        )));
    }
    let Some(folder) = &args.suite.suite else {
        let loaded = args.scene.load()?;
        compare_scene(args, &rows, &loaded, &args.out, started)?;
        crate::say!("wrote {}", args.out.join("index.md").display());
        return Ok(());
    };
    compare_suite(args, &rows, folder, started)
}

/// `compare --suite`: a report per scene in a folder of its name, and a summary over them.
fn compare_suite(
    args: &CompareArgs,
    rows: &Rows<'_>,
    folder: &std::path::Path,
    started: Instant,
) -> Result<(), CliError> {
    if args.views.views.iter().any(|v| v.trim() != "all") {
        return Err(CliError::usage(
            "--suite compares every view of each scene; drop --views",
        ));
    }
    // Every scene file loaded before any work: a missing model fails at once.
    let scenes = crate::args::suite_scenes(folder)?;
    let mut markdown = format!(
        "# gnomon compare: the suite in {}\n\nEach scene's report is in its folder; the \
         figures are means over its named views ({}x{} pixels, {}x{} shadow maps). Wrong \
         pixels against the exact shadow volumes; undersampling p99 in pixels per texel.\n\n\
         | scene | views | technique | mean wrong pixels | worst view | mean undersampling p99 | \
         setup (us) | frame (ms) |\n| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |\n",
        folder.display(),
        args.size.0,
        args.size.1,
        args.shadow_map,
        args.shadow_map
    );
    let mut json_scenes = Vec::new();
    for (stem, loaded) in &scenes {
        eprintln!("compare: scene {stem} ({} views)", loaded.views.len());
        let out = args.out.join(stem);
        let summary = compare_scene(args, rows, loaded, &out, started)?;
        let mut json_rows = Vec::new();
        for r in &summary {
            let _ = writeln!(
                markdown,
                "| [{stem}]({}/index.md) | {} | {} | {:.3}% | {:.3}% | {} | {:.1} | {:.1} |",
                stem.replace(' ', "%20"),
                r.wrong.len(),
                r.label,
                mean(&r.wrong),
                r.wrong.iter().copied().fold(0.0, f64::max),
                two_places(mean(&r.p99)),
                mean(&r.setup_us),
                mean(&r.frame_ms)
            );
            json_rows.push(json!({
                "technique": r.label,
                "mean_wrong_percent": mean(&r.wrong),
                "worst_wrong_percent": r.wrong.iter().copied().fold(0.0, f64::max),
                "mean_undersampling_p99": mean(&r.p99),
                "mean_setup_us": mean(&r.setup_us),
                "mean_frame_ms": mean(&r.frame_ms),
            }));
        }
        json_scenes.push(json!({ "scene": stem, "name": loaded.name, "techniques": json_rows }));
    }
    write_text(&args.out.join("index.md"), &markdown)?;
    write_text(
        &args.out.join("suite.json"),
        &serde_json::to_string_pretty(&json!({ "scenes": json_scenes }))
            .expect("JSON of plain values"),
    )?;
    eprintln!(
        "compared {} scenes in {:.1} s",
        scenes.len(),
        started.elapsed().as_secs_f64()
    );
    crate::say!("wrote {}", args.out.join("index.md").display());
    Ok(())
}

/// Compares `techniques` over the chosen views of one scene, writing its report into `out`;
/// returns its summary rows.
fn compare_scene(
    args: &CompareArgs,
    compared: &Rows<'_>,
    loaded: &crate::args::LoadedScene,
    out: &std::path::Path,
    started: Instant,
) -> Result<Vec<SummaryRow>, CliError> {
    let views = args.views.select(&loaded.views)?;
    let mut run = SceneRun::new(args, compared, loaded, views.len())?;
    std::fs::create_dir_all(out)
        .map_err(|e| CliError::runtime(format!("cannot create {}: {e}", out.display())))?;
    let mut markdown = run.header();
    run.warm_up(views.first().copied())?;
    let mut summary = run.empty_summary();
    let mut report = Vec::new();
    for view in &views {
        let drawn = run.view(view, &mut summary)?;
        let (width, height) = drawn.grid.size();
        write_png(
            &out.join(format!("{}.png", view.name)),
            width,
            height,
            image::ColorType::Rgba8,
            &drawn.grid.pixels,
        )?;
        markdown.push_str(&drawn.markdown(view));
        report.push(drawn.json(view));
    }
    run.progress.finish_and_clear();
    markdown.push_str(&summary_markdown(&summary));
    let write = |name: &str, text: &str| write_text(&out.join(name), text);
    write("index.md", &markdown)?;
    write(
        "report.json",
        &serde_json::to_string_pretty(&json!({
            "scene": loaded.name,
            "size": [args.size.0, args.size.1],
            "shadow_map": args.shadow_map,
            "device": run.renderer.gpu().describe(),
            "timing": run.renderer.timing_source().name(),
            "views": report,
        }))
        .expect("JSON of plain values"),
    )?;
    eprintln!(
        "compared {} techniques over {} views of {} ({:.1} s so far)",
        compared.techniques.len(),
        views.len(),
        loaded.name,
        started.elapsed().as_secs_f64()
    );
    Ok(summary)
}

/// An image of cells of one frame's size, `columns` wide, filled row by row.
struct Grid {
    cell: (u32, u32),
    columns: u32,
    rows: u32,
    pixels: Vec<u8>,
}

impl Grid {
    fn new(cell: (u32, u32), columns: u32, rows: u32) -> Self {
        let pixels = vec![255u8; (cell.0 * columns * cell.1 * rows * 4) as usize];
        Self {
            cell,
            columns,
            rows,
            pixels,
        }
    }

    fn size(&self) -> (u32, u32) {
        (self.cell.0 * self.columns, self.cell.1 * self.rows)
    }

    /// The reference's row: the exact volumes' frame and mask, and the soft shadows of the
    /// area light where there are.
    fn paste_reference(
        &mut self,
        row: u32,
        exact: &gnomon_render::VolumeFrame,
        soft: Option<&gnomon_render::SoftFrame>,
    ) {
        self.paste(&exact.frame.color, 0, row);
        let mask: Vec<u8> = exact
            .frame
            .mask
            .iter()
            .flat_map(|&m| [m, m, m, 255])
            .collect();
        self.paste(&mask, 1, row);
        if let Some(soft) = soft {
            self.paste(&soft.frame.color, 2, row);
        }
    }

    /// Copies a frame's RGBA pixels into the cell at `column`, `row`.
    fn paste(&mut self, image: &[u8], column: u32, row: u32) {
        let (width, height) = self.cell;
        let grid_width = self.size().0;
        let line = (width * 4) as usize;
        for y in 0..height {
            let from = y as usize * line;
            let to = (((row * height + y) * grid_width + column * width) * 4) as usize;
            self.pixels[to..to + line].copy_from_slice(&image[from..from + line]);
        }
    }
}

/// What every view of one scene's comparison shares: the rows, the renderer and its settings.
struct SceneRun<'a> {
    args: &'a CompareArgs,
    techniques: &'a [crate::rows::Row],
    loaded: &'a crate::args::LoadedScene,
    /// Planar shadows' receiver, where the planar row is asked for (a scene without a ground
    /// says so in its rows).
    receiver: Option<Result<gnomon::planar::PlanarReceiver, CliError>>,
    row_scene: crate::rows::RowScene,
    renderer: gnomon_render::Renderer,
    settings: RenderSettings,
    progress: indicatif::ProgressBar,
}

/// One view's comparison: its grid, its rows' JSON and the reference's figures.
struct DrawnView {
    grid: Grid,
    rows: Vec<Value>,
    exact_ms: f64,
    volumes_command: String,
    soft_command: Option<String>,
}

/// One map row drawn in a view: its grid cells and its figures.
struct MapRow {
    cells: [Vec<u8>; 3],
    n_dot_l: Vec<f32>,
    wrong_percent: f64,
    p99: f64,
    penumbra: Option<f64>,
    setup_us: f64,
    frame_ms: f64,
    json: Value,
}

impl<'a> SceneRun<'a> {
    fn new(
        args: &'a CompareArgs,
        compared: &'a Rows<'a>,
        loaded: &'a crate::args::LoadedScene,
        views: usize,
    ) -> Result<Self, CliError> {
        let techniques = compared.techniques;
        let receiver = compared
            .planar
            .then(|| crate::render::planar_receiver(&loaded.scene, None));
        let row_scene =
            crate::rows::RowScene::new(&loaded.scene, techniques.iter().any(|r| r.projective()))?;
        let renderer = open_renderer(&loaded.scene, args.size, Some(args.shadow_map))?;
        let settings = RenderSettings {
            width: args.size.0,
            height: args.size.1,
            filter: args.soft.pcf.into(),
            area_light_radius: args.soft.pcss_radius(),
            metrics: true,
            ..RenderSettings::default()
        };
        let rows = techniques.len() + usize::from(compared.planar) + 1;
        let progress = crate::output::progress_bar(views * rows);
        Ok(Self {
            args,
            techniques,
            loaded,
            receiver,
            row_scene,
            renderer,
            settings,
            progress,
        })
    }

    /// The grid's rows: one per technique, planar shadows where asked, the exact volumes.
    fn grid_rows(&self) -> u32 {
        (self.techniques.len() + usize::from(self.receiver.is_some())) as u32 + 1
    }

    /// The settings a row's own go over: PCSS filters maps read by depth; rows that read IDs
    /// or coverage keep the default filter (and their commands say nothing of it).
    fn row_base(&self, row: &crate::rows::Row) -> RenderSettings {
        if row.read == gnomon_render::MapRead::Depth {
            self.settings
        } else {
            RenderSettings {
                filter: Filter::default(),
                area_light_radius: 0.0,
                ..self.settings
            }
        }
    }

    /// A map row's filter flags for its command: the filter and the area light (the samples
    /// are the reference's).
    fn soft_flags(&self, row: &crate::rows::Row) -> String {
        if row.read != gnomon_render::MapRead::Depth {
            return String::new();
        }
        let soft = &self.args.soft;
        crate::render::SoftArgs {
            area_samples: None,
            area_light: soft.area_light.filter(|_| soft.pcss()),
            ..soft.clone()
        }
        .non_default_flags()
    }

    /// The report's title and how to read its tables and grids.
    fn header(&self) -> String {
        let args = self.args;
        let area = match args.soft.area_light {
            Some(radius) => format!(
                " Area lights of radius {radius} (degrees for a sun, world units for spot and \
                 point lights){}; penumbra error: \
                 the mean absolute difference of the first light's shadow factor from the soft \
                 shadows of the same area light ({} hard lights with exact volumes, the third \
                 column of the volumes' row) over the pixels with N.L > 0.1 where either lies \
                 between 0.02 and 0.98 (the union of both penumbrae).",
                if args.soft.pcss() {
                    ", maps read by depth filtered with their PCSS"
                } else {
                    ", maps filtered without them (hard shadows)"
                },
                args.soft
                    .area_samples
                    .unwrap_or(crate::render::DEFAULT_AREA_SAMPLES)
            ),
            None => String::new(),
        };
        format!(
            "# gnomon compare: {} scene\n\n{}x{} pixels, {}x{} shadow maps, rendered on {}. Wrong \
             pixels: share of the pixels with N.L > 0.1 whose one-tap shadow-map mask differs from \
             the exact shadow volumes' (false shadow: shadowed by the map, lit in fact; missed \
             shadow: the reverse). SPPSM comes twice: its two maps at the size above each, and \
             (sppsm-same-texels) two maps of half the area, the texels of one map; dual paraboloid maps \
             likewise (paraboloid-cube-texels: two maps with the texels of a cube's six faces). A row \
             that cannot draw a view's light (cube and paraboloid: point lights only; SPPSM and \
             cascades: no point light) says n/a. Undersampling: pixels per texel along the worst direction \
             (1 = one texel per pixel), over the same pixels; area p99: pixels per texel in area \
             (1 / |det J|, the measure SPPSM's plane compares). Frame: setup + shadow pass + main pass \
             (pass times from {}).\n\n\
             Each grid has one row per technique in the table's order, then the exact shadow \
             volumes; columns: the frame, the mask errors (red: false shadow, blue: missed \
             shadow), the sampling error map.{area}\n",
            self.loaded.name,
            args.size.0,
            args.size.1,
            args.shadow_map,
            args.shadow_map,
            self.renderer.gpu().describe(),
            self.renderer.timing_source().name(),
        )
    }

    /// One untimed frame first: the first draw compiles the pipelines. Its map is the first
    /// row's that takes the first view's light (a row that refuses it is left out of that
    /// view, and must not fail the run here).
    fn warm_up(&mut self, view: Option<&gnomon_scene::NamedView>) -> Result<(), CliError> {
        let Some(view) = view else {
            return Ok(());
        };
        let (width, height) = self.args.size;
        let (camera, light) = view.camera_and_light(width as f64 / height as f64)?;
        let lights = std::slice::from_ref(&light);
        if let Some(row) = self.techniques.iter().find(|r| r.refuses(lights).is_none()) {
            let samples = vec![self.renderer.view_samples(&camera, &light)?];
            let bounds = self.row_scene.bounds();
            let (setups, _) = light_setups(row, &camera, lights, bounds, &samples)?;
            self.renderer
                .render(&camera, &light, &setups[0], &self.settings)?;
        }
        self.renderer
            .render_volumes(&camera, &light, &self.settings, StencilMode::ZFail)?;
        Ok(())
    }

    fn empty_summary(&self) -> Vec<SummaryRow> {
        self.techniques
            .iter()
            .map(|t| t.label.clone())
            .chain(
                self.receiver
                    .is_some()
                    .then(|| crate::names::PLANAR.to_string()),
            )
            .map(|label| SummaryRow {
                label,
                wrong: Vec::new(),
                p99: Vec::new(),
                penumbra: Vec::new(),
                setup_us: Vec::new(),
                frame_ms: Vec::new(),
            })
            .collect()
    }

    /// Every row in one view against its exact volumes (and the soft shadows of its area
    /// lights, the penumbrae's reference), each row's figures added to `summary`.
    fn view(
        &mut self,
        view: &gnomon_scene::NamedView,
        summary: &mut [SummaryRow],
    ) -> Result<DrawnView, CliError> {
        let (width, height) = self.args.size;
        let camera = view.camera(width as f64 / height as f64)?;
        // Every light of the view (a scene file's view may have several).
        let lights = view.lights()?;
        self.progress.set_message(format!("{}: volumes", view.name));
        let exact = self.renderer.render_volumes_lit_by(
            &camera,
            &lights,
            &self.settings,
            StencilMode::ZFail,
        )?;
        let soft = self.soft_volumes(view, &camera, &lights)?;
        // What the pixels see from each light, once per view, shared by every technique.
        let samples = lights
            .iter()
            .map(|light| self.renderer.view_samples(&camera, light))
            .collect::<Result<Vec<_>, _>>()?;
        self.progress.inc(1);
        let mut grid = Grid::new(self.args.size, 3, self.grid_rows());
        let mut rows = Vec::new();
        // N.L of the view's pixels (for the rows without maps): a map row's metrics.
        let mut view_n_dot_l: Option<Vec<f32>> = None;
        for (k, entry) in self.techniques.iter().enumerate() {
            self.progress
                .set_message(format!("{}: {}", view.name, entry.label));
            if let Some(why) = entry.refuses(&lights) {
                // Its grid row stays empty; the summary leaves this view out for it.
                rows.push(crate::report::skipped_record(None, &entry.label, why));
                self.progress.inc(1);
                continue;
            }
            let drawn = self.map_row(
                entry,
                view,
                (&camera, &lights, &samples),
                &exact,
                soft.as_ref(),
            )?;
            for (column, cell) in drawn.cells.iter().enumerate() {
                grid.paste(cell, column as u32, k as u32);
            }
            summary[k].add(
                drawn.wrong_percent,
                drawn.p99,
                drawn.setup_us,
                drawn.frame_ms,
            );
            summary[k].penumbra.extend(drawn.penumbra);
            view_n_dot_l.get_or_insert(drawn.n_dot_l);
            rows.push(drawn.json);
            self.progress.inc(1);
        }
        self.row_scene.restore(&mut self.renderer)?;
        let receiver = self.receiver.as_ref().map(|r| match r {
            Ok(receiver) => Ok(receiver.clone()),
            Err(e) => Err(e.message.clone()),
        });
        if let Some(receiver) = receiver {
            self.progress.set_message(format!("{}: planar", view.name));
            rows.push(match receiver {
                Ok(receiver) => {
                    let lit = (&camera, lights.as_slice(), samples.as_slice());
                    let k = self.techniques.len();
                    let drawn = (&exact, &mut grid, &mut summary[k]);
                    self.planar_row(view, &receiver, lit, view_n_dot_l, drawn)?
                }
                Err(why) => crate::report::skipped_record(None, crate::names::PLANAR, &why),
            });
            self.progress.inc(1);
        }
        grid.paste_reference(self.grid_rows() - 1, &exact, soft.as_ref());
        let t = exact.frame.timings;
        Ok(DrawnView {
            grid,
            rows,
            exact_ms: t.shadow_pass_ms + t.main_pass_ms,
            volumes_command: (self.commands()).render(
                view,
                None,
                "volumes",
                " --out frame.png --mask mask.png",
            ),
            soft_command: soft.as_ref().map(|_| self.soft_command(view)),
        })
    }

    /// With an area light, the soft shadows of the view's area lights: the reference of the
    /// penumbrae.
    fn soft_volumes(
        &mut self,
        view: &gnomon_scene::NamedView,
        camera: &gnomon::Camera,
        lights: &[gnomon::Light],
    ) -> Result<Option<gnomon_render::SoftFrame>, CliError> {
        let scene_box = self.row_scene.bounds().scene_box();
        let Some(clusters) = self.args.soft.area_clusters(lights, &scene_box)? else {
            return Ok(None);
        };
        self.progress
            .set_message(format!("{}: soft volumes", view.name));
        Ok(Some(self.renderer.render_soft_volumes(
            camera,
            &clusters,
            &self.settings,
            StencilMode::ZFail,
        )?))
    }

    /// One map technique in one view: its frame, mask errors and sampling error map.
    fn map_row(
        &mut self,
        entry: &crate::rows::Row,
        view: &gnomon_scene::NamedView,
        (camera, lights, samples): (&gnomon::Camera, &[gnomon::Light], &[gnomon::ViewSamples]),
        exact: &gnomon_render::VolumeFrame,
        soft: Option<&gnomon_render::SoftFrame>,
    ) -> Result<MapRow, CliError> {
        let (width, height) = self.args.size;
        let base = self.row_base(entry);
        let lit = (camera, lights, samples);
        let drawn = self.row_scene.draw(&mut self.renderer, entry, lit, &base)?;
        let (setup, setup_us, frame) = (&drawn.setups[0], drawn.setup_us, &drawn.frame);
        let metrics = frame.metrics.as_ref().expect("metrics asked for");
        let (errors, error_image) = mask_errors(frame, &metrics.n_dot_l, &exact.frame);
        // The lookup's classification is the first light's, of maps read by depth.
        let sure = (lights.len() == 1 && entry.read == gnomon_render::MapRead::Depth).then(|| {
            SureErrors::of(
                &frame.mask,
                &exact.frame.mask,
                &metrics.n_dot_l,
                &metrics.unsure,
            )
        });
        let t = frame.timings;
        let frame_ms = setup_us / 1e3 + t.shadow_pass_ms + t.main_pass_ms;
        let undersampling = heatmap::percentiles(metrics, &metrics.undersampling);
        let p99 = undersampling["p99"].as_f64().unwrap_or(f64::NAN);
        // PCSS filters maps read by depth; the other reads take one tap.
        let penumbra = soft
            .filter(|_| entry.read == gnomon_render::MapRead::Depth)
            .map(|soft| {
                gnomon_render::penumbra_error(
                    &soft.factor,
                    frame.shadow.as_deref().expect("a map frame has its factor"),
                    &metrics.n_dot_l,
                )
            });
        // sppsm-same-texels is sppsm at its own map size.
        let command = self.commands().render(
            view,
            Some(entry),
            entry.technique_name(),
            &format!(
                "{} --out frame.png --mask mask.png --error-map error.png",
                self.soft_flags(entry)
            ),
        );
        let json = json!({
            "command": command,
            "shadow_map": entry.resolution,
            "maps": setup.maps.len(),
            "fallback": setup.fallback().map(|f| f.name()),
            "wrong_percent": errors.wrong_percent(),
            "false_shadow_percent": errors.false_shadow_percent(),
            "missed_shadow_percent": errors.missed_shadow_percent(),
            "compared_pixels": errors.compared,
            "unsure_percent": sure.map(|s| s.unsure_percent()),
            "sure_wrong_percent": sure.map(|s| s.sure_wrong_percent()),
            "undersampling": undersampling,
            "area_undersampling": heatmap::percentiles(metrics, &metrics.area),
            "penumbra_error": penumbra.map(|p| p.mean),
            "penumbra_pixels": penumbra.map(|p| p.pixels),
            "setup_us": setup_us,
            "frame_ms": frame_ms,
        });
        let json = crate::report::row_record(None, &entry.label, json);
        let error_map = heatmap::draw(metrics, width, height);
        // The frame's colour and N.L become the row's cells and the view's N.L, not copies.
        let mut frame = drawn.frame;
        let n_dot_l = frame.metrics.take().map(|m| m.n_dot_l).unwrap_or_default();
        Ok(MapRow {
            cells: [frame.color, error_image, error_map],
            n_dot_l,
            wrong_percent: errors.wrong_percent(),
            p99,
            penumbra: penumbra.map(|p| p.mean),
            setup_us,
            frame_ms,
            json,
        })
    }

    /// Planar shadows in one view, judged on the N.L of a map row's frame (or, where none
    /// drew the view, the focused map's).
    fn planar_row(
        &mut self,
        view: &gnomon_scene::NamedView,
        receiver: &gnomon::planar::PlanarReceiver,
        (camera, lights, samples): (&gnomon::Camera, &[gnomon::Light], &[gnomon::ViewSamples]),
        n_dot_l: Option<Vec<f32>>,
        (exact, grid, summary): (&gnomon_render::VolumeFrame, &mut Grid, &mut SummaryRow),
    ) -> Result<Value, CliError> {
        let n_dot_l = match n_dot_l {
            Some(n) => n,
            None => {
                let focused = crate::rows::row("focused", &self.args.params, self.args.shadow_map)?;
                let lit = (camera, lights, samples);
                let drawn =
                    (self.row_scene).draw(&mut self.renderer, &focused, lit, &self.settings)?;
                drawn.frame.metrics.expect("metrics asked for").n_dot_l
            }
        };
        let frame = self
            .renderer
            .render_planar_lit_by(camera, lights, receiver, &self.settings)?
            .frame;
        let (errors, error_image) = mask_errors(&frame, &n_dot_l, &exact.frame);
        let t = frame.timings;
        let frame_ms = t.shadow_pass_ms + t.main_pass_ms;
        let k = self.techniques.len() as u32;
        grid.paste(&frame.color, 0, k);
        grid.paste(&error_image, 1, k);
        summary.add(errors.wrong_percent(), f64::NAN, 0.0, frame_ms);
        let command = (self.commands()).render(
            view,
            None,
            crate::names::PLANAR,
            " --out frame.png --mask mask.png",
        );
        let figures = json!({
            "command": command,
            "maps": 0,
            "wrong_percent": errors.wrong_percent(),
            "false_shadow_percent": errors.false_shadow_percent(),
            "missed_shadow_percent": errors.missed_shadow_percent(),
            "compared_pixels": errors.compared,
            "setup_us": 0.0,
            "frame_ms": frame_ms,
        });
        Ok(crate::report::row_record(
            None,
            crate::names::PLANAR,
            figures,
        ))
    }

    /// What the rows' reproduce commands share.
    fn commands(&self) -> crate::rows::Commands<'_> {
        crate::rows::Commands {
            scene_options: &self.loaded.options,
            params: &self.args.params,
            shadow_map: self.args.shadow_map,
            size: self.args.size,
        }
    }

    /// The command that draws the soft shadows of the view's area light (the volumes of its
    /// cluster of hard lights).
    fn soft_command(&self, view: &gnomon_scene::NamedView) -> String {
        let mut flags = self.args.soft.clone();
        flags.pcf = crate::render::PcfArg::Hardware2x2;
        let extra = format!(
            "{} --out soft.png --mask soft-factor.png",
            flags.non_default_flags()
        );
        self.commands().render(view, None, "volumes", &extra)
    }
}

impl SummaryRow {
    fn add(&mut self, wrong_percent: f64, p99: f64, setup_us: f64, frame_ms: f64) {
        self.wrong.push(wrong_percent);
        self.p99.push(p99);
        self.setup_us.push(setup_us);
        self.frame_ms.push(frame_ms);
    }
}

impl DrawnView {
    /// The view's section of the report: its table, its grid and the commands of its rows.
    fn markdown(&self, view: &gnomon_scene::NamedView) -> String {
        let mut markdown = format!(
            "\n## {} ({})\n\nExact shadow volumes: frame {:.1} ms.\n\n\
             | technique | wrong pixels | false shadow | missed shadow | undersampling p50 | p95 | p99 | max | area p99 | penumbra error | setup (us) | frame (ms) | fallback |\n\
             | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |\n",
            view.name, view.description, self.exact_ms
        );
        for r in &self.rows {
            markdown.push_str(&table_row(r));
        }
        let mut labels: Vec<&str> = self
            .rows
            .iter()
            .map(|r| r["technique"].as_str().unwrap_or_default())
            .collect();
        labels.push("exact shadow volumes");
        let _ = writeln!(
            markdown,
            "\n![{}]({}.png)\n\nGrid rows, top to bottom: {}. Columns: the frame, the mask \
             errors (red: false shadow, blue: missed shadow), the sampling error map.\n\n\
             Each row from the command line:\n",
            view.name,
            view.name,
            labels.join(", ")
        );
        for r in &self.rows {
            let _ = writeln!(
                markdown,
                "- {}: `{}`",
                r["technique"].as_str().unwrap_or_default(),
                r["command"].as_str().unwrap_or_default()
            );
        }
        let _ = writeln!(
            markdown,
            "- exact shadow volumes: `{}`",
            self.volumes_command
        );
        if let Some(command) = &self.soft_command {
            let _ = writeln!(
                markdown,
                "- soft shadows of the area light (the penumbrae's reference; the exact volumes' \
                 row, third column): `{command}`"
            );
        }
        markdown
    }

    /// The view in `report.json`.
    fn json(self, view: &gnomon_scene::NamedView) -> Value {
        json!({
            "view": view.name,
            "description": view.description,
            "eye": view.eye.to_array(),
            "target": view.target.to_array(),
            "far": view.far,
            "up": view.up.to_array(),
            "fov": view.fov_y_degrees,
            "near": view.near,
            "light": crate::report::view_light_json(&view.light),
            "more_lights": view.more_lights.iter().map(crate::report::view_light_json).collect::<Vec<_>>(),
            "volumes_command": self.volumes_command,
            "volumes_frame_ms": self.exact_ms,
            "soft_command": self.soft_command,
            "techniques": self.rows,
        })
    }
}

/// One row of a view's table, from its JSON.
fn table_row(r: &Value) -> String {
    if let Some(why) = r["skipped"].as_str() {
        let label = r["technique"].as_str().unwrap_or_default();
        return format!("| {label} | n/a: {why} ||||||||||||\n");
    }
    let u = &r["undersampling"];
    let f = |v: &Value| v.as_f64().map_or("-".to_string(), |x| format!("{x:.2}"));
    format!(
        "| {} | {:.3}% | {:.3}% | {:.3}% | {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | {} |\n",
        r["technique"].as_str().unwrap_or_default(),
        r["wrong_percent"].as_f64().unwrap_or_default(),
        r["false_shadow_percent"].as_f64().unwrap_or_default(),
        r["missed_shadow_percent"].as_f64().unwrap_or_default(),
        f(&u["p50"]),
        f(&u["p95"]),
        f(&u["p99"]),
        f(&u["max"]),
        f(&r["area_undersampling"]["p99"]),
        r["penumbra_error"]
            .as_f64()
            .map_or("-".to_string(), |x| format!("{x:.4}")),
        r["setup_us"].as_f64().unwrap_or_default(),
        r["frame_ms"].as_f64().unwrap_or_default(),
        r["fallback"].as_str().unwrap_or("none"),
    )
}

/// The scene's table over all views.
fn summary_markdown(summary: &[SummaryRow]) -> String {
    let mut markdown = "\n## Over all views\n\n| technique | mean wrong pixels | worst view | mean undersampling p99 | mean penumbra error |\n| --- | ---: | ---: | ---: | ---: |\n".to_string();
    for row in summary {
        let worst = row.wrong.iter().copied().fold(0.0, f64::max);
        let penumbra = if row.penumbra.is_empty() {
            "-".to_string()
        } else {
            format!("{:.4}", mean(&row.penumbra))
        };
        let _ = writeln!(
            markdown,
            "| {} | {:.3}% | {worst:.3}% | {} | {penumbra} |",
            row.label,
            mean(&row.wrong),
            two_places(mean(&row.p99))
        );
    }
    markdown
}
