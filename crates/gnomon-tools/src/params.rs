//! The technique parameters every front end reads: one definition of each (the command
//! line's options, which the Python and C bindings take by the same names), how a technique
//! reads them, and which technique reads which.

use clap::{Args, ValueEnum};
use gnomon::{CascadeFit, CascadeSelect, CascadeSplit, PerspectiveMap, Technique};

use crate::UsageError;

/// How `--cascade-split` cuts the view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CascadeSplitArg {
    /// Zhang's practical split (with `--cascade-lambda`).
    Practical,
    /// Logarithmic.
    Log,
    /// Uniform.
    Uniform,
    /// The first slice up to a depth, then logarithmic (Bevy's rule).
    FirstThenLog(f64),
    /// The K - 1 view depths between the slices.
    Distances(usize, [f64; gnomon::MAX_CASCADES - 1]),
}

/// Parses `--cascade-split`: practical, log, uniform, first-log:D, or D1,D2,... (increasing,
/// at most 7).
pub fn cascade_split_arg(s: &str) -> Result<CascadeSplitArg, String> {
    match s.trim() {
        "practical" => Ok(CascadeSplitArg::Practical),
        "log" => Ok(CascadeSplitArg::Log),
        "uniform" => Ok(CascadeSplitArg::Uniform),
        first if first.starts_with("first-log:") => first["first-log:".len()..]
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|d| d.is_finite() && *d > 0.0)
            .map(CascadeSplitArg::FirstThenLog)
            .ok_or_else(|| format!("'{first}': first-log:D needs a positive depth D")),
        list => {
            let mut depths = [0.0; gnomon::MAX_CASCADES - 1];
            let parts: Vec<&str> = list.split(',').map(str::trim).collect();
            if parts.len() > depths.len() {
                return Err(format!(
                    "at most {} split distances (for {} cascades)",
                    depths.len(),
                    gnomon::MAX_CASCADES
                ));
            }
            for (slot, part) in depths.iter_mut().zip(&parts) {
                *slot = part.parse::<f64>().map_err(|_| {
                    format!(
                        "'{list}' is not practical, log, uniform, first-log:D or distances D1,D2,..."
                    )
                })?;
            }
            Ok(CascadeSplitArg::Distances(parts.len(), depths))
        }
    }
}

/// The single-map technique fitting each cascade on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CascadeFitArg {
    /// The focused map.
    Focused,
    /// Light space perspective shadow maps.
    Lispsm,
    /// Trapezoidal shadow maps.
    Tsm,
    /// Extended perspective shadow maps.
    Xpsm,
    /// Perspective shadow maps.
    Psm,
}

/// How a point picks among the cascades' maps on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CascadeSelectArg {
    /// Coverage for stable cascades, view depth for the others.
    Auto,
    /// The map of the slice the point's view depth falls in (as Bevy, Godot and Unity do).
    Depth,
    /// The first (finest) map whose square holds the point (stable cascades only).
    Coverage,
}

/// The perspective map of SPPSM on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SppsmWithArg {
    /// Perspective shadow maps (the paper's choice).
    Psm,
    /// Light space perspective shadow maps.
    Lispsm,
    /// Trapezoidal shadow maps.
    Tsm,
    /// Extended perspective shadow maps.
    Xpsm,
}

