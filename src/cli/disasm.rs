//! `trax disasm FILE.elf [--source]`: disassembles the executable sections, optionally
//! interleaving the source lines (from DWARF) that each run of instructions came from.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use trax_emulator::{demangle, DebugInfo, Executable};

/// Arguments of `trax disasm`.
#[derive(Args, Debug)]
pub struct DisasmArgs {
    /// The executable (ELF).
    pub file: PathBuf,
    /// Interleave source lines from the debug information.
    #[arg(long)]
    pub source: bool,
}

/// Runs `trax disasm`.
pub fn run(a: DisasmArgs) -> ExitCode {
    let path = a.file.display().to_string();
    let data = match std::fs::read(&a.file) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {path}: {e}");
            return ExitCode::FAILURE;
        }
    };
    match disassemble(&path, &data, a.source) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The disassembly listing of an executable.
pub fn disassemble(path: &str, data: &[u8], source: bool) -> Result<String, String> {
    let exe = Executable::parse(path, data).map_err(|e| e.to_string())?;
    let dbg = if source {
        Some(DebugInfo::parse(path, data).map_err(|e| e.to_string())?)
    } else {
        None
    };
    let mut out = String::new();
    let mut last_loc: Option<(String, u32)> = None;
    for seg in &exe.segments {
        let (start, end) = (
            seg.addr.max(exe.text_start),
            (seg.addr + seg.data.len() as u32).min(exe.text_end),
        );
        let mut pc = start;
        while pc + 4 <= end {
            if let Some(sym) = exe.symbols.iter().find(|s| s.addr == pc) {
                let _ = writeln!(out, "\n{pc:08x} <{}>:", demangle(&sym.name));
            }
            let o = (pc - seg.addr) as usize;
            let w = u32::from_le_bytes([
                seg.data[o],
                seg.data[o + 1],
                seg.data[o + 2],
                seg.data[o + 3],
            ]);
            if let Some(d) = &dbg {
                if let Some(f) = d.frames(pc).first() {
                    let key = (f.file.clone().unwrap_or_default(), f.line);
                    if last_loc.as_ref() != Some(&key) && f.line != 0 {
                        let text = f
                            .file
                            .as_deref()
                            .and_then(|file| d.source_line(file, f.line))
                            .unwrap_or_default();
                        let _ = writeln!(out, ";; {}: {}", f.location(), text.trim());
                        last_loc = Some(key);
                    }
                }
            }
            let inst = trax_emulator::decode(w);
            let _ = writeln!(out, "{pc:8x}:\t{w:08x}\t{inst}");
            pc += 4;
        }
    }
    Ok(out)
}
