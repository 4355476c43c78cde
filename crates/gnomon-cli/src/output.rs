//! Output files checked before any work, and standard output that a closed pipe ends quietly.

use std::io::Write;
use std::path::Path;

use crate::CliError;

/// Checks, before any work, that `path` (the option `option`) can be written as one of
/// `extensions` (lower case, without the dot): the extension names the format, the path is
/// not a folder, its folder exists (no folders are made for it), and a file can be made or
/// opened there. Nothing is left behind.
pub fn check_output(option: &str, path: &Path, extensions: &[&str]) -> Result<(), CliError> {
    let shown = path.display();
    if path.is_dir() {
        return Err(CliError::usage(format!(
            "{option} {shown} is a folder; give a file name"
        )));
    }
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !extension
        .as_deref()
        .is_some_and(|e| extensions.contains(&e))
    {
        let wanted: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
        return Err(CliError::usage(format!(
            "{option} {shown}: the file must end in {}",
            wanted.join(" or ")
        )));
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(CliError::usage(format!(
            "{option} {shown}: the folder {} does not exist",
            folder.display()
        )));
    }
    writable(path).map_err(|e| CliError::usage(format!("{option} {shown} cannot be written: {e}")))
}

/// Opens `path` for appending if it exists, else makes it and removes it again. Another
/// command checking the same path at the same moment (two renders to the default
/// `frame.png`) can make or remove it between the steps: either outcome shows the folder
/// takes the file, so neither is an error.
fn writable(path: &Path) -> std::io::Result<()> {
    use std::io::ErrorKind::{AlreadyExists, NotFound};
    let gone_is_fine = |done: std::io::Result<()>| match done {
        Err(e) if e.kind() == NotFound => Ok(()),
        done => done,
    };
    let append = || {
        let opened = std::fs::OpenOptions::new().append(true).open(path);
        gone_is_fine(opened.map(|_| ()))
    };
    if path.exists() {
        return append();
    }
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
    {
        Ok(_) => gone_is_fine(std::fs::remove_file(path)),
        Err(e) if e.kind() == AlreadyExists => append(),
        Err(e) => Err(e),
    }
}

/// Checks every output of a command (option, path, formats) and that no two are the same
/// file.
pub fn check_outputs(outputs: &[(&str, &Path, &[&str])]) -> Result<(), CliError> {
    for (k, (option, path, extensions)) in outputs.iter().enumerate() {
        check_output(option, path, extensions)?;
        if let Some((other, _, _)) = outputs[..k].iter().find(|(_, p, _)| p == path) {
            return Err(CliError::usage(format!(
                "{other} and {option} name the same file, {}",
                path.display()
            )));
        }
    }
    Ok(())
}

/// The progress bar of a long command: `steps` frames or rows, the current one named in its
/// message, on standard error.
pub fn progress_bar(steps: usize) -> indicatif::ProgressBar {
    let progress = indicatif::ProgressBar::new(steps as u64);
    progress.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} ({elapsed})")
            .expect("a valid template"),
    );
    progress
}

/// Writes `text` to standard output. When the reader has gone (`gnomon analyze | head`), the
/// program ends quietly with success, as command-line tools do.
pub fn print(text: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// `println!` through [`print`].
#[macro_export]
macro_rules! say {
    () => { $crate::output::print("\n") };
    ($($arg:tt)*) => { $crate::output::print(&format!("{}\n", format_args!($($arg)*))) };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Commands that check the same default output at once (the CLI tests run `render`
    /// without `--out` in parallel) each find it writable, and none leaves a file behind.
    #[test]
    fn checks_of_one_path_at_once_all_pass() {
        let dir = std::env::temp_dir().join(format!("gnomon-check-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("frame.png");
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| {
                    for _ in 0..500 {
                        check_output("--out", &path, &["png"]).unwrap();
                    }
                });
            }
        });
        assert!(!path.exists());
        let folder = dir.join("folder.png");
        std::fs::create_dir(&folder).unwrap();
        assert!(check_output("--out", &folder, &["png"]).is_err());
        assert!(check_output("--out", &dir.join("frame.jpg"), &["png"]).is_err());
        assert!(check_output("--out", &dir.join("none/frame.png"), &["png"]).is_err());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