/// Technique parameters; each applies to its technique and is ignored by the others.
#[derive(Debug, Clone, Copy, Default, PartialEq, Args)]
pub struct TechniqueParams {
    /// LiSPSM: the distance n of the projection reference point, in world units (default:
    /// the paper's n_opt / sin(gamma)).
    #[arg(long, allow_hyphen_values = true)]
    pub lispsm_n: Option<f64>,
    /// TSM, with --tsm-focus: where the focus line lands in the map's y, in (-1, 1) (default
    /// -0.6, the 80% rule).
    #[arg(long, allow_hyphen_values = true)]
    pub tsm_xi: Option<f64>,
    /// TSM: where the focus point lies along the view, as a fraction of the way from the near
    /// plane to the far end of the view body, in [0, 1], for the paper's 80% rule with
    /// --tsm-xi (default: the projection point that balances the aliasing at z_n and z_f, as
    /// LiSPSM's n_opt does).
    #[arg(long, allow_hyphen_values = true)]
    pub tsm_focus: Option<f64>,
    /// XPSM: warp strength per world unit (default 0.05, for scenes in metres).
    #[arg(long, allow_hyphen_values = true)]
    pub xpsm_coef: Option<f64>,
    /// XPSM: the smallest warp w allowed over the focus region, in (0, 1) (default 0.085).
    #[arg(long, allow_hyphen_values = true)]
    pub xpsm_epsilon_w: Option<f64>,
    /// PSM: how far the virtual camera slides back, in world units (default sqrt(z_n z_f)).
    #[arg(long, allow_hyphen_values = true)]
    pub psm_slide_back: Option<f64>,
    /// PSM, LiSPSM, TSM, XPSM: keep the warp at the technique's full strength even where it
    /// samples the view more coarsely than the focused map (by default the warp is weakened
    /// there, or the focused map used, and the diagnostics say so). SPPSM's perspective map
    /// never has the limit: SPPSM picks the finer map per point itself.
    #[arg(long)]
    pub no_warp_limit: bool,
    /// SPPSM: the perspective map next to the focused one (default psm); the parameters
    /// above apply to it.
    #[arg(long, value_enum)]
    pub sppsm_with: Option<SppsmWithArg>,
    /// SPPSM: focusing iterations, 1 to 20 (default 10).
    #[arg(long)]
    pub sppsm_iterations: Option<u32>,
    /// Cascades: the number of slices of the view, 1 to 8 (default 4).
    #[arg(long)]
    pub cascades: Option<usize>,
    /// Cascades: how the view is cut: practical (Zhang's blend of log and uniform, with
    /// --cascade-lambda), log, uniform, first-log:D (the first slice to depth D, then log:
    /// Bevy's rule), or the K - 1 view depths D1,D2,... between the slices (default
    /// practical).
    #[arg(long, value_parser = cascade_split_arg, allow_hyphen_values = true)]
    pub cascade_split: Option<CascadeSplitArg>,
    /// Cascades: the practical split's weight of the log split, 0 to 1 (default 0.5).
    #[arg(long, allow_hyphen_values = true)]
    pub cascade_lambda: Option<f64>,
    /// Cascades: the view depth beyond which nothing is shadowed, with a fade over its last
    /// 10% (default: the camera's far plane).
    #[arg(long, allow_hyphen_values = true)]
    pub shadow_distance: Option<f64>,
    /// Cascades: the technique fitting each slice (default lispsm); its parameters above
    /// apply to it.
    #[arg(long, value_enum)]
    pub cascade_fit: Option<CascadeFitArg>,
    /// Cascades: the blend band between neighbours, as a fraction of the slice, 0 to 0.5
    /// (default 0.1).
    #[arg(long, allow_hyphen_values = true)]
    pub cascade_blend: Option<f64>,
    /// Cascades: stable cascades (directional lights): slices bounded by spheres in the
    /// light's fixed frame, snapped to whole texels, so that the texel grid stays put while
    /// the camera moves; --cascade-fit is not used.
    #[arg(long)]
    pub stable: bool,
    /// Cascades: the K maps share the texels of one --shadow-map map (each
    /// shadow-map / sqrt(K) on a side) instead of each having that size.
    #[arg(long)]
    pub equal_texels: bool,
    /// Cascades: choose the number of cascades per view, up to --cascades: 1, 2, ... are set
    /// up in turn while each undersamples the view samples less at the median than the one
    /// before, and the last that did is kept (not with explicit --cascade-split distances);
    /// `flicker` and `view` keep the previous frame's number unless that one samples the
    /// view more than 10% better.
    #[arg(long)]
    pub cascade_adaptive: bool,
    /// Cascades: how a point picks its map (default auto: stable cascades by coverage, the
    /// nearest map whose square holds it, which reads finer texels than its view depth's
    /// map; fitted cascades by view depth, since a fitted map holds only its slice).
    #[arg(long, value_enum)]
    pub cascade_select: Option<CascadeSelectArg>,
}

