//! `trax config list` (the chip presets, one line each) and `trax config show NAME|FILE
//! [--set PATH=VALUE ..]` (the complete, resolved config as TOML with every field's
//! documentation as comments: a file to copy, edit and pass with `--config FILE`).

use std::process::ExitCode;

use clap::{Args, Subcommand};
use trax::pipeline::{chip_config, chip_label};
use trax_emulator::timing::{ChipConfig, CHIP_PRESETS};

use super::run::{fail, parse_set};

/// Arguments of `trax config`.
#[derive(Args, Debug)]
pub struct ConfigArgs {
    #[command(subcommand)]
    command: ConfigCommand,
}

#[derive(Subcommand, Debug)]
enum ConfigCommand {
    /// List the chip presets with their shape, caches, DRAM and stream memory.
    List,
    /// Print a chip config, every field resolved (preset, file and overrides applied), as
    /// TOML with each field's meaning, unit and default as a comment.
    Show(ShowArgs),
}

/// Arguments of `trax config show`.
#[derive(Args, Debug)]
struct ShowArgs {
    /// A preset (`trax config list`) or a TOML file.
    config: String,
    /// Set a field by its dotted path, as `trax run --set` does.
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = parse_set)]
    set: Vec<(String, toml::Value)>,
}

/// Runs `trax config`.
pub fn run(a: ConfigArgs) -> ExitCode {
    match a.command {
        ConfigCommand::List => {
            print!("{}", list());
            ExitCode::SUCCESS
        }
        ConfigCommand::Show(s) => match show(&s.config, &s.set) {
            Ok(text) => {
                print!("{text}");
                ExitCode::SUCCESS
            }
            Err(e) => fail(e),
        },
    }
}

/// `N KiB`/`N MiB` for a byte count.
fn bytes(b: u64) -> String {
    match b {
        b if b >= 1 << 20 && b % (1 << 20) == 0 => format!("{} MiB", b >> 20),
        b if b >= 1 << 10 && b % (1 << 10) == 0 => format!("{} KiB", b >> 10),
        b => format!("{b} B"),
    }
}

/// One line describing a chip: shape, caches, DRAM, stream memory, pipelines.
pub fn describe(c: &ChipConfig) -> String {
    let l2s = c.tms.div_ceil(c.tms_per_l2);
    let dram = match c.memory.dram.model {
        trax_emulator::memsys::DramModel::Simple => format!(
            "simple DRAM ({} cycles, {} B/cycle)",
            c.memory.dram.simple.latency, c.memory.dram.simple.bandwidth_bytes_per_cycle
        ),
        trax_emulator::memsys::DramModel::Detailed => format!(
            "detailed DRAM ({:.0} GB/s)",
            c.memory.dram.detailed.peak_gbps()
        ),
    };
    let mut s = format!(
        "{} TMs x {} threads at {} GHz, L1 {}, {} L2 of {} each, {dram}",
        c.tms,
        c.threads_per_tm,
        c.clock_ghz,
        bytes(u64::from(c.memory.l1.capacity_bytes)),
        l2s,
        bytes(u64::from(c.memory.l2.capacity_bytes)),
    );
    if c.stream_memory.capacity_bytes > 0 {
        s += &format!(
            ", {} stream memory",
            bytes(u64::from(c.stream_memory.capacity_bytes))
        );
    }
    if c.pipe_modes() > 1 {
        s += ", pipelines";
    }
    s
}

/// The text of `trax config list`.
fn list() -> String {
    let mut s = String::new();
    for name in CHIP_PRESETS {
        if let Some(c) = ChipConfig::preset(name) {
            s += &format!("{name:<14} {}\n", describe(&c));
        }
    }
    s += "\n`trax config show NAME` prints one in full, as a TOML file to copy and edit;\n\
          a file may also start with `preset = \"NAME\"` and set only what differs.\n";
    s
}

/// The text of `trax config show`.
fn show(config: &str, sets: &[(String, toml::Value)]) -> Result<String, String> {
    let chip = chip_config(config, sets, None, None, None)?;
    let label = chip_label(config, sets, None, None, None);
    let header = vec![
        format!("chip: {label}"),
        describe(&chip),
        "Every field resolved: save this as FILE.toml, edit it and run with --config FILE.toml."
            .into(),
        "(A file may instead start with preset = \"NAME\" and list only what differs.)".into(),
    ];
    Ok(chip.to_documented_toml(&header))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn list_names_every_preset() {
        let text = list();
        for p in CHIP_PRESETS {
            assert!(
                text.lines().any(|l| l.starts_with(&format!("{p} "))),
                "{text}"
            );
        }
        assert!(text.contains("80 TMs x 32 threads"), "{text}");
    }

    /// `show` gives a file that loads back as the same chip, overrides included, and
    /// bad input an error naming it.
    #[test]
    fn show_prints_a_loadable_resolved_config() {
        let sets = vec![(
            "memory.l2.capacity_bytes".to_string(),
            toml::Value::Integer(524288),
        )];
        let text = show("baseline", &sets).unwrap();
        assert!(
            text.starts_with("# chip: baseline + 1 override (memory.l2.capacity_bytes=524288)\n"),
            "{text}"
        );
        assert!(text.contains("# Thread multiprocessors."), "{text}");
        let dir = std::env::temp_dir().join(format!("trax-config-show-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("mine.toml");
        std::fs::write(&file, &text).unwrap();
        let back = chip_config(file.to_str().unwrap(), &[], None, None, None).unwrap();
        let want = chip_config("baseline", &sets, None, None, None).unwrap();
        assert_eq!(back.memory, want.memory);
        assert_eq!(back.units, want.units);
        let e = show("no-such-chip", &[]).unwrap_err();
        assert!(
            e.contains("no-such-chip") && e.contains("strata-plus"),
            "{e}"
        );
        assert!(e.contains("trax config list"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
