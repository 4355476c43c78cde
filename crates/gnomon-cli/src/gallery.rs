//! The demo's gallery: each drawn cell judged against the exact volumes, a front page of the
//! rows a user compares (an engine's stable cascades, gnomon's best, SPPSM, the exact volumes,
//! soft shadows) with zoomed crops where shadow edges differ, and every cell on a second page.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use gnomon::{MapSelection, ShadowSetup};
use gnomon_render::{Frame, MASK_EMPTY};
use gnomon_scene::NamedView;
use serde_json::Value;

use crate::CliError;
use crate::render::{write_png, write_text};

/// What a cell shows, which decides how it is judged.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A shadow-map technique: judged against the exact volumes.
    Map,
    /// Planar projected shadows: judged too (only the ground receives).
    Planar,
    /// The exact shadow volumes: the judge.
    Exact,
    /// Soft shadows (the reference, PCSS): judged by penumbra error, not by a mask.
    Soft,
}

/// One drawn frame of one view, or a row that the view's lights refuse.
#[derive(Debug, Clone)]
pub struct Cell {
    pub view: String,
    pub label: String,
    /// The images' file stem in the gallery folder.
    pub stem: String,
    /// The `gnomon render` command that draws it.
    pub command: String,
    pub kind: Kind,
    /// Counts and times, as a line of text.
    pub figures: String,
    /// What fell back, in words.
    pub fallbacks: Vec<String>,
    /// Whether `STEM_light.png` was written.
    pub light_view: bool,
    /// Why the row is not drawn on this view.
    pub skipped: Option<String>,
    pub(crate) color: Vec<u8>,
    pub(crate) mask: Vec<u8>,
    pub(crate) n_dot_l: Option<Vec<f32>>,
    /// Wrong pixels against the exact volumes, percent, and the error image.
    pub(crate) wrong: Option<(f64, Vec<u8>)>,
}

impl Cell {
    /// A row the view's lights refuse.
    pub fn skipped(view: &str, label: &str, why: &str) -> Self {
        Self {
            skipped: Some(why.to_string()),
            ..Self::empty(view, label, Kind::Map)
        }
    }

    /// A drawn frame (its images are written by the caller).
    pub fn drawn(
        view: &str,
        label: &str,
        stem: String,
        command: String,
        kind: Kind,
        frame: &Frame,
    ) -> Self {
        Self {
            stem,
            command,
            color: frame.color.clone(),
            mask: frame.mask.clone(),
            n_dot_l: frame.metrics.as_ref().map(|m| m.n_dot_l.clone()),
            ..Self::empty(view, label, kind)
        }
    }

    fn empty(view: &str, label: &str, kind: Kind) -> Self {
        Self {
            view: view.to_string(),
            label: label.to_string(),
            stem: String::new(),
            command: String::new(),
            kind,
            figures: String::new(),
            fallbacks: Vec::new(),
            light_view: false,
            skipped: None,
            color: Vec::new(),
            mask: Vec::new(),
            n_dot_l: None,
            wrong: None,
        }
    }

    /// Wrong pixels against the exact volumes, in percent, where judged.
    pub fn wrong_percent(&self) -> Option<f64> {
        self.wrong.as_ref().map(|w| w.0)
    }
}

/// The one writer of gallery cells: each drawn cell's images go into the gallery folder as
/// they are drawn, its record into `setups.json`, and each cell, drawn or refused, is a step
/// of the progress bar.
pub struct CellWriter {
    folder: PathBuf,
    pub progress: indicatif::ProgressBar,
    records: Vec<Value>,
}

impl CellWriter {
    /// A writer into `folder` (made by the caller) over `steps` steps.
    pub fn new(folder: &Path, steps: usize) -> Self {
        Self {
            folder: folder.to_path_buf(),
            progress: crate::output::progress_bar(steps),
            records: Vec::new(),
        }
    }

    /// A row the view's lights refuse: a step, its record and its cell.
    pub fn skipped(&mut self, view: &str, label: &str, why: &str) -> Cell {
        self.progress.inc(1);
        (self.records).push(crate::report::skipped_record(Some(view), label, why));
        Cell::skipped(view, label, why)
    }

    /// Writes `frame`'s images as `cell`'s (its light view where the cell says so), keeps
    /// `record` and steps the progress bar.
    pub fn write(&mut self, cell: Cell, frame: &Frame, record: Value) -> Result<Cell, CliError> {
        let light = (cell.light_view).then(|| self.folder.join(format!("{}_light.png", cell.stem)));
        crate::render::write_frame(
            frame,
            &self.folder.join(format!("{}.png", cell.stem)),
            None,
            light.as_deref(),
        )?;
        self.records.push(record);
        self.progress
            .set_message(format!("{} {}", cell.view, cell.label));
        self.progress.inc(1);
        Ok(cell)
    }

