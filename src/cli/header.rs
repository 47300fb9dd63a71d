//! `trax header -o DIR [--cpp]`: writes the generated kernel API headers for C (`trax.h`,
//! `trax_isa.h`) and C++ (`trax.hpp`) kernels, e.g. for an editor or another build system.
//! `trax build` does not need them: it puts its own copy on the include path.

use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `trax header`.
#[derive(Args, Debug)]
pub struct HeaderArgs {
    /// Directory to write the headers into (created if missing).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Also write the C++ layer `trax.hpp`.
    #[arg(long)]
    pub cpp: bool,
}

/// Runs `trax header`.
pub fn run(a: HeaderArgs) -> ExitCode {
    if let Err(e) = std::fs::create_dir_all(&a.output) {
        eprintln!("error: cannot create {}: {e}", a.output.display());
        return ExitCode::from(1);
    }
    for (name, text) in trax::clang::headers() {
        if name.ends_with(".hpp") && !a.cpp {
            continue;
        }
        let p = a.output.join(name);
        if let Err(e) = std::fs::write(&p, text) {
            eprintln!("error: cannot write {}: {e}", p.display());
            return ExitCode::from(1);
        }
        println!("{}", p.display());
    }
    ExitCode::SUCCESS
}
