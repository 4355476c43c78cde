//! The `gnomon` binary: the command line of [`gnomon_cli`].

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    gnomon_cli::main()
}