    /// Every record kept, in the order of the cells.
    pub fn records(&self) -> &[Value] {
        &self.records
    }
}

/// Every cell of one view.
#[derive(Debug, Clone)]
pub struct ViewCells {
    pub view: NamedView,
    /// Whether the view's main light is directional (the cascade rows need one).
    pub directional: bool,
    pub cells: Vec<Cell>,
}

impl ViewCells {
    /// Judges each map and planar cell against the exact volumes' mask on the pixels facing
    /// the light (N.L > 0.1, from the view's first frame with metrics), as `compare` does.
    pub fn judge_against_exact(&mut self) {
        let Some(exact) = self.cell("volumes").map(|c| c.mask.clone()) else {
            return;
        };
        let Some(n_dot_l) = self.cells.iter().find_map(|c| c.n_dot_l.clone()) else {
            return;
        };
        for cell in &mut self.cells {
            if matches!(cell.kind, Kind::Map | Kind::Planar) && cell.skipped.is_none() {
                let (errors, image) =
                    crate::compare::mask_errors_of(&cell.color, &cell.mask, &n_dot_l, &exact);
                cell.wrong = Some((errors.wrong_percent(), image));
            }
        }
    }

    /// Drops the pixels the pages will not show: every cell's N.L, and the frames, masks and
    /// error images of the rows that are not on the front page (their figures stay). A demo
    /// holds every view's cells until it writes the pages.
    pub fn keep_front_pixels_only(&mut self) {
        for cell in &mut self.cells {
            cell.n_dot_l = None;
            if !FRONT_ROWS.iter().any(|(label, _)| *label == cell.label) {
                cell.color = Vec::new();
                cell.mask = Vec::new();
                if let Some((_, image)) = &mut cell.wrong {
                    *image = Vec::new();
                }
            }
        }
    }

    fn cell(&self, label: &str) -> Option<&Cell> {
        self.cells
            .iter()
            .find(|c| c.label == label && c.skipped.is_none())
    }
}

/// A setup's fallbacks in words: each with the maps it fell back in, where there are several.
pub fn fallback_words(setup: &ShadowSetup) -> Vec<String> {
    let fallbacks = &setup.diagnostics.fallbacks;
    if setup.maps.len() == 1 {
        return fallbacks.iter().map(|f| f.reason().to_string()).collect();
    }
    let kind = match setup.selection {
        MapSelection::Cascades(_) => "cascade",
        MapSelection::CubeFaces(_) => "cube face",
        _ => "map",
    };
    fallbacks
        .iter()
        .map(|f| {
            let maps: Vec<String> = (0..setup.maps.len())
                .filter(|&i| setup.map_diagnostics(i).fallbacks.contains(f))
                .map(|i| i.to_string())
                .collect();
            let plural = if maps.len() > 1 { "s" } else { "" };
            format!("{kind}{plural} {}: {}", maps.join(", "), f.reason())
        })
        .collect()
}

/// What the page says of the run.
pub struct Page<'a> {
    pub scene: &'a str,
    pub size: (u32, u32),
    pub shadow_map: u32,
    pub device: String,
}

/// The front page's rows: label, and a one-line legend.
const FRONT_ROWS: [(&str, &str); 5] = [
    (
        "cascades-stable",
        "What engines ship (Bevy's defaults): four stable cascades bounded by spheres and \
         snapped to whole texels, the first to 10 m, each at a quarter of one map's texels.",
    ),
    (
        "cascades-best",
        "gnomon's best: LiSPSM in each cascade with the warp limit, the number of cascades \
         chosen per view, the same texels in all.",
    ),
    (
        "sppsm",
        "Separating-plane PSM: the focused map and a perspective one, each pixel reading the \
         finer (two maps' texels).",
    ),
    (
        "volumes",
        "Exact shadows (stenciled shadow volumes): what every row is judged against.",
    ),
    (
        "soft",
        "Soft shadows of the light as an area light, the reference: hard lights with exact \
         volumes, averaged.",
    ),
];

/// Views on the front page.
const FRONT_VIEWS: usize = 3;