/// The technique parameters `technique` reads (SPPSM: its own and its perspective map's).
pub fn options_read_by(technique: &Technique) -> Vec<&'static str> {
    match technique {
        Technique::Lispsm(_) => vec!["--lispsm-n", "--no-warp-limit"],
        Technique::Tsm(_) => vec!["--tsm-xi", "--tsm-focus", "--no-warp-limit"],
        Technique::Xpsm(_) => vec!["--xpsm-coef", "--xpsm-epsilon-w", "--no-warp-limit"],
        Technique::Psm(_) => vec!["--psm-slide-back", "--no-warp-limit"],
        Technique::Cascades(c) => {
            let mut read = vec![
                "--cascades",
                "--cascade-split",
                "--cascade-lambda",
                "--shadow-distance",
                "--cascade-fit",
                "--cascade-blend",
                "--stable",
                "--equal-texels",
                "--cascade-adaptive",
                "--cascade-select",
            ];
            // Stable cascades fit a sphere per slice: no fit technique, none of its options.
            if c.stable {
                read.retain(|o| *o != "--cascade-fit");
            } else if let Some(fit) = fit_technique(c.fit) {
                read.extend(options_read_by(&fit));
            }
            read
        }
        Technique::Sppsm(s) => {
            let mut read = vec!["--sppsm-with", "--sppsm-iterations"];
            read.extend(
                options_read_by(&perspective_technique(s.perspective))
                    .into_iter()
                    .filter(|o| *o != "--no-warp-limit"),
            );
            read
        }
        _ => Vec::new(),
    }
}

/// A cascade's fit as the technique on its own (`None`: the focused map, which reads no
/// parameter).
fn fit_technique(fit: CascadeFit) -> Option<Technique> {
    match fit {
        CascadeFit::Focused => None,
        CascadeFit::Lispsm(t) => Some(Technique::Lispsm(t)),
        CascadeFit::Tsm(t) => Some(Technique::Tsm(t)),
        CascadeFit::Xpsm(t) => Some(Technique::Xpsm(t)),
        CascadeFit::Psm(t) => Some(Technique::Psm(t)),
    }
}

/// SPPSM's perspective map as the technique on its own.
fn perspective_technique(map: PerspectiveMap) -> Technique {
    match map {
        PerspectiveMap::Psm(p) => Technique::Psm(p),
        PerspectiveMap::Lispsm(p) => Technique::Lispsm(p),
        PerspectiveMap::Tsm(p) => Technique::Tsm(p),
        PerspectiveMap::Xpsm(p) => Technique::Xpsm(p),
    }
}

