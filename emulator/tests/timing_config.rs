//! Chip configuration: presets, TOML overrides, and errors that name the bad field.

use trax_emulator::memsys::DramModel;
use trax_emulator::timing::{ChipConfig, CHIP_PRESETS};

#[test]
fn presets_are_valid_and_baseline_is_table_2_5() {
    for p in CHIP_PRESETS {
        let c = ChipConfig::preset(p).unwrap();
        c.validate().unwrap();
        assert_eq!(c.name, *p);
    }
    let b = ChipConfig::preset("baseline").unwrap();
    assert_eq!((b.tms, b.threads_per_tm, b.tms_per_l2), (80, 32, 20));
    assert_eq!(b.units["int_mul"].count, 2);
    assert_eq!(b.units["fp_mul"].count, 8);
    assert_eq!(b.units["fp_add"].count, 8);
    assert_eq!(b.units["fp_inv_sqrt"].count, 1);
    assert_eq!((b.icache.per_tm, b.icache.banks), (2, 16));
    assert_eq!(
        (b.memory.l1.capacity_bytes, b.memory.l1.banks),
        (32 * 1024, 4)
    );
    assert_eq!(
        (b.memory.l2.capacity_bytes, b.memory.l2.banks),
        (256 * 1024, 16)
    );
    assert_eq!(b.memory.dram.model, DramModel::Detailed);
    assert!(ChipConfig::preset("nope").is_none());
}

#[test]
fn toml_overrides_a_preset() {
    let c = ChipConfig::from_toml_str(
        r#"
preset = "baseline"
tms = 4
[units.fp_add]
count = 2
latency = 3
[memory.l1]
banks = 8
[memory.dram]
preset = "simple"
"#,
        "test.toml",
    )
    .unwrap();
    assert_eq!(c.tms, 4);
    assert_eq!(c.threads_per_tm, 32);
    assert_eq!((c.units["fp_add"].count, c.units["fp_add"].latency), (2, 3));
    assert!(c.units["fp_add"].pipelined);
    assert_eq!(
        c.units["fp_mul"].count, 8,
        "other units keep the preset's values"
    );
    assert_eq!(c.memory.l1.banks, 8);
    assert_eq!(c.memory.l1.capacity_bytes, 32 * 1024);
    assert_eq!(c.memory.dram.model, DramModel::Simple);
}

#[test]
fn round_trips_through_toml() {
    for p in CHIP_PRESETS {
        let c = ChipConfig::preset(p).unwrap();
        let back = ChipConfig::from_toml_str(&c.to_toml(), "round trip").unwrap();
        assert_eq!(c, back, "{p}");
    }
}

#[test]
fn errors_name_the_field() {
    let e = ChipConfig::from_toml_str("tmss = 3", "a.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("tmss") && e.contains("a.toml"), "{e}");
    let e = ChipConfig::from_toml_str("[units.fp_addd]\ncount = 1", "b.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("fp_addd"), "{e}");
    let e = ChipConfig::from_toml_str("[units.fp_add]\ncount = 1\nlatncy = 2", "c.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("latncy"), "{e}");
    let e = ChipConfig::from_toml_str("[units.fp_add]\ncount = 0", "d.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("units.fp_add.count"), "{e}");
    let e = ChipConfig::from_toml_str("threads_per_tm = 0", "e.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("threads_per_tm"), "{e}");
    let e = ChipConfig::from_toml_str("preset = \"huge\"", "f.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("huge"), "{e}");
    let e = ChipConfig::from_toml_str("[memory.l1]\nbanks = 3", "g.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("l1.banks"), "{e}");
    let e = ChipConfig::from_toml_str("tms = [", "h.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("h.toml"), "{e}");
    let e = ChipConfig::load("/nonexistent/chip.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/chip.toml"), "{e}");
}

/// A mistyped value names its field path and where it is in the file (once it said only
/// `invalid type: string "four", expected u32`).
#[test]
fn type_errors_name_the_field_path_and_position() {
    let err = |text: &str| {
        ChipConfig::from_toml_str(text, "t.toml")
            .unwrap_err()
            .to_string()
    };
    let e = err("preset = \"baseline\"\n[units.fp_add]\ncount = \"four\"\n");
    assert!(
        e.contains("t.toml:3:9") && e.contains("`units.fp_add.count`"),
        "{e}"
    );
    assert!(e.contains("invalid type: string \"four\""), "{e}");
    let e = err("tms = 2\n[memory]\nl1 = { banks = 2.5 }\n");
    assert!(
        e.contains("t.toml:3:16") && e.contains("`memory.l1.banks`"),
        "{e}"
    );
    let e = err("tms = 2\n\n  threads_per_tm = true\n");
    assert!(
        e.contains("t.toml:3:20") && e.contains("`threads_per_tm`"),
        "{e}"
    );
    let e = err("[memory.dram.detailed.timing]\ntCAS = [1]\n");
    assert!(
        e.contains("t.toml:2:8") && e.contains("memory.dram.detailed.timing.tCAS"),
        "{e}"
    );
    // Syntax errors have a position too.
    let e = err("tms = 4\ntms = ]\n");
    assert!(e.contains("t.toml:2:"), "{e}");
    // The memory-system and DRAM documents alike.
    let e = trax_emulator::memsys::MemSysConfig::from_toml_str("[l1]\ncapacity_bytes = \"big\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 2, column 18") && e.contains("`l1.capacity_bytes`"),
        "{e}"
    );
    let e = trax_emulator::memsys::DramConfig::from_toml_str("[detailed]\nchannels = -1\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 2, column 12") && e.contains("`detailed.channels`"),
        "{e}"
    );
}
