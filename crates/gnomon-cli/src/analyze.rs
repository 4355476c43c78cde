//! `gnomon analyze`: perspective aliasing dp/ds along the view axis, measured from every
//! technique's actual matrices in the LiSPSM paper's ideal configuration (or with a tilt
//! gamma between view and light): a table, JSON, and the paper's Figure 6 as an SVG plot.

use std::path::PathBuf;

use clap::Args;
use gnomon::analysis::{AliasingCurve, IdealConfiguration};
use gnomon_tools::analysis::{AnalysisRow, analyze};

use crate::CliError;
use crate::args::TechniqueParams;

/// `gnomon analyze`.
#[derive(Debug, Clone, Args)]
pub struct AnalyzeArgs {
    /// Near plane distance z_n.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub zn: f64,
    /// Far plane distance z_f.
    #[arg(long, default_value_t = 100.0, allow_hyphen_values = true)]
    pub zf: f64,
    /// Angle between the view direction and the light's direction of travel, degrees, in
    /// (0, 180); 90 is the paper's ideal case.
    #[arg(long, default_value_t = 90.0, allow_hyphen_values = true)]
    pub gamma: f64,
    #[command(flatten)]
    pub params: TechniqueParams,
    /// Samples along the view axis (spaced geometrically from z_n to z_f).
    #[arg(long, default_value_t = 200)]
    pub samples: usize,
    /// Shadow-map resolution in texels (the one-texel inset shows at small sizes).
    #[arg(long, default_value_t = crate::args::DEFAULT_SHADOW_MAP, allow_hyphen_values = true, value_parser = crate::args::parse_shadow_map)]
    pub shadow_map: u32,
    /// Print JSON instead of a table (with every sampled curve).
    #[arg(long)]
    pub json: bool,
    /// Also write the curves as an SVG plot (log y axis): the LiSPSM paper's Figure 6 and
    /// the SPPSM paper's Figure 1 for all techniques.
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// Runs `gnomon analyze`.
pub fn run(args: &AnalyzeArgs) -> Result<(), CliError> {
    if let Some(path) = &args.plot {
        crate::output::check_output("--plot", path, &["svg"])?;
    }
    let config = IdealConfiguration::new(args.zn, args.zf, args.gamma)?;
    if args.samples < 2 || args.samples > 100_000 {
        return Err(CliError::usage(format!(
            "--samples must be in 2..=100000 (got {})",
            args.samples
        )));
    }
    let analysis = analyze(config, &args.params, args.samples, args.shadow_map)?;
    let rows = &analysis.rows;
    if let Some(path) = &args.plot {
        plot(path, &config, rows)?;
    }
    let ideal = config.logarithmic_ideal();
    if args.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&analysis.to_json()).expect("JSON of plain values")
        );
        return Ok(());
    }
    crate::say!(
        "dp/ds along the view axis (projection term 1), z_n = {}, z_f = {}, gamma = {} degrees, \
         {}x{} maps",
        config.z_near,
        config.z_far,
        config.gamma_degrees,
        args.shadow_map,
        args.shadow_map
    );
    crate::say!(
        "{:<10} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}  fallback",
        "technique",
        "max",
        "z of max",
        "at z_n",
        "at z_f",
        "min",
        "z of min"
    );
    for r in rows {
        match &r.curve {
            Ok(c) => crate::say!(
                "{:<10} {:>9.3} {:>9.2} {:>9.3} {:>9.3} {:>9.3} {:>9.2}  {}",
                r.label,
                c.max,
                c.z_of_max,
                c.at_near,
                c.at_far,
                c.min,
                c.z_of_min,
                r.fallback.unwrap_or("none")
            ),
            Err(e) => crate::say!("{:<10} not measurable: {e}", r.label),
        }
    }
    crate::say!(
        "logarithmic ideal z_n ln(z_f / z_n) = {ideal:.3} (no single map has a smaller maximum)"
    );
    if let Some(path) = &args.plot {
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// The curves on a log y axis, with the logarithmic ideal as a dashed line, and the legend
/// beside the plot (not over the data). A curve that coincides with an earlier one (to a
/// thousandth everywhere) is drawn dashed over it and its legend entry says which it equals.
fn plot(
    path: &std::path::Path,
    config: &IdealConfiguration,
    rows: &[AnalysisRow],
) -> Result<(), CliError> {
    use plotters::prelude::*;
    let error = |e: String| CliError::runtime(format!("cannot plot to {}: {e}", path.display()));
    let curves: Vec<(&str, &AliasingCurve)> = rows
        .iter()
        .filter_map(|r| r.curve.as_ref().ok().map(|c| (r.label.as_str(), c)))
        .collect();
    let ideal = config.logarithmic_ideal();
    let (lo, hi) = curves.iter().fold((ideal, ideal), |(lo, hi), (_, c)| {
        (lo.min(c.min), hi.max(c.max))
    });
    let root = SVGBackend::new(path, (1100, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
    let (plot_area, legend_area) = root.split_horizontally(880);
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(
            format!(
                "perspective aliasing dp/ds, z_n = {}, z_f = {}, gamma = {} deg",
                config.z_near, config.z_far, config.gamma_degrees
            ),
            ("sans-serif", 22),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            config.z_near..config.z_far,
            (0.5 * lo..2.0 * hi).log_scale(),
        )
        .map_err(|e| error(e.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("z (distance along the view axis)")
        .y_desc("dp/ds")
        .draw()
        .map_err(|e| error(e.to_string()))?;
    let mut legend: Vec<(String, RGBAColor, bool)> = Vec::new();
    for (k, (label, c)) in curves.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let points = c.z.iter().copied().zip(c.dp_ds.iter().copied());
        match same_as(&curves, k) {
            None => {
                chart
                    .draw_series(LineSeries::new(points, color.stroke_width(2)))
                    .map_err(|e| error(e.to_string()))?;
                legend.push((label.to_string(), color, false));
            }
            Some(other) => {
                chart
                    .draw_series(DashedLineSeries::new(points, 8, 8, color.stroke_width(3)))
                    .map_err(|e| error(e.to_string()))?;
                legend.push((format!("{label} (= {other})"), color, true));
            }
        }
    }
    chart
        .draw_series(DashedLineSeries::new(
            [(config.z_near, ideal), (config.z_far, ideal)],
            6,
            4,
            BLACK.stroke_width(1),
        ))
        .map_err(|e| error(e.to_string()))?;
    legend.push((
        format!("logarithmic ideal {ideal:.2}"),
        BLACK.to_rgba(),
        true,
    ));
    draw_legend(&legend_area, &legend).map_err(error)?;
    root.present().map_err(|e| error(e.to_string()))?;
    Ok(())
}

/// The label of an earlier curve that curve `k` coincides with (to a thousandth everywhere).
fn same_as<'a>(curves: &[(&'a str, &AliasingCurve)], k: usize) -> Option<&'a str> {
    let c = curves[k].1;
    curves[..k].iter().find_map(|(label, d)| {
        let equal = c.dp_ds.len() == d.dp_ds.len()
            && c.dp_ds
                .iter()
                .zip(&d.dp_ds)
                .all(|(a, b)| (a - b).abs() <= 1e-3 * a.abs().max(b.abs()));
        equal.then_some(*label)
    })
}

/// The legend's entries (label, colour, dashed), one under another.
fn draw_legend<DB: plotters::prelude::DrawingBackend>(
    legend_area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    legend: &[(String, plotters::prelude::RGBAColor, bool)],
) -> Result<(), String> {
    use plotters::prelude::*;
    let error = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    for (k, (label, color, dashed)) in legend.iter().enumerate() {
        let y = 60 + 26 * k as i32;
        let line = if *dashed {
            vec![(10, y), (18, y), (26, y), (34, y)]
        } else {
            vec![(10, y), (34, y)]
        };
        let segments: Vec<_> = if *dashed {
            line.chunks(2).map(|s| s.to_vec()).collect()
        } else {
            vec![line]
        };
        for segment in segments {
            legend_area
                .draw(&PathElement::new(segment, color.stroke_width(3)))
                .map_err(error)?;
        }
        legend_area
            .draw(&Text::new(
                label.clone(),
                (42, y - 8),
                ("sans-serif", 16).into_font(),
            ))
            .map_err(error)?;
    }
    Ok(())
}
