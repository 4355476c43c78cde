//! The `gnomon` binary as a user runs it, a module per command (one test binary, so that
//! the tests share its threads).

mod analyze;
mod bench;
mod common;
mod compare;
mod demo;
mod flicker;
mod options;
mod render;
mod scenes;
mod setup;
