//! Argument parsing and dispatch to subcommands.

use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(name = "trax", version, about = "TRaX-Rust toolchain and ray-tracing hardware simulator")]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
}

pub fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    match cli.command {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_is_well_formed() {
        Cli::command().debug_assert();
    }
}