/// Writes `index.html` (the front page, with its crops) and `all.html` (every cell).
pub fn write(out: &Path, page: &Page<'_>, views: &[ViewCells]) -> Result<(), CliError> {
    let front = front_views(views);
    let mut sections = String::new();
    for view in &front {
        sections += &front_section(out, page.size, view)?;
    }
    let intro = format!(
        "<p>The rows a user compares, on the {} views where an engine's stable cascades and \
         gnomon's best differ most. Each row: the frame, a zoom (2.25x) of the part where shadow \
         edges differ most (the yellow box), and the same part with the wrong pixels marked \
         against the exact volumes (<span style=\"color:#e61e1e\">red: false shadow</span>, \
         <span style=\"color:#1e6ef5\">blue: missed shadow</span>). Wrong pixels are counted \
         over the pixels facing the light. {}x{} pixels, {}x{} shadow maps, rendered on {}. \
         Every technique on every view: <a href=\"all.html\">all.html</a>; every setup and \
         timing: <a href=\"setups.json\">setups.json</a>.</p>",
        front.len(),
        page.size.0,
        page.size.1,
        page.shadow_map,
        page.shadow_map,
        escape(&page.device)
    );
    let title = format!("gnomon demo: {} scene", escape(page.scene));
    write_text(&out.join("index.html"), &html(&title, &(intro + &sections)))?;
    write_text(&out.join("all.html"), &html(&title, &full_grid(views)))?;
    Ok(())
}

/// The views whose main light is a sun and where the stable and best cascades differ most
/// (in the views' order), else the first views.
fn front_views(views: &[ViewCells]) -> Vec<&ViewCells> {
    let gap = |v: &ViewCells| {
        let wrong = |label| v.cell(label).and_then(Cell::wrong_percent);
        wrong("cascades-stable")
            .zip(wrong("cascades-best"))
            .map(|(s, b)| s - b)
    };
    let mut ranked: Vec<(usize, f64)> = views
        .iter()
        .enumerate()
        .filter(|(_, v)| v.directional)
        .filter_map(|(i, v)| gap(v).map(|g| (i, g)))
        .collect();
    ranked.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut chosen: Vec<usize> = ranked.iter().take(FRONT_VIEWS).map(|r| r.0).collect();
    if chosen.is_empty() {
        chosen = (0..views.len().min(FRONT_VIEWS)).collect();
    }
    chosen.sort_unstable();
    chosen.into_iter().map(|i| &views[i]).collect()
}

/// The crop, (x, y, width, height) in pixels: the quarter-size window holding the most pixels
/// where a front map row disagrees with the exact volumes.
fn crop_of(view: &ViewCells, (width, height): (u32, u32)) -> (usize, usize, usize, usize) {
    let (w, h) = (width as usize, height as usize);
    let (cw, ch) = ((w / 4).max(1), (h / 4).max(1));
    let exact = view.cell("volumes").map(|c| &c.mask);
    let maps: Vec<&Cell> = FRONT_ROWS
        .iter()
        .filter_map(|(label, _)| view.cell(label))
        .filter(|c| c.kind == Kind::Map)
        .collect();
    // A summed-area table of the disagreeing pixels.
    let mut sum = vec![0u32; (w + 1) * (h + 1)];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let differs = exact.is_some_and(|e| {
                e[i] != MASK_EMPTY
                    && maps
                        .iter()
                        .any(|c| c.mask[i] != MASK_EMPTY && c.mask[i] != e[i])
            });
            sum[(y + 1) * (w + 1) + x + 1] =
                u32::from(differs) + sum[y * (w + 1) + x + 1] + sum[(y + 1) * (w + 1) + x]
                    - sum[y * (w + 1) + x];
        }
    }
    let count = |x: usize, y: usize| {
        let at = |x: usize, y: usize| sum[y * (w + 1) + x];
        at(x + cw, y + ch) + at(x, y) - at(x + cw, y) - at(x, y + ch)
    };
    let mut best = ((w - cw) / 2, (h - ch) / 2, 0);
    for y in (0..=h - ch).step_by(4) {
        for x in (0..=w - cw).step_by(4) {
            let n = count(x, y);
            if n > best.2 {
                best = (x, y, n);
            }
        }
    }
    (best.0, best.1, cw, ch)
}

/// The `(x, y, w, h)` part of an RGBA image `width` pixels wide.
fn cropped(rgba: &[u8], width: usize, (x, y, w, h): (usize, usize, usize, usize)) -> Vec<u8> {
    (y..y + h)
        .flat_map(|row| &rgba[(row * width + x) * 4..(row * width + x + w) * 4])
        .copied()
        .collect()
}

