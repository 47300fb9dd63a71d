//! A toy unit, the worked example of adding a unit: this file and its line in
//! [`super::UNITS`] (`#[cfg(test)] toy::UNIT`), nothing else. It takes the count-leading-
//! zeros instructions (`clz`, `clo`) from the bitwise units on chips whose config has a
//! `[units.toy]` table. The test walks it through every output the registry feeds: the
//! config (`trax config show`'s TOML, validation), a timing run (its operations and
//! conflicts), the statistics (JSON, summary), energy and area, and the sweep column.

use super::{unit_decl, UnitDecl};
use crate::decode::Inst;

/// The toy unit.
pub const UNIT: UnitDecl = unit_decl!(
    toy,
    Bitwise,
    "Toy leading-zero counter (an example unit: takes clz and clo from the bitwise units).",
    takes = |i: &Inst| matches!(i, Inst::Clz { .. } | Inst::Clo { .. })
);

#[cfg(test)]
mod tests {
    use trax_runtime::image::{Perms, Segment};

    use crate::machine::{Machine, MachineConfig};
    use crate::run::Limits;
    use crate::timing::engine::Engine;
    use crate::timing::{stats, ChipConfig, UnitConfig};

    const TEXT: u32 = trax_runtime::abi::TEXT_BASE;

    /// `trax.clock $3` (a zero-cost debug op: the `clz` after it is issued from the
    /// engine's slow path), `clz $2, $0` eight times (independent), then `trax.halt`.
    fn program() -> Vec<u8> {
        use trax_runtime::isa::{instr, TraxOp};
        let clz = (2 << 11) | (1 << 6) | 0x10; // SPECIAL, rs 0, rd 2, 00001 010000
        let mut words = vec![instr(TraxOp::Clock).encode(&[3])];
        words.extend([clz; 8]);
        words.push(instr(TraxOp::Halt).encode(&[]));
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    /// A timing run of [`program`] on 1 TM of 8 threads: its statistics.
    fn run(cfg: &ChipConfig) -> stats::TimingStats {
        let text = program();
        let end = TEXT + text.len() as u32;
        let seg = Segment::new("text", TEXT, text, Perms::RX);
        let mc = MachineConfig {
            tms: cfg.tms,
            threads_per_tm: cfg.threads_per_tm,
            ..MachineConfig::default()
        };
        let mut m = Machine::new(&[seg], TEXT, end, TEXT, mc).unwrap();
        let mut e = Engine::new(cfg, &m, Limits::default(), 1).unwrap();
        let mut out = Vec::new();
        let outcome = e.run(&mut m, &mut out);
        assert!(matches!(outcome, crate::Outcome::Finished), "{outcome:?}");
        stats::build(cfg, &e.c, e.now, e.mem().stats(), &m.shared)
    }

    fn chip(toy: Option<UnitConfig>) -> ChipConfig {
        let mut c = ChipConfig::preset("tiny").unwrap();
        c.threads_per_tm = 8;
        if let Some(t) = toy {
            c.units.insert("toy".into(), t);
        }
        c.validate().unwrap();
        c
    }

    fn toy(energy_nj: f64, area_mm2: f64) -> UnitConfig {
        UnitConfig {
            count: 1,
            latency: 3,
            pipelined: false,
            area_mm2,
            energy_nj,
        }
    }

    /// Every statistic declared in the `timing` object ([`stats::TimingStats::STATS`] and
    /// the groups nested in it) is in a run's JSON at its path, with its declared type.
    #[test]
    fn every_declared_statistic_is_in_the_json() {
        use crate::timing::stat::{value_at, walk};
        let s = run(&chip(None));
        let json = serde_json::to_value(&s).unwrap();
        for st in walk(stats::TimingStats::STATS) {
            let v = value_at(&json, "timing", st.path)
                .unwrap_or_else(|| panic!("{} is not in the JSON", st.path));
            let ok = match st.ty.trim_end_matches('?') {
                "int" => v.is_u64(),
                "float" => v.is_f64(),
                "object" | "map" => v.is_object(),
                t => panic!("{}: no check for type {t}", st.path),
            };
            assert!(
                ok || (st.ty.ends_with('?') && v.is_null()),
                "{}: {v}",
                st.path
            );
        }
    }

    #[test]
    fn the_toy_unit_appears_in_every_output() {
        // Config: `trax config show` documents it, validation accepts it, and a wrong
        // field of it is named.
        let with = chip(Some(toy(0.5, 0.25)));
        let shown = with.to_documented_toml(&[]);
        assert!(shown.contains("[units.toy]"), "{shown}");
        assert!(shown.contains("# Toy leading-zero counter"), "{shown}");
        let mut bad = with.clone();
        bad.units.get_mut("toy").unwrap().latency = 0;
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("units.toy.latency"));

        // Timing: 8 threads x 8 clz on one non-pipelined unit of latency 3: 64 operations,
        // one every 3 cycles, the others waiting for it. Without the unit, the clz are
        // bitwise operations on one unit per thread: no conflicts, far fewer cycles.
        let s = run(&with);
        let plain = run(&chip(None));
        assert_eq!(s.class_mix.get("toy"), Some(&64));
        assert_eq!(plain.class_mix.get("toy"), None);
        assert_eq!(
            plain.class_mix["bitwise"],
            s.class_mix.get("bitwise").unwrap_or(&0) + 64
        );
        assert!(s.unit_conflicts["toy"] > 0);
        // The 64th operation issues 63 x 3 cycles after the first.
        assert!(s.cycles > 63 * 3, "{}", s.cycles);
        assert!(plain.cycles < 64, "{}", plain.cycles);

        // Statistics: the JSON and the summary name it.
        let json = serde_json::to_value(&s).unwrap();
        assert_eq!(json["class_mix"]["toy"], 64);
        assert!(s.summary().contains("toy"), "{}", s.summary());

        // Energy and area: its operations' energy and its area are the execution units'.
        let zero = run(&chip(Some(toy(0.0, 0.0))));
        let de = s.energy.execution_units - zero.energy.execution_units;
        assert!((de - 64.0 * 0.5e-9).abs() < 1e-15, "{de}");
        let da = s.area.execution_units - zero.area.execution_units;
        assert!((da - 0.25).abs() < 1e-12, "{da}");

        // Sweep: its column reads the document's count.
        let u = super::UNIT;
        assert_eq!(u.ops_column, "toy_ops");
        let at = u.ops_path.split('.').skip(1).fold(&json, |v, k| &v[k]);
        assert_eq!(at, 64);
    }
}
