//! Scripted input for deterministic viewer runs: one JSON object a line, indexed by frame
//! (`{"frame": 3, "key": "W", "down": true}`, `{"frame": 5, "drag": [dx, dy], "button":
//! "right"}`, `{"frame": 9, "scroll": 2}`), so that a run does the same whatever the frame rate.

use std::fmt;

/// A key the viewer knows, by the name a script gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Key {
    /// W: fly forward.
    W,
    /// A: fly left.
    A,
    /// S: fly back.
    S,
    /// D: fly right.
    D,
    /// Q: fly down.
    Q,
    /// E: fly up.
    E,
    /// Shift: fly four times faster.
    Shift,
    /// Left arrow: the sun's azimuth down.
    Left,
    /// Right arrow: the sun's azimuth up.
    Right,
    /// Up arrow: the sun higher.
    Up,
    /// Down arrow: the sun lower.
    Down,
    /// C: print (and copy) the `gnomon render` command of the frame.
    C,
    /// F1: the help overlay.
    F1,
    /// F12: a screenshot.
    F12,
    /// Escape: quit.
    Escape,
}

impl Key {
    /// Every key, with its name in scripts.
    pub const ALL: [(Key, &'static str); 15] = [
        (Key::W, "W"),
        (Key::A, "A"),
        (Key::S, "S"),
        (Key::D, "D"),
        (Key::Q, "Q"),
        (Key::E, "E"),
        (Key::Shift, "Shift"),
        (Key::Left, "Left"),
        (Key::Right, "Right"),
        (Key::Up, "Up"),
        (Key::Down, "Down"),
        (Key::C, "C"),
        (Key::F1, "F1"),
        (Key::F12, "F12"),
        (Key::Escape, "Escape"),
    ];

    /// The key named `name` (case-insensitive).
    pub fn named(name: &str) -> Option<Key> {
        Self::ALL
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name.trim()))
            .map(|(k, _)| *k)
    }
}

/// The mouse button of a drag: what it moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DragButton {
    /// Left: orbit around the target.
    Left,
    /// Right: mouse look.
    Right,
    /// Middle: the sun.
    Middle,
}

/// One input of a script or of the window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    /// A key pressed (`down`) or released.
    Key {
        /// Which key.
        key: Key,
        /// Pressed or released.
        down: bool,
    },
    /// The mouse moved by `delta` pixels with `button` held.
    Drag {
        /// The motion in pixels, x right and y down.
        delta: [f64; 2],
        /// The button held.
        button: DragButton,
    },
    /// The wheel turned by `steps` notches (positive: toward the target).
    Scroll(f64),
}

/// A script's inputs, each with the frame (counted from 0) before which it applies.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Script {
    events: Vec<(u64, Input)>,
}

/// A line of a script that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptError {
    /// The line, from 1.
    pub line: usize,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for ScriptError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for ScriptError {}

