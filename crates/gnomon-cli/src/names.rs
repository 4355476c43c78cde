//! One registry of what the commands draw, by name: the core's shadow-map techniques
//! ([`gnomon::Technique`]), the exact shadow volumes with each way of counting them, planar
//! projected shadows, and `compare`'s extra row. Every command (and the viewer) parses technique names here.

use gnomon::{ShadowTechnique, Technique};
use gnomon_render::{MapRead, StencilMode};

/// The exact shadow volumes, one name per way of counting.
pub const VOLUMES: [(&str, StencilMode); 3] = [
    ("volumes", StencilMode::ZFail),
    ("volumes-z-pass", StencilMode::ZPass),
    ("volumes-per-caster", StencilMode::PerCaster),
];

/// Planar projected shadows (the shadows lecture's "projection to a plane"): the casters
/// flattened onto the ground's top face (or `--receiver-plane`); nothing else is shadowed.
pub const PLANAR: &str = "planar";

/// Projective texture shadows (the lecture's light maps) on the focused map's projection:
/// casters' coverage projected onto whatever lies behind or in front of them, casters lit.
pub const PROJECTIVE: &str = "projective";

/// Object-ID shadow maps (the lecture's "Object ID Shadows") on the focused map's projection:
/// shadowed where the map holds another object's ID; no bias, no self-shadowing.
pub const OBJECT_ID: &str = "object-id";

/// Object IDs and depth (the lecture's "Combining Shadow and Object Maps"): another object's
/// ID shadows, an object's own texels compare depth.
pub const ID_DEPTH: &str = "id-depth";

/// The lecture's light-space maps read otherwise than by depth, each on the focused map's
/// projection, by name.
pub const MAP_READS: [(&str, MapRead); 3] = [
    (PROJECTIVE, MapRead::Coverage),
    (OBJECT_ID, MapRead::ObjectId),
    (ID_DEPTH, MapRead::IdDepth),
];

/// `compare`'s row of SPPSM with two maps of half the area each (the texels of one map).
pub const SPPSM_SAME_TEXELS: &str = "sppsm-same-texels";

/// `compare`'s row of dual paraboloid maps with the texels of a cube's six faces (two maps of
/// three times the area each).
pub const PARABOLOID_CUBE_TEXELS: &str = "paraboloid-cube-texels";

/// `compare`'s cascade rows, each four cascades sharing the texels of one map (what the
/// engines ship, and ours), with the options that give them:
/// - `cascades-stable`: stable focused cascades, the first slice to 10 m then logarithmic to
///   the far plane, a blend band of 0.2 (Bevy's defaults, as Godot and Unity fit them), each
///   point reading the finest map whose square holds it (stable cascades' default; Bevy picks
///   by view depth, `--cascade-select depth`);
/// - `cascades-lispsm`: LiSPSM in each cascade, the practical split with lambda 0.5, a band
///   of 0.1 (Filament's way);
/// - `cascades-best`: gnomon's best measured configuration: LiSPSM in each cascade (with the
///   warp limit), the practical split with lambda 0.5, no blend band, and the number of
///   cascades (1 to 4) chosen per view: 1, 2, ... while the median undersampling over the
///   view samples falls (`--cascade-adaptive`; log splits, other lambdas, other counts and
///   the other fits all measured worse: the book's cascades page).
pub const CASCADE_ROWS: [(&str, &str); 3] = [
    (
        "cascades-stable",
        "--cascades 4 --stable --cascade-split first-log:10 --cascade-blend 0.2 --equal-texels",
    ),
    (
        "cascades-lispsm",
        "--cascades 4 --cascade-fit lispsm --cascade-split practical --cascade-lambda 0.5 --cascade-blend 0.1 --equal-texels",
    ),
    (
        "cascades-best",
        "--cascades 4 --cascade-fit lispsm --cascade-split practical --cascade-lambda 0.5 --cascade-blend 0 --equal-texels --cascade-adaptive",
    ),
];

/// Something a command draws: a shadow-map technique or the exact volumes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drawn {
    /// A shadow-map technique (default parameters).
    Map(Technique),
    /// Stenciled shadow volumes, counted as the mode says.
    Volumes(StencilMode),
    /// Planar projected shadows on one receiver plane ([`PLANAR`]).
    Planar,
    /// The focused map read otherwise than by depth ([`MAP_READS`]: projective texture
    /// shadows).
    Read(MapRead),
}

