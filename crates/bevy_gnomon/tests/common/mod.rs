//! What the Bevy tests share: the image size and the example's options for a view.

use clap::Parser;
use gnomon_scene::NamedView;

use crate::args;

/// The tests' image size.
pub const SIZE: (u32, u32) = (640, 360);

/// A mask's value for a pixel not judged.
pub const NOT_JUDGED: u8 = 128;

/// The options the example would get for a view and whose shadows (`bevy`, or gnomon's
/// technique and its options, as the example takes them).
pub fn options(view: &str, shadows: &str, views: &[NamedView]) -> args::Options {
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let mut words = vec!["scene", "--view", view, "--size", &size];
    match shadows {
        "bevy" => words.extend(["--shadows", "bevy"]),
        technique => {
            words.extend(["--shadows", "gnomon", "--technique"]);
            words.extend(technique.split_whitespace());
        }
    }
    let cli = args::Cli::try_parse_from(words).unwrap();
    args::options(cli, views).unwrap()
}
