//! Cache and memory-system configuration (TOML, serde), with named presets.
//!
//! Every struct rejects unknown fields, so a misspelt key is named in the error. A table may
//! start with `preset = "NAME"`: the preset's values are the base and the other keys override them
//! (see [`load_with_preset`]).

use super::dram_config::DramConfig;
use super::MemSysError;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// How addresses are spread over the banks of a cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BankInterleave {
    /// `bank = (addr / 4) % banks` (consecutive words in consecutive banks), as the original.
    Word,
    /// `bank = (addr / line_bytes) % banks` (whole lines per bank).
    Line,
}

/// Per-TM L1 data cache: direct-mapped, banked, write-around (no allocate on store).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct L1Config {
    /// Capacity in bytes (power of two). Default 32768 (thesis Table 2.5, original default.config).
    pub capacity_bytes: u32,
    /// Line size in bytes (power of two, >= 4). Default 64.
    pub line_bytes: u32,
    /// Number of banks (power of two); each bank serves one access per core cycle. Default 4.
    pub banks: u32,
    /// Bank selection. Default `word`.
    pub interleave: BankInterleave,
    /// Hit latency in core cycles (load issue to data ready), 0 to [`MAX_HIT_LATENCY`].
    /// Default 1 (thesis §2.2.1.1).
    pub hit_latency: u32,
    /// Miss-status holding registers: distinct lines that may wait on memory at once. Default 64.
    pub mshrs: u32,
    /// If true, accesses to the same word in the same cycle share a bank access (no conflict).
    /// Default false (the original's `--l1-read-copy`).
    pub read_copy: bool,
    /// Area in mm². Default: none = looked up in the Cacti table ([`super::cacti`]).
    pub area_mm2: Option<f64>,
    /// Energy per read access in nJ. Default: none = looked up in the Cacti table.
    pub energy_nj: Option<f64>,
}

impl Default for L1Config {
    fn default() -> Self {
        L1Config {
            capacity_bytes: 32 * 1024,
            line_bytes: 64,
            banks: 4,
            interleave: BankInterleave::Word,
            hit_latency: 1,
            mshrs: 64,
            read_copy: false,
            area_mm2: None,
            energy_nj: None,
        }
    }
}

/// L2 cache shared by a group of TMs: banked, set-associative (direct-mapped by default),
/// write-around.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct L2Config {
    /// Capacity in bytes (power of two). Default 524288 (thesis Table 2.5 uses 256 KB or 512 KB).
    pub capacity_bytes: u32,
    /// Line size in bytes (power of two, must equal the L1 line). Default 64.
    pub line_bytes: u32,
    /// Number of banks (power of two). Default 16 (thesis Table 2.5).
    pub banks: u32,
    /// Bank selection. Default `word`.
    pub interleave: BankInterleave,
    /// Ways per set (power of two); 1 = direct-mapped. Replacement is LRU. Default 1.
    pub associativity: u32,
    /// Hit latency in core cycles, added on top of the L1's, 0 to [`MAX_HIT_LATENCY`].
    /// Default 3 (thesis §2.2.1.1).
    pub hit_latency: u32,
    /// Distinct lines that may wait on DRAM at once. Default 256.
    pub mshrs: u32,
    /// Area in mm². Default: none = Cacti table.
    pub area_mm2: Option<f64>,
    /// Energy per read access in nJ. Default: none = Cacti table.
    pub energy_nj: Option<f64>,
}

impl Default for L2Config {
    fn default() -> Self {
        L2Config {
            capacity_bytes: 512 * 1024,
            line_bytes: 64,
            banks: 16,
            interleave: BankInterleave::Word,
            associativity: 1,
            hit_latency: 3,
            mshrs: 256,
            area_mm2: None,
            energy_nj: None,
        }
    }
}

/// Longest cache hit latency, core cycles (L1 and L2 alike). A last-level cache of today
/// hits in about 50; the timing model advances in quanta of the L1 plus L2 hit latency, so
/// this also bounds the time between two of its chip-wide phases (progress, limits).
pub const MAX_HIT_LATENCY: u32 = 1000;

/// Checks that `field` = `value` lies in `range` (`unit` after it in the message), the one
/// wording of a range error in chip and memory configs.
pub fn check_range(
    field: &str,
    value: u64,
    range: std::ops::RangeInclusive<u64>,
    unit: &str,
) -> Result<(), String> {
    if range.contains(&value) {
        return Ok(());
    }
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    Err(format!(
        "{field} = {value} must be in {}..={}{unit}",
        range.start(),
        range.end()
    ))
}

/// The whole memory system below the thread processors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct MemSysConfig {
    /// Per-TM L1 data cache.
    pub l1: L1Config,
    /// Shared L2 caches (one per group of TMs).
    pub l2: L2Config,
    /// Main memory.
    pub dram: DramConfig,
}