impl Drawn {
    /// By name: a technique of [`Technique::NAMES`] or one of [`VOLUMES`].
    pub fn parse(name: &str) -> Result<Self, String> {
        let name = name.trim();
        if let Some((_, mode)) = VOLUMES.iter().find(|(n, _)| *n == name) {
            return Ok(Drawn::Volumes(*mode));
        }
        if name == PLANAR {
            return Ok(Drawn::Planar);
        }
        if let Some((_, read)) = MAP_READS.iter().find(|(n, _)| *n == name) {
            return Ok(Drawn::Read(*read));
        }
        name.parse::<Technique>()
            .map(Drawn::Map)
            .map_err(|_| format!("unknown technique '{name}' (known: {})", known(true)))
    }

    /// The map technique it sets up, if any (the map reads of [`MAP_READS`]: the focused
    /// map's).
    pub fn map_technique(&self) -> Option<Technique> {
        match self {
            Drawn::Map(t) => Some(*t),
            Drawn::Read(_) => Some(Technique::Focused(Default::default())),
            Drawn::Volumes(_) | Drawn::Planar => None,
        }
    }

    /// Its name.
    pub fn name(&self) -> &'static str {
        match self {
            Drawn::Map(t) => t.name(),
            Drawn::Volumes(mode) => {
                VOLUMES
                    .iter()
                    .find(|(_, m)| m == mode)
                    .expect("every mode has a name")
                    .0
            }
            Drawn::Planar => PLANAR,
            Drawn::Read(read) => read_name(*read),
        }
    }

    /// How the main pass reads its maps ([`MapRead::Depth`] for every map technique).
    pub fn map_read(&self) -> MapRead {
        match self {
            Drawn::Read(read) => *read,
            _ => MapRead::Depth,
        }
    }
}

/// The name of a map read of [`MAP_READS`], or the depth read's technique name `focused`.
pub fn read_name(read: MapRead) -> &'static str {
    MAP_READS
        .iter()
        .find(|(_, r)| *r == read)
        .map_or("focused", |(n, _)| n)
}

/// A shadow-map technique by name (the commands that need a map: setup, analyze, compare,
/// demo).
pub fn parse_map(name: &str) -> Result<Technique, String> {
    match Drawn::parse(name)? {
        Drawn::Map(t) => Ok(t),
        Drawn::Volumes(_) | Drawn::Planar | Drawn::Read(_) => Err(format!(
            "'{name}' draws no shadow map; this needs a shadow-map technique (known: {})",
            known(false)
        )),
    }
}

/// The known names, comma-separated, with the volumes' when `volumes`.
pub fn known(volumes: bool) -> String {
    let mut names: Vec<&str> = Technique::NAMES.to_vec();
    if volumes {
        names.extend(VOLUMES.iter().map(|(n, _)| *n));
        names.push(PLANAR);
        names.extend(MAP_READS.iter().map(|(n, _)| *n));
    }
    names.join(", ")
}

/// `Drawn::parse` as a clap value parser.
pub fn drawn_arg(name: &str) -> Result<Drawn, String> {
    Drawn::parse(name)
}

/// `parse_map` as a clap value parser.
pub fn map_arg(name: &str) -> Result<Technique, String> {
    parse_map(name)
}

/// The scene as `drawn` draws it: projective shadows keep the ground as a receiver only (a
/// casting ground would cover the whole light map, and casters are lit), everything else as
/// it is.
pub fn drawn_scene(
    drawn: Drawn,
    mut scene: gnomon_render::RenderScene,
) -> gnomon_render::RenderScene {
    if drawn.map_read() == gnomon_render::MapRead::Coverage {
        for instance in scene.instances.iter_mut().filter(|i| i.name == "ground") {
            instance.casts = false;
        }
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_to_itself() {
        for name in Technique::NAMES
            .iter()
            .chain(VOLUMES.iter().map(|(n, _)| n))
            .chain([&PLANAR])
            .chain(MAP_READS.iter().map(|(n, _)| n))
        {
            assert_eq!(Drawn::parse(name).unwrap().name(), *name);
        }
        assert!(
            Drawn::parse("nope")
                .unwrap_err()
                .contains("volumes-per-caster")
        );
        assert!(parse_map("volumes").is_err());
        assert_eq!(parse_map("lispsm").unwrap().name(), "lispsm");
    }
}
