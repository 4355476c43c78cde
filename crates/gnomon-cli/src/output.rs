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
    let writable = if path.exists() {
        std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map(|_| ())
    } else {
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .and_then(|_| std::fs::remove_file(path))
    };
    writable.map_err(|e| CliError::usage(format!("{option} {shown} cannot be written: {e}")))
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