impl TechniqueParams {
    /// The options that give these parameters (option, option with its value), for a
    /// command that reproduces a figure.
    pub fn flags(&self) -> Vec<(&'static str, String)> {
        let mut flags = Vec::new();
        let mut number = |name: &'static str, value: Option<f64>| {
            if let Some(v) = value {
                flags.push((name, format!("{name}={v}")));
            }
        };
        number("--lispsm-n", self.lispsm_n);
        number("--tsm-xi", self.tsm_xi);
        number("--tsm-focus", self.tsm_focus);
        number("--xpsm-coef", self.xpsm_coef);
        number("--xpsm-epsilon-w", self.xpsm_epsilon_w);
        number("--psm-slide-back", self.psm_slide_back);
        number("--cascade-lambda", self.cascade_lambda);
        number("--shadow-distance", self.shadow_distance);
        number("--cascade-blend", self.cascade_blend);
        if self.no_warp_limit {
            flags.push(("--no-warp-limit", "--no-warp-limit".to_string()));
        }
        if let Some(with) = self.sppsm_with {
            flags.push((
                "--sppsm-with",
                format!(
                    "--sppsm-with {}",
                    with.to_possible_value()
                        .map_or("psm".into(), |v| v.get_name().to_string())
                ),
            ));
        }
        if let Some(n) = self.sppsm_iterations {
            flags.push(("--sppsm-iterations", format!("--sppsm-iterations {n}")));
        }
        if let Some(k) = self.cascades {
            flags.push(("--cascades", format!("--cascades {k}")));
        }
        if let Some(split) = self.cascade_split {
            let value = match split {
                CascadeSplitArg::Practical => "practical".to_string(),
                CascadeSplitArg::Log => "log".to_string(),
                CascadeSplitArg::Uniform => "uniform".to_string(),
                CascadeSplitArg::FirstThenLog(d) => format!("first-log:{d}"),
                CascadeSplitArg::Distances(n, d) => d[..n]
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(","),
            };
            flags.push(("--cascade-split", format!("--cascade-split {value}")));
        }
        if let Some(fit) = self.cascade_fit {
            flags.push((
                "--cascade-fit",
                format!(
                    "--cascade-fit {}",
                    fit.to_possible_value()
                        .map_or("lispsm".into(), |v| v.get_name().to_string())
                ),
            ));
        }
        if self.stable {
            flags.push(("--stable", "--stable".to_string()));
        }
        if self.equal_texels {
            flags.push(("--equal-texels", "--equal-texels".to_string()));
        }
        if self.cascade_adaptive {
            flags.push(("--cascade-adaptive", "--cascade-adaptive".to_string()));
        }
        if let Some(select) = self.cascade_select {
            flags.push((
                "--cascade-select",
                format!(
                    "--cascade-select {}",
                    select
                        .to_possible_value()
                        .map_or("auto".into(), |v| v.get_name().to_string())
                ),
            ));
        }
        flags
    }

    /// Refuses a parameter that none of `techniques` (with the parameters applied) reads.
    pub fn check_used_by(&self, techniques: &[Technique]) -> Result<(), UsageError> {
        if self.tsm_xi.is_some() && self.tsm_focus.is_none() {
            return Err(UsageError::new(
                "--tsm-xi places the focus line of --tsm-focus (the 80% rule); give both",
            ));
        }
        let read: Vec<&str> = techniques.iter().flat_map(options_read_by).collect();
        if let Some((option, _)) = self.flags().into_iter().find(|(o, _)| !read.contains(o)) {
            let names: Vec<&str> = techniques
                .iter()
                .map(gnomon::ShadowTechnique::name)
                .collect();
            return Err(UsageError::new(format!(
                "{option} does nothing for {}",
                names.join(", ")
            )));
        }
        Ok(())
    }

    /// `technique` with these parameters.
    pub fn apply(&self, technique: Technique) -> Technique {
        let limit = !self.no_warp_limit;
        match technique {
            Technique::Lispsm(mut t) => {
                t.n = self.lispsm_n.or(t.n);
                t.limit &= limit;
                Technique::Lispsm(t)
            }
            Technique::Tsm(mut t) => {
                t.xi = self.tsm_xi.unwrap_or(t.xi);
                t.focus = self.tsm_focus.or(t.focus);
                t.limit &= limit;
                Technique::Tsm(t)
            }
            Technique::Psm(mut t) => {
                t.slide_back = self.psm_slide_back.or(t.slide_back);
                t.limit &= limit;
                Technique::Psm(t)
            }
            Technique::Xpsm(mut t) => {
                t.coef = self.xpsm_coef.unwrap_or(t.coef);
                t.epsilon_w = self.xpsm_epsilon_w.unwrap_or(t.epsilon_w);
                t.limit &= limit;
                Technique::Xpsm(t)
            }
            Technique::Sppsm(t) => Technique::Sppsm(self.apply_sppsm(t)),
            Technique::Cascades(t) => Technique::Cascades(self.apply_cascades(t)),
            other => other,
        }
    }

    /// SPPSM with its perspective map and that map's own parameters, as for the technique
    /// alone.
    fn apply_sppsm(&self, mut t: gnomon::Sppsm) -> gnomon::Sppsm {
        if let Some(with) = self.sppsm_with {
            t.perspective = match with {
                SppsmWithArg::Psm => PerspectiveMap::Psm(Default::default()),
                SppsmWithArg::Lispsm => PerspectiveMap::Lispsm(Default::default()),
                SppsmWithArg::Tsm => PerspectiveMap::Tsm(Default::default()),
                SppsmWithArg::Xpsm => PerspectiveMap::Xpsm(Default::default()),
            };
        }
        t.perspective = match self.apply(perspective_technique(t.perspective)) {
            Technique::Psm(p) => PerspectiveMap::Psm(p),
            Technique::Lispsm(p) => PerspectiveMap::Lispsm(p),
            Technique::Tsm(p) => PerspectiveMap::Tsm(p),
            Technique::Xpsm(p) => PerspectiveMap::Xpsm(p),
            _ => t.perspective,
        };
        t.iterations = self.sppsm_iterations.unwrap_or(t.iterations);
        t
    }

    /// Cascades with their split, fit (and the fit's own parameters), blend and selection.
    fn apply_cascades(&self, mut t: gnomon::Cascades) -> gnomon::Cascades {
        t.count = self.cascades.unwrap_or(t.count);
        t.split = self.split(t.split);
        t.shadow_distance = self.shadow_distance.or(t.shadow_distance);
        if let Some(fit) = self.cascade_fit {
            t.fit = match fit {
                CascadeFitArg::Focused => CascadeFit::Focused,
                CascadeFitArg::Lispsm => CascadeFit::Lispsm(Default::default()),
                CascadeFitArg::Tsm => CascadeFit::Tsm(Default::default()),
                CascadeFitArg::Xpsm => CascadeFit::Xpsm(Default::default()),
                CascadeFitArg::Psm => CascadeFit::Psm(Default::default()),
            };
        }
        t.fit = match fit_technique(t.fit).map(|f| self.apply(f)) {
            Some(Technique::Lispsm(f)) => CascadeFit::Lispsm(f),
            Some(Technique::Tsm(f)) => CascadeFit::Tsm(f),
            Some(Technique::Xpsm(f)) => CascadeFit::Xpsm(f),
            Some(Technique::Psm(f)) => CascadeFit::Psm(f),
            _ => t.fit,
        };
        t.blend = self.cascade_blend.unwrap_or(t.blend);
        t.stable |= self.stable;
        t.equal_texels |= self.equal_texels;
        t.adaptive |= self.cascade_adaptive;
        if let Some(select) = self.cascade_select {
            t.select = match select {
                CascadeSelectArg::Auto => CascadeSelect::Auto,
                CascadeSelectArg::Depth => CascadeSelect::ViewDepth,
                CascadeSelectArg::Coverage => CascadeSelect::Coverage,
            };
        }
        t
    }

    /// The split rule: the one given, else the technique's with the lambda given.
    fn split(&self, split: CascadeSplit) -> CascadeSplit {
        let lambda = match split {
            CascadeSplit::Practical { lambda } => lambda,
            _ => 0.5,
        };
        let lambda = self.cascade_lambda.unwrap_or(lambda);
        match self.cascade_split {
            None => match split {
                CascadeSplit::Practical { .. } => CascadeSplit::Practical { lambda },
                other => other,
            },
            Some(CascadeSplitArg::Practical) => CascadeSplit::Practical { lambda },
            Some(CascadeSplitArg::Log) => CascadeSplit::Log,
            Some(CascadeSplitArg::Uniform) => CascadeSplit::Uniform,
            Some(CascadeSplitArg::FirstThenLog(first)) => CascadeSplit::FirstThenLog { first },
            Some(CascadeSplitArg::Distances(count, depths)) => {
                CascadeSplit::Distances { count, depths }
            }
        }
    }
}