/// One view of the front page: a row per front technique.
fn front_section(out: &Path, size: (u32, u32), view: &ViewCells) -> Result<String, CliError> {
    let crop = crop_of(view, size);
    let (x, y, w, h) = crop;
    let write_crop = |name: String, rgba: &[u8]| -> Result<String, CliError> {
        let part = cropped(rgba, size.0 as usize, crop);
        let path = out.join(&name);
        write_png(&path, w as u32, h as u32, image::ColorType::Rgba8, &part)?;
        Ok(name)
    };
    let box_style = format!(
        "left:{:.2}%;top:{:.2}%;width:{:.2}%;height:{:.2}%",
        100.0 * x as f64 / size.0 as f64,
        100.0 * y as f64 / size.1 as f64,
        100.0 * w as f64 / size.0 as f64,
        100.0 * h as f64 / size.1 as f64
    );
    let mut rows = String::new();
    for (label, legend) in FRONT_ROWS {
        let Some(cell) = view.cell(label) else {
            continue;
        };
        let zoom = write_crop(format!("{}_crop.png", cell.stem), &cell.color)?;
        let marked = match &cell.wrong {
            Some((_, image)) => {
                let name = write_crop(format!("{}_crop_wrong.png", cell.stem), image)?;
                format!("<img src=\"{name}\" class=zoom>")
            }
            None => "<p class=note>the reference: not judged by a mask</p>".to_string(),
        };
        let _ = write!(
            rows,
            "<tr><td class=legend><b>{label}</b>{}<br>{}<br><small>{}</small>{}</td>\
             <td><div class=frame><img src=\"{stem}.png\" width=360><div class=box style=\"{box_style}\"></div></div></td>\
             <td><img src=\"{zoom}\" class=zoom></td><td>{marked}</td></tr>",
            cell.wrong_percent()
                .map(|p| format!(" · <b>{p:.3}%</b> wrong"))
                .unwrap_or_default(),
            escape(legend),
            escape(&cell.figures),
            fallback_list(&cell.fallbacks),
            stem = cell.stem,
        );
    }
    Ok(format!(
        "<h2>{} <small>{}</small></h2><table><tr><th>row</th><th>frame</th><th>zoom</th>\
         <th>wrong pixels marked</th></tr>{rows}</table>",
        escape(&view.view.name),
        escape(&view.view.description)
    ))
}

fn fallback_list(words: &[String]) -> String {
    if words.is_empty() {
        return String::new();
    }
    let items: String = words
        .iter()
        .map(|w| format!("<li>{}</li>", escape(w)))
        .collect();
    format!("<br><small>Fell back:</small><ul>{items}</ul>")
}

/// The second page: every cell of every view, wrapped to the window's width.
fn full_grid(views: &[ViewCells]) -> String {
    let mut body = String::from(
        "<p>Every technique on every view. Each cell: the frame, the shadow maps as the light \
         sees them (the camera's view frustum in red), the share of wrong pixels against the exact \
         volumes, the figures, and the command that draws it. <a href=\"index.html\">Back to \
         the front page</a>.</p>",
    );
    for view in views {
        let _ = write!(
            body,
            "<h2>{} <small>{}</small></h2><div class=grid>",
            escape(&view.view.name),
            escape(&view.view.description)
        );
        for cell in &view.cells {
            body += &grid_cell(cell);
        }
        body += "</div>";
    }
    body
}

fn grid_cell(cell: &Cell) -> String {
    if let Some(why) = &cell.skipped {
        return format!(
            "<figure><figcaption><b>{}</b>: not drawn here: {}</figcaption></figure>",
            escape(&cell.label),
            escape(why)
        );
    }
    let light = if cell.light_view {
        format!("<img src=\"{}_light.png\" width=320>", cell.stem)
    } else {
        String::new()
    };
    format!(
        "<figure><img src=\"{stem}.png\" width=320>{light}<figcaption><b>{}</b>{}<br>{}{}<br>\
         <code>{}</code></figcaption></figure>",
        escape(&cell.label),
        cell.wrong_percent()
            .map(|p| format!(" · {p:.3}% wrong"))
            .unwrap_or_default(),
        escape(&cell.figures),
        fallback_list(&cell.fallbacks),
        escape(&cell.command),
        stem = cell.stem,
    )
}

fn html(title: &str, body: &str) -> String {
    format!(
        "<!doctype html><meta charset=utf-8><meta name=viewport content=\"width=device-width\">\
         <title>{title}</title><style>\
         body{{font-family:sans-serif;max-width:1560px;margin:8px auto;padding:0 8px}}\
         td,th{{vertical-align:top;padding:4px;text-align:left}}\
         td.legend{{width:280px}} ul{{margin:2px 0;padding-left:18px;font-size:small}}\
         .frame{{position:relative;display:inline-block}} .frame img{{display:block}}\
         .box{{position:absolute;border:2px solid #ffd400;box-sizing:border-box}}\
         img.zoom{{width:360px;image-rendering:pixelated}}\
         .grid{{display:flex;flex-wrap:wrap;gap:10px}}\
         figure{{width:320px;margin:0}} figcaption{{font-size:small}}\
         code{{word-break:break-all;font-size:x-small}}</style><h1>{title}</h1>{body}"
    )
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