impl Script {
    /// Reads a script: one JSON object a line (blank lines skipped), each with a `frame` and
    /// one of `key` (with `down`), `drag` (with `button`) and `scroll`.
    pub fn parse(text: &str) -> Result<Self, ScriptError> {
        let mut events = Vec::new();
        for (i, line) in text.lines().enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            let error = |message: String| ScriptError {
                line: i + 1,
                message,
            };
            let value: serde_json::Value =
                serde_json::from_str(line).map_err(|e| error(format!("not JSON: {e}")))?;
            let object = value
                .as_object()
                .ok_or_else(|| error("expected a JSON object".into()))?;
            let frame = object
                .get("frame")
                .and_then(serde_json::Value::as_u64)
                .ok_or_else(|| error("'frame' must be a whole number from 0".into()))?;
            let kinds: Vec<&str> = ["key", "drag", "scroll"]
                .into_iter()
                .filter(|k| object.contains_key(*k))
                .collect();
            if kinds.len() != 1 {
                return Err(error(
                    "give exactly one of 'key', 'drag' and 'scroll'".into(),
                ));
            }
            let known: &[&str] = match kinds[0] {
                "key" => &["frame", "key", "down"],
                "drag" => &["frame", "drag", "button"],
                _ => &["frame", "scroll"],
            };
            if let Some(unknown) = object.keys().find(|k| !known.contains(&k.as_str())) {
                return Err(error(format!("unknown field '{unknown}'")));
            }
            let input = match kinds[0] {
                "key" => {
                    let name = object["key"]
                        .as_str()
                        .ok_or_else(|| error("'key' must be a string".into()))?;
                    let key = Key::named(name).ok_or_else(|| {
                        let names: Vec<&str> = Key::ALL.iter().map(|(_, n)| *n).collect();
                        error(format!(
                            "unknown key '{name}' (known: {})",
                            names.join(", ")
                        ))
                    })?;
                    let down = object
                        .get("down")
                        .and_then(serde_json::Value::as_bool)
                        .ok_or_else(|| error("a key needs 'down': true or false".into()))?;
                    Input::Key { key, down }
                }
                "drag" => {
                    let delta = object["drag"]
                        .as_array()
                        .filter(|a| a.len() == 2)
                        .and_then(|a| Some([a[0].as_f64()?, a[1].as_f64()?]))
                        .ok_or_else(|| error("'drag' must be [dx, dy] in pixels".into()))?;
                    let button = match object.get("button").and_then(serde_json::Value::as_str) {
                        Some("left") => DragButton::Left,
                        Some("right") => DragButton::Right,
                        Some("middle") => DragButton::Middle,
                        _ => {
                            return Err(error(
                                "a drag needs 'button': \"left\", \"right\" or \"middle\"".into(),
                            ));
                        }
                    };
                    Input::Drag { delta, button }
                }
                _ => Input::Scroll(
                    object["scroll"]
                        .as_f64()
                        .ok_or_else(|| error("'scroll' must be a number of notches".into()))?,
                ),
            };
            if let Input::Drag { delta: d, .. } = input
                && !(d[0].is_finite() && d[1].is_finite())
            {
                return Err(error("'drag' must be finite".into()));
            }
            events.push((frame, input));
        }
        // Stable: inputs of one frame keep the script's order.
        events.sort_by_key(|(frame, _)| *frame);
        Ok(Self { events })
    }

    /// The inputs that apply before frame `frame`, in the script's order.
    pub fn at(&self, frame: u64) -> impl Iterator<Item = Input> + '_ {
        let start = self.events.partition_point(|(f, _)| *f < frame);
        self.events[start..]
            .iter()
            .take_while(move |(f, _)| *f == frame)
            .map(|(_, input)| *input)
    }

    /// The last frame with an input (none: 0).
    pub fn last_frame(&self) -> u64 {
        self.events.last().map_or(0, |(f, _)| *f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_three_kinds_in_frame_order() {
        let script = Script::parse(
            "{\"frame\": 5, \"drag\": [10, -4.5], \"button\": \"right\"}\n\n\
             {\"frame\": 3, \"key\": \"w\", \"down\": true}\n\
             {\"frame\": 5, \"scroll\": 2}\n",
        )
        .unwrap();
        assert_eq!(
            script.at(3).collect::<Vec<_>>(),
            [Input::Key {
                key: Key::W,
                down: true
            }]
        );
        assert_eq!(
            script.at(5).collect::<Vec<_>>(),
            [
                Input::Drag {
                    delta: [10.0, -4.5],
                    button: DragButton::Right
                },
                Input::Scroll(2.0)
            ]
        );
        assert_eq!(script.at(4).count(), 0);
        assert_eq!(script.last_frame(), 5);
    }

    #[test]
    fn a_bad_line_is_named() {
        for (text, needle) in [
            (
                "{\"frame\": 1, \"key\": \"Z\", \"down\": true}",
                "unknown key 'Z'",
            ),
            ("{\"frame\": -1, \"scroll\": 1}", "'frame'"),
            ("{\"frame\": 1}", "exactly one"),
            (
                "{\"frame\": 1, \"scroll\": 1, \"key\": \"W\"}",
                "exactly one",
            ),
            (
                "{\"frame\": 1, \"drag\": [1], \"button\": \"left\"}",
                "[dx, dy]",
            ),
            (
                "{\"frame\": 1, \"drag\": [1, 2], \"button\": \"side\"}",
                "'button'",
            ),
            ("{\"frame\": 1, \"key\": \"W\"}", "'down'"),
            (
                "{\"frame\": 1, \"scroll\": 1, \"speed\": 2}",
                "unknown field 'speed'",
            ),
            ("frame 1", "not JSON"),
        ] {
            let error = Script::parse(&format!("\n{text}")).unwrap_err();
            assert_eq!(error.line, 2, "{text}");
            assert!(error.message.contains(needle), "{text}: {}", error.message);
        }
    }
}