/// A parameter's value as a binding passes it: a flag's on or off, or an option's value
/// as text.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// A flag (`stable`, `no_warp_limit`, ...).
    Flag(bool),
    /// An option's value, as it would be written on the command line.
    Text(String),
}

impl TechniqueParams {
    /// The parameters of command-line words (`["--cascades", "3", "--stable"]`), with the
    /// command line's messages for bad ones.
    pub fn parse_words<S: AsRef<str>>(words: &[S]) -> Result<Self, UsageError> {
        let command = Self::augment_args(clap::Command::new("parameters").no_binary_name(true));
        let matches = command
            .try_get_matches_from(words.iter().map(AsRef::as_ref))
            .map_err(|e| UsageError::new(first_line(&e.to_string())))?;
        <Self as clap::FromArgMatches>::from_arg_matches(&matches)
            .map_err(|e| UsageError::new(first_line(&e.to_string())))
    }

    /// The parameters by name, as the bindings take them: the options' names with `_` for
    /// `-` and without the dashes (`cascade_split`, `stable`).
    pub fn from_named(values: &[(String, ParamValue)]) -> Result<Self, UsageError> {
        let command = Self::augment_args(clap::Command::new("parameters"));
        let mut words = Vec::new();
        for (name, value) in values {
            let Some(arg) = command
                .get_arguments()
                .find(|a| a.get_id() == name.as_str())
            else {
                let known: Vec<&str> = command
                    .get_arguments()
                    .map(|a| a.get_id().as_str())
                    .collect();
                return Err(UsageError::new(format!(
                    "unknown parameter '{name}' (known: {})",
                    known.join(", ")
                )));
            };
            let long = format!("--{}", arg.get_long().unwrap_or(name));
            let is_flag = matches!(arg.get_action(), clap::ArgAction::SetTrue);
            match (value, is_flag) {
                (ParamValue::Flag(true), true) => words.push(long),
                (ParamValue::Flag(false), true) => {}
                (ParamValue::Text(text), false) => words.push(format!("{long}={text}")),
                (ParamValue::Flag(_), false) => {
                    return Err(UsageError::new(format!(
                        "{name} takes a value, not True or False"
                    )));
                }
                (ParamValue::Text(_), true) => {
                    return Err(UsageError::new(format!("{name} is True or False")));
                }
            }
        }
        Self::parse_words(&words)
    }
}

/// The message of a clap error, on one line, without its `error: ` prefix.
fn first_line(text: &str) -> String {
    let lines: Vec<&str> = text
        .lines()
        .take_while(|l| !l.trim().is_empty())
        .map(str::trim)
        .collect();
    lines.join(" ").trim_start_matches("error: ").to_string()
}