impl MemSysConfig {
    /// Parses a TOML document with optional `[l1]`, `[l2]`, `[dram]` tables (`[dram]` may name a
    /// `preset`).
    pub fn from_toml_str(text: &str) -> Result<Self, MemSysError> {
        let mut table: toml::Table = toml::from_str(text).map_err(|e| toml_err(text, e))?;
        let mut out = MemSysConfig::default();
        if let Some(v) = table.remove("l1") {
            out.l1 = crate::tomlerr::deserialize(v, Some(text), &["l1"]).map_err(field_err)?;
        }
        if let Some(v) = table.remove("l2") {
            out.l2 = crate::tomlerr::deserialize(v, Some(text), &["l2"]).map_err(field_err)?;
        }
        if let Some(v) = table.remove("dram") {
            out.dram = load_with_preset(v, DramConfig::preset, "dram", Some((text, &["dram"])))?;
        }
        if let Some(k) = table.keys().next() {
            return Err(MemSysError::Config(format!(
                "unknown field `{k}`, expected one of `l1`, `l2`, `dram`"
            )));
        }
        out.validate()?;
        Ok(out)
    }

    /// Checks cross-field constraints of all parts.
    pub fn validate(&self) -> Result<(), MemSysError> {
        for (field, v) in [
            ("l1.hit_latency", self.l1.hit_latency),
            ("l2.hit_latency", self.l2.hit_latency),
        ] {
            check_range(field, v.into(), 0..=MAX_HIT_LATENCY.into(), "core cycles")
                .map_err(MemSysError::Config)?;
        }
        check_cache(
            "l1",
            self.l1.capacity_bytes,
            self.l1.line_bytes,
            self.l1.banks,
            1,
        )?;
        check_cache(
            "l2",
            self.l2.capacity_bytes,
            self.l2.line_bytes,
            self.l2.banks,
            self.l2.associativity,
        )?;
        if self.l1.line_bytes != self.l2.line_bytes {
            return Err(MemSysError::Config(format!(
                "l1.line_bytes ({}) must equal l2.line_bytes ({})",
                self.l1.line_bytes, self.l2.line_bytes
            )));
        }
        if self.l1.mshrs == 0 || self.l2.mshrs == 0 {
            return Err(MemSysError::Config(
                "l1.mshrs and l2.mshrs must be >= 1".into(),
            ));
        }
        self.dram.validate()
    }
}

/// Checks one cache geometry (`what` names the table in errors).
pub(crate) fn check_cache(
    what: &str,
    capacity: u32,
    line: u32,
    banks: u32,
    ways: u32,
) -> Result<(), MemSysError> {
    let pow2 = |name: &str, v: u32| {
        if v == 0 || !v.is_power_of_two() {
            Err(MemSysError::Config(format!(
                "{what}.{name} = {v} must be a power of two"
            )))
        } else {
            Ok(())
        }
    };
    pow2("capacity_bytes", capacity)?;
    pow2("line_bytes", line)?;
    pow2("banks", banks)?;
    pow2("associativity", ways)?;
    if line < 4 {
        return Err(MemSysError::Config(format!(
            "{what}.line_bytes = {line} must be >= 4"
        )));
    }
    if u64::from(line) * u64::from(ways) > u64::from(capacity) {
        return Err(MemSysError::Config(format!(
            "{what}: capacity_bytes ({capacity}) smaller than one set (line_bytes {line} x associativity {ways})"
        )));
    }
    Ok(())
}

/// A TOML syntax error with its line and column.
pub(crate) fn toml_err(text: &str, e: toml::de::Error) -> MemSysError {
    MemSysError::Toml(match e.span() {
        Some(s) => {
            let (l, c) = crate::tomlerr::line_col(text, s.start);
            format!("line {l}, column {c}: {}", e.message().trim_end())
        }
        None => e.message().trim_end().to_string(),
    })
}

/// A field error: the field's path, its line and column when known, and serde's message.
fn field_err(e: crate::tomlerr::FieldError) -> MemSysError {
    MemSysError::Config(match e.at {
        Some((l, c)) => format!("line {l}, column {c}: {}", e.message()),
        None => e.message(),
    })
}

/// Deserializes `value` (a TOML table) into `T`. The base is the preset named by a
/// `preset = "NAME"` key (from `lookup`), or `T::default()` without one; the table's other keys
/// are merged over the serialized base (recursively for sub-tables) and the result is
/// deserialized, so partial tables work and unknown keys are still rejected by name.
/// `source` is the document text and the table's key path in it, for error positions.
pub fn load_with_preset<T, F>(
    value: toml::Value,
    lookup: F,
    table: &str,
    source: Option<(&str, &[&str])>,
) -> Result<T, MemSysError>
where
    T: DeserializeOwned + Serialize + Default,
    F: Fn(&str) -> Option<T>,
{
    let toml::Value::Table(mut user) = value else {
        return Err(MemSysError::Config(format!("[{table}] must be a table")));
    };
    let base = match user.remove("preset") {
        None => T::default(),
        Some(toml::Value::String(name)) => lookup(&name)
            .ok_or_else(|| MemSysError::Config(format!("[{table}]: unknown preset {name:?}")))?,
        Some(other) => {
            return Err(MemSysError::Config(format!(
                "[{table}]: preset must be a string, found {}",
                other.type_str()
            )))
        }
    };
    let mut merged =
        toml::Value::try_from(&base).map_err(|e| MemSysError::Config(format!("[{table}]: {e}")))?;
    crate::tomlerr::merge(&mut merged, toml::Value::Table(user));
    let (text, prefix) = source.unzip();
    crate::tomlerr::deserialize(merged, text, prefix.unwrap_or(&[table])).map_err(field_err)
}
