//! The sweep file (`trax sweep SWEEP.toml`): parsing with source positions, checking, and
//! expansion into points.
//!
//! ```toml
//! name = "tms_scaling"                 # optional (default: the file's stem)
//! kernel = "../examples/pathtracer.rs" # run parameters shared by every point ...
//! config = "baseline"
//! width = 64
//! memory.l2.capacity_bytes = 262144    # ... and chip config fields (dotted paths)
//! repetitions = 1                      # runs of each point (default 1)
//!
//! [axes]                               # varied: every combination (grid product)
//! tms = [1, 2, 4, 8]
//!
//! [[cases]]                            # explicit points, each crossed with the grid
//! config = "baseline"
//! [[cases]]
//! config = "strata"
//! memory.dram.preset = "hbm2"
//! label.chip = "STRaTA"               # a label: a column of results.csv, not a config field
//!
//! [slurm]                              # defaults for --slurm
//! partition = "short"
//!
//! [[plot]]                             # charts `collect` draws (see `trax plot`)
//! x = "tms"
//! y = "fps"
//! ```
//!
//! A parameter is a run knob (see [`KNOBS`]), a label (`label.NAME`, see [`LABEL_PREFIX`]:
//! recorded, not run) or, for any other name, a field of the chip config set as `trax run
//! --set PATH=VALUE` does. Every point's config is built while the
//! file is checked, so an unknown field, a value of the wrong type or out of range is an error
//! naming the field and its line before anything runs.
//!
//! Point ids: the first 16 hex digits of the SHA-256 of `trax-sweep-point/1\n` followed by
//! one `name=value\n` line per parameter, sorted by name, where value is the canonical text of
//! [`PVal::canonical`]. The parameters are every knob with a default (filled in when the file
//! leaves it out), the knobs and config fields the file gives, and `rep` when it is not 0. The
//! kernel, config and scene are hashed as written in the file (not their contents or where the
//! file lives), so a results directory stays valid when the checkout moves; the point's JSON
//! records the kernel's hashes.

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use toml_edit::{ImDocument, Item, Value};
use trax_emulator::timing::sample::{MIN_WARMUP_CYCLES, MIN_WINDOWS};
use trax_emulator::NUM_GLOBALS;

/// A parameter value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PVal {
    /// Boolean.
    Bool(bool),
    /// Integer.
    Int(i64),
    /// Floating point.
    Float(f64),
    /// String.
    Str(String),
}

impl PVal {
    /// Canonical text (for ids): integers in decimal, floats in Rust's shortest round-trip
    /// form with a `.`, booleans as `true`/`false`, strings JSON-quoted.
    pub fn canonical(&self) -> String {
        match self {
            PVal::Bool(b) => b.to_string(),
            PVal::Int(i) => i.to_string(),
            PVal::Float(f) => format!("{f:?}"),
            PVal::Str(s) => serde_json::to_string(s).unwrap_or_default(),
        }
    }

    /// The value as TOML (for chip config fields).
    pub fn to_toml(&self) -> toml::Value {
        match self {
            PVal::Bool(b) => toml::Value::Boolean(*b),
            PVal::Int(i) => toml::Value::Integer(*i),
            PVal::Float(f) => toml::Value::Float(*f),
            PVal::Str(s) => toml::Value::String(s.clone()),
        }
    }

    /// The value as a table cell or command-line argument (strings unquoted).
    pub fn plain(&self) -> String {
        match self {
            PVal::Str(s) => s.clone(),
            PVal::Float(f) => format!("{f:?}"),
            other => other.canonical(),
        }
    }

    fn type_name(&self) -> &'static str {
        match self {
            PVal::Bool(_) => "boolean",
            PVal::Int(_) => "integer",
            PVal::Float(_) => "float",
            PVal::Str(_) => "string",
        }
    }
}

/// A position in the sweep file (1-based).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Loc {
    /// Line.
    pub line: usize,
    /// Column (characters).
    pub col: usize,
}

/// A bad sweep file: where, which field, what is wrong.
#[derive(Debug)]
pub struct SpecError {
    /// The sweep file.
    pub file: String,
    /// Where (when known).
    pub loc: Option<Loc>,
    /// The field (dotted path), empty for the file as a whole.
    pub field: String,
    /// What is wrong.
    pub msg: String,
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.loc {
            write!(f, ":{}:{}", l.line, l.col)?;
        }
        if self.field.is_empty() {
            write!(f, ": {}", self.msg)
        } else {
            write!(f, ": `{}`: {}", self.field, self.msg)
        }
    }
}

/// What a knob's value must be.
#[derive(Clone, Copy, Debug)]
pub enum KnobKind {
    /// A string.
    Str,
    /// An integer in the range.
    Int(i64, i64),
    /// One of the strings.
    OneOf(&'static [&'static str]),
}

/// A run knob: a `trax run` option a sweep can fix or vary.
#[derive(Debug)]
pub struct Knob {
    /// Name in the sweep file and the table.
    pub name: &'static str,
    /// What its values must be.
    pub kind: KnobKind,
    /// The default filled in when the file leaves it out (none: left to `trax run` and not
    /// part of the point's parameters). These are `trax run`'s defaults.
    pub default: Option<DefaultVal>,
}

/// A knob's default.
#[derive(Clone, Copy, Debug)]
pub enum DefaultVal {
    /// String default.
    Str(&'static str),
    /// Integer default.
    Int(i64),
}

const U32: KnobKind = KnobKind::Int(1, u32::MAX as i64);

/// The run knobs. Kernel, config, scene, view and light paths are relative to the sweep file.
pub const KNOBS: &[Knob] = &[
    knob("kernel", KnobKind::Str, None),
    knob("config", KnobKind::Str, Some(DefaultVal::Str("tiny"))),
    knob(
        "mode",
        KnobKind::OneOf(&["timing", "functional"]),
        Some(DefaultVal::Str("timing")),
    ),
    knob("opt_level", KnobKind::Int(0, 3), Some(DefaultVal::Int(2))),
    knob("scene", KnobKind::Str, Some(DefaultVal::Str("cornell"))),
    knob("view", KnobKind::Str, None),
    knob("light", KnobKind::Str, None),
    knob("width", U32, Some(DefaultVal::Int(128))),
    knob("height", U32, Some(DefaultVal::Int(128))),
    knob("spp", U32, Some(DefaultVal::Int(1))),
    knob(
        "depth",
        KnobKind::Int(0, u32::MAX as i64),
        Some(DefaultVal::Int(4)),
    ),
    knob(
        "seed",
        KnobKind::Int(0, u32::MAX as i64),
        Some(DefaultVal::Int(1)),
    ),
    knob("threads", U32, None),
    knob("l2s", U32, None),
    knob("quantum", U32, None),
    knob("max_instructions", KnobKind::Int(1, i64::MAX), None),
    knob("max_cycles", KnobKind::Int(1, i64::MAX), None),
    // Sampled simulation (`trax run --sample N` and its `--sample-*` flags): a point with
    // `sample` is a sampled run, its metrics estimates with 95% intervals.
    knob(
        "sample",
        KnobKind::Int(MIN_WINDOWS as i64, u32::MAX as i64),
        None,
    ),
    knob(
        "sample_warmup",
        KnobKind::Int(MIN_WARMUP_CYCLES as i64, i64::MAX),
        None,
    ),
    knob(
        "sample_window",
        KnobKind::Int(MIN_WARMUP_CYCLES as i64, i64::MAX),
        None,
    ),
    knob(
        "sample_counter",
        KnobKind::Int(0, NUM_GLOBALS as i64 - 1),
        None,
    ),
    knob("sample_items", U32, None),
    knob("sample_seed", KnobKind::Int(0, u32::MAX as i64), None),
];

/// The knobs that set how a sampled point samples (each needs `sample`).
pub const SAMPLE_KNOBS: &[&str] = &[
    "sample_warmup",
    "sample_window",
    "sample_counter",
    "sample_items",
    "sample_seed",
];

const fn knob(name: &'static str, kind: KnobKind, default: Option<DefaultVal>) -> Knob {
    Knob {
        name,
        kind,
        default,
    }
}

/// Top-level keys with a meaning of their own.
const RESERVED: &[&str] = &[
    "name",
    "repetitions",
    "axes",
    "cases",
    "slurm",
    "plot",
    "rep",
    "limits",
];

/// Prefix of label parameters (`label.NAME = VALUE`): recorded with the point (its id,
/// `results.csv`, plots) but not passed to `trax run`, e.g. a common x axis for cases that
/// vary different config fields (an L2 size here, a stream-memory size there).
pub const LABEL_PREFIX: &str = "label.";

/// Whether `name` is a label parameter ([`LABEL_PREFIX`]).
pub fn is_label(name: &str) -> bool {
    name.strip_prefix(LABEL_PREFIX)
        .is_some_and(|n| !n.is_empty())
}

/// The knob called `name`.
pub fn knob_named(name: &str) -> Option<&'static Knob> {
    KNOBS.iter().find(|k| k.name == name)
}

/// A value and where it is.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct At<T> {
    /// The value.
    pub v: T,
    /// Where it is.
    pub loc: Loc,
}

/// A parameter as given in the file: its name and value, each with its position.
pub type Param = (At<String>, At<PVal>);

/// One varied parameter.
#[derive(Clone, Debug)]
pub struct Axis {
    /// Parameter name.
    pub name: At<String>,
    /// Its values.
    pub values: Vec<At<PVal>>,
}

/// `[slurm]` settings (each may be overridden by a flag).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct SlurmSettings {
    /// `--partition`.
    pub partition: Option<String>,
    /// `--time` (Slurm's formats, e.g. `30:00`, `1-00:00:00`).
    pub time: Option<String>,
    /// `--account`.
    pub account: Option<String>,
    /// Points each array task runs one after the other.
    pub per_task: Option<u32>,
    /// Array tasks running at once (the `%K` of `--array`).
    pub max_running: Option<u32>,
    /// CPUs per task (each point's `--host-threads`).
    pub cpus_per_task: Option<u32>,
}

/// Per-point limits (`[limits]` in the sweep file, `--point-time`/`--point-memory` on the
/// command line). A point over one is stopped and recorded as failed with the limit it hit.
/// They are not parameters: they change no result, only whether there is one.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Limits {
    /// Wall-clock seconds a point may run.
    pub time_s: Option<u64>,
    /// Bytes of resident memory a point may use (its peak, `ru_maxrss`).
    pub memory_bytes: Option<u64>,
}

/// Most seconds a time limit may be (a year).
const MAX_TIME_S: u64 = 366 * 24 * 3600;

/// A duration: whole seconds (`90`), a number with a unit (`90s`, `30m`, `1.5h`, `2d`) or
/// Slurm's `[D-]HH:MM:SS`/`MM:SS`; at least 1 s, at most a year.
pub fn parse_duration(s: &str) -> Result<u64, String> {
    let bad = || {
        format!("{s:?} is not a duration (e.g. 90, \"90s\", \"30m\", \"1.5h\", \"2d\", \"1:30:00\", \"2-00:00:00\")")
    };
    let t = s.trim();
    let secs: f64 = if t.contains(':') {
        let (days, hms) = match t.split_once('-') {
            Some((d, r)) => (d.parse::<u64>().map_err(|_| bad())?, r),
            None => (0, t),
        };
        let parts: Vec<u64> = hms
            .split(':')
            .map(|p| p.parse::<u64>().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        let (h, m, sec) = match parts.as_slice() {
            [m, sec] => (0, *m, *sec),
            [h, m, sec] => (*h, *m, *sec),
            _ => return Err(bad()),
        };
        ((days.min(MAX_TIME_S) * 24 + h.min(MAX_TIME_S)) * 60 + m.min(MAX_TIME_S)) as f64 * 60.0
            + sec.min(MAX_TIME_S) as f64
    } else {
        let split = t
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(t.len());
        let (num, unit) = t.split_at(split);
        let n: f64 = num.parse().map_err(|_| bad())?;
        let scale = match unit.trim() {
            "" | "s" | "sec" => 1.0,
            "m" | "min" => 60.0,
            "h" => 3600.0,
            "d" => 86400.0,
            _ => return Err(bad()),
        };
        n * scale
    };
    if !(1.0..=MAX_TIME_S as f64).contains(&secs) {
        return Err(format!("{s:?} must be from 1 second to a year"));
    }
    Ok(secs.round() as u64)
}

/// An amount of memory: a number with a unit, binary as Slurm's `--mem` (`512M`, `4G`,
/// `4GiB`, `1.5G`, `65536K`; `B` for bytes); a bare number is MiB (Slurm's default).
/// At least 1 MiB, at most 1 PiB.
pub fn parse_memory(s: &str) -> Result<u64, String> {
    let bad = || {
        format!("{s:?} is not an amount of memory (e.g. \"512M\", \"4G\", \"4GiB\"; a bare number is MiB)")
    };
    let t = s.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let n: f64 = num.parse().map_err(|_| bad())?;
    let unit = unit.trim().to_ascii_uppercase();
    let unit = unit
        .strip_suffix("IB")
        .or_else(|| unit.strip_suffix('B').filter(|u| !u.is_empty()))
        .unwrap_or(&unit);
    let scale = match unit {
        "" | "M" => 1u64 << 20,
        "B" => 1,
        "K" => 1 << 10,
        "G" => 1 << 30,
        "T" => 1 << 40,
        _ => return Err(bad()),
    };
    let bytes = n * scale as f64;
    if !((1u64 << 20) as f64..=(1u64 << 50) as f64).contains(&bytes) {
        return Err(format!("{s:?} must be from 1 MiB to 1 PiB"));
    }
    Ok(bytes as u64)
}

/// `bytes` for a person (and Slurm's `--mem`): whole MiB, as `N M`.
pub fn show_mib(bytes: u64) -> String {
    format!("{}M", bytes.div_ceil(1 << 20))
}

fn parse_limits(src: &Src, item: &Item, kloc: Option<Loc>) -> Result<Limits, SpecError> {
    let mut l = Limits::default();
    for (k, it, loc) in table_entries(src, "limits", item, kloc)? {
        let field = format!("limits.{k}");
        let vloc = src.loc(it.span()).or(loc);
        let text = match it.as_value() {
            Some(Value::String(s)) => s.value().clone(),
            Some(Value::Integer(i)) => i.value().to_string(),
            Some(Value::Float(f)) => f.value().to_string(),
            other => {
                return Err(src.err(
                    vloc,
                    &field,
                    format!(
                        "must be a string or a number, found {}",
                        other.map_or("a table", value_type)
                    ),
                ))
            }
        };
        match k {
            "time" => l.time_s = Some(parse_duration(&text).map_err(|m| src.err(vloc, &field, m))?),
            "memory" => {
                l.memory_bytes = Some(parse_memory(&text).map_err(|m| src.err(vloc, &field, m))?)
            }
            _ => return Err(src.err(loc, &field, "unknown field (expected time, memory)")),
        }
    }
    Ok(l)
}

/// How a plot shows its metric.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum PlotKind {
    /// Lines with markers, one per `by` value.
    Line,
    /// Grouped bars, one per `by` value.
    Bar,
    /// Stacked bars of the energy per frame by component.
    Energy,
}

/// A `[[plot]]` of the sweep file.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PlotSpec {
    /// File name (without extension) under `plots/`.
    pub name: String,
    /// Parameter on the x axis.
    pub x: String,
    /// Metric on the y axis (`energy_j` for `kind = "energy"`).
    pub y: String,
    /// Parameter whose values get a series each.
    pub by: Option<String>,
    /// Chart kind.
    pub kind: PlotKind,
    /// Title (default: metric vs parameter).
    pub title: Option<String>,
    /// Only rows with these parameter values.
    pub filter: Vec<(String, String)>,
    /// X axis label (default: the parameter's name and unit).
    #[serde(default)]
    pub xlabel: Option<String>,
    /// Y axis label (default: the metric's name and unit).
    #[serde(default)]
    pub ylabel: Option<String>,
    /// Log x axis (`None`: chosen from the data, see `plot::axis::Axis::fit`).
    #[serde(default)]
    pub log_x: Option<bool>,
    /// Log y axis (`None`: chosen from the data).
    #[serde(default)]
    pub log_y: Option<bool>,
    /// Energy charts: the components to stack, by name (`dram`, `l2`, ...; empty: every
    /// component the table has).
    #[serde(default)]
    pub components: Vec<String>,
    /// Where the plot is in the sweep file.
    #[serde(skip)]
    pub loc: Option<Loc>,
}

/// A parsed sweep file.
#[derive(Debug)]
pub struct SweepSpec {
    /// The file as given.
    pub file: PathBuf,
    /// The directory relative paths in it are resolved against.
    pub dir: PathBuf,
    /// Sweep name.
    pub name: String,
    /// Parameters every point shares, in file order.
    pub fixed: Vec<Param>,
    /// Grid axes, in file order.
    pub axes: Vec<Axis>,
    /// Explicit cases, each a list of parameters.
    pub cases: Vec<Vec<Param>>,
    /// Runs of each point.
    pub repetitions: u32,
    /// Slurm defaults.
    pub slurm: SlurmSettings,
    /// Plots.
    pub plots: Vec<PlotSpec>,
    /// Per-point limits.
    pub limits: Limits,
}

impl SweepSpec {
    /// Adds a parameter every point shares, as if the file gave it at the top level (`trax
    /// sweep --sample N`); refused when the file gives it already, or the value is not one
    /// the knob takes. `flag` names the option in errors.
    pub fn add_fixed(&mut self, flag: &str, name: &str, v: PVal) -> Result<(), String> {
        check_knob(name, &v).map_err(|m| format!("{flag}: {m}"))?;
        let given = self
            .fixed
            .iter()
            .map(|(n, _)| n)
            .chain(self.axes.iter().map(|a| &a.name))
            .chain(self.cases.iter().flatten().map(|(n, _)| n))
            .find(|n| n.v == name);
        if let Some(n) = given {
            return Err(format!(
                "{flag}: {} gives `{name}` already (line {})",
                self.file.display(),
                n.loc.line
            ));
        }
        let loc = Loc::default();
        self.fixed.push((
            At {
                v: name.to_string(),
                loc,
            },
            At { v, loc },
        ));
        Ok(())
    }
}

/// One expanded point.
#[derive(Clone, Debug)]
pub struct Point {
    /// Stable id (see the module documentation).
    pub id: String,
    /// The id as a number.
    pub id_bits: u64,
    /// Its combination index in the [`Grid`].
    pub index: u64,
    /// Every parameter, by name.
    pub params: BTreeMap<String, PVal>,
    /// Where each parameter the file gives comes from.
    pub locs: BTreeMap<String, Loc>,
}

struct Src<'a> {
    file: String,
    text: &'a str,
}

impl Src<'_> {
    fn loc(&self, span: Option<Range<usize>>) -> Option<Loc> {
        let start = span?.start.min(self.text.len());
        let before = &self.text[..start];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Some(Loc { line, col })
    }

    fn err(&self, loc: Option<Loc>, field: &str, msg: impl Into<String>) -> SpecError {
        SpecError {
            file: self.file.clone(),
            loc,
            field: field.to_string(),
            msg: msg.into(),
        }
    }
}

/// Reads and parses a sweep file.
pub fn load(path: &Path) -> Result<SweepSpec, SpecError> {
    let text = std::fs::read_to_string(path).map_err(|e| SpecError {
        file: path.display().to_string(),
        loc: None,
        field: String::new(),
        msg: e.to_string(),
    })?;
    parse(&text, path)
}

/// Parses the text of a sweep file (`path` names it in errors and anchors relative paths).
pub fn parse(text: &str, path: &Path) -> Result<SweepSpec, SpecError> {
    let src = Src {
        file: path.display().to_string(),
        text,
    };
    let doc = ImDocument::parse(text.to_string()).map_err(|e| {
        let loc = src.loc(e.span());
        src.err(loc, "", e.message().trim_end().to_string())
    })?;
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let mut spec = SweepSpec {
        file: path.to_path_buf(),
        dir,
        name: path
            .file_stem()
            .map_or_else(|| "sweep".into(), |s| safe_name(&s.to_string_lossy())),
        fixed: Vec::new(),
        axes: Vec::new(),
        cases: Vec::new(),
        repetitions: 1,
        slurm: SlurmSettings::default(),
        plots: Vec::new(),
        limits: Limits::default(),
    };
    let root = doc.as_table();
    for (key, item) in root.iter() {
        let kloc = src.loc(root.key(key).and_then(|k| k.span()));
        match key {
            "name" => spec.name = name_item(&src, key, item)?,
            "repetitions" => {
                spec.repetitions = int_item(&src, key, item, 1, 1_000_000)? as u32;
            }
            "axes" => spec.axes = parse_axes(&src, item, kloc)?,
            "cases" => spec.cases = parse_cases(&src, item, kloc)?,
            "slurm" => spec.slurm = parse_slurm(&src, item, kloc)?,
            "plot" => spec.plots = parse_plots(&src, item, kloc)?,
            "limits" => spec.limits = parse_limits(&src, item, kloc)?,
            "rep" => {
                return Err(src.err(kloc, key, "is the repetition index; use `repetitions = N`"))
            }
            _ => {
                let mut leaves = Vec::new();
                flatten(&src, key.to_string(), kloc, Node::Item(item), &mut leaves)?;
                spec.fixed.extend(params_of(&src, leaves)?);
            }
        }
    }
    check_names(&src, &spec)?;
    Ok(spec)
}

/// A node of the document: a table item or an (inline) value.
#[derive(Clone, Copy)]
enum Node<'a> {
    Item(&'a Item),
    Value(&'a Value),
}

/// Flattens tables into `(dotted name, value)` leaves (arrays are leaves).
fn flatten<'a>(
    src: &Src,
    name: String,
    kloc: Option<Loc>,
    node: Node<'a>,
    out: &mut Vec<(At<String>, &'a Value)>,
) -> Result<(), SpecError> {
    let sub = |k: &str| format!("{name}.{k}");
    match node {
        Node::Item(Item::None) => {}
        Node::Item(Item::Value(v)) => flatten(src, name, kloc, Node::Value(v), out)?,
        Node::Item(Item::Table(t)) => {
            for (k, it) in t.iter() {
                let l = src.loc(t.key(k).and_then(|k| k.span())).or(kloc);
                flatten(src, sub(k), l, Node::Item(it), out)?;
            }
        }
        Node::Item(Item::ArrayOfTables(a)) => {
            return Err(src.err(
                src.loc(a.span()).or(kloc),
                &name,
                "an array of tables is not a parameter",
            ))
        }
        Node::Value(Value::InlineTable(t)) => {
            for (k, v) in t.iter() {
                let l = src.loc(t.key(k).and_then(|k| k.span())).or(kloc);
                flatten(src, sub(k), l, Node::Value(v), out)?;
            }
        }
        Node::Value(v) => out.push((
            At {
                v: name,
                loc: kloc.unwrap_or_default(),
            },
            v,
        )),
    }
    Ok(())
}

/// A scalar parameter value.
fn scalar(src: &Src, name: &str, v: &Value) -> Result<At<PVal>, SpecError> {
    let loc = src.loc(v.span()).unwrap_or_default();
    let p = match v {
        Value::String(s) => PVal::Str(s.value().clone()),
        Value::Integer(i) => PVal::Int(*i.value()),
        Value::Float(f) => PVal::Float(*f.value()),
        Value::Boolean(b) => PVal::Bool(*b.value()),
        other => {
            return Err(src.err(
                Some(loc),
                name,
                format!(
                    "must be a string, integer, float or boolean, found {}",
                    value_type(other)
                ),
            ))
        }
    };
    Ok(At { v: p, loc })
}

fn value_type(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a float",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date-time",
        Value::Array(_) => "an array",
        Value::InlineTable(_) => "a table",
    }
}

/// `(name, scalar)` parameters of a table (the top level, or a case).
fn params_of(src: &Src, leaves: Vec<(At<String>, &Value)>) -> Result<Vec<Param>, SpecError> {
    leaves
        .into_iter()
        .map(|(n, v)| {
            let val = scalar(src, &n.v, v)?;
            Ok((n, val))
        })
        .collect()
}

fn parse_axes(src: &Src, item: &Item, kloc: Option<Loc>) -> Result<Vec<Axis>, SpecError> {
    if !item.is_table_like() {
        return Err(src.err(kloc, "axes", "must be a table of `name = [values]`"));
    }
    let mut leaves = Vec::new();
    // Names inside `[axes]` are the parameters, without the `axes.` prefix.
    let node = match item {
        Item::Table(t) => t
            .iter()
            .map(|(k, it)| (k, t.key(k), Node::Item(it)))
            .collect(),
        Item::Value(Value::InlineTable(t)) => t
            .iter()
            .map(|(k, v)| (k, t.key(k), Node::Value(v)))
            .collect::<Vec<_>>(),
        _ => Vec::new(),
    };
    for (k, key, n) in node {
        let l = src.loc(key.and_then(|k| k.span())).or(kloc);
        flatten(src, k.to_string(), l, n, &mut leaves)?;
    }
    let mut axes = Vec::new();
    for (name, v) in leaves {
        let Value::Array(a) = v else {
            return Err(src.err(
                Some(name.loc),
                &name.v,
                format!(
                    "an axis is a list of values (`{} = [..]`), found {}",
                    name.v,
                    value_type(v)
                ),
            ));
        };
        if a.is_empty() {
            return Err(src.err(
                Some(name.loc),
                &name.v,
                "empty axis: give at least one value",
            ));
        }
        let values = a
            .iter()
            .map(|v| scalar(src, &name.v, v))
            .collect::<Result<Vec<_>, _>>()?;
        axes.push(Axis { name, values });
    }
    Ok(axes)
}

fn parse_cases(src: &Src, item: &Item, kloc: Option<Loc>) -> Result<Vec<Vec<Param>>, SpecError> {
    let mut cases = Vec::new();
    match item {
        Item::ArrayOfTables(a) => {
            for t in a.iter() {
                let mut leaves = Vec::new();
                for (k, it) in t.iter() {
                    let l = src.loc(t.key(k).and_then(|k| k.span())).or(kloc);
                    flatten(src, k.to_string(), l, Node::Item(it), &mut leaves)?;
                }
                cases.push(params_of(src, leaves)?);
            }
        }
        Item::Value(Value::Array(a)) => {
            for v in a.iter() {
                let Value::InlineTable(t) = v else {
                    return Err(src.err(
                        src.loc(v.span()),
                        "cases",
                        format!(
                            "each case is a table of parameters, found {}",
                            value_type(v)
                        ),
                    ));
                };
                let mut leaves = Vec::new();
                for (k, v) in t.iter() {
                    let l = src.loc(t.key(k).and_then(|k| k.span())).or(kloc);
                    flatten(src, k.to_string(), l, Node::Value(v), &mut leaves)?;
                }
                cases.push(params_of(src, leaves)?);
            }
        }
        _ => {
            return Err(src.err(
                kloc,
                "cases",
                "must be an array of tables (`[[cases]]`) of parameters",
            ))
        }
    }
    if let Some(i) = cases.iter().position(|c| c.is_empty()) {
        return Err(src.err(kloc, "cases", format!("case {} is empty", i + 1)));
    }
    Ok(cases)
}

fn string_item(src: &Src, name: &str, item: &Item) -> Result<String, SpecError> {
    match item.as_value() {
        Some(Value::String(s)) => Ok(s.value().clone()),
        other => Err(src.err(
            src.loc(item.span()),
            name,
            format!(
                "must be a string, found {}",
                other.map_or("a table", value_type)
            ),
        )),
    }
}

fn bool_item(src: &Src, name: &str, item: &Item) -> Result<bool, SpecError> {
    match item.as_value() {
        Some(Value::Boolean(b)) => Ok(*b.value()),
        other => Err(src.err(
            src.loc(item.span()),
            name,
            format!(
                "must be true or false, found {}",
                other.map_or("a table", value_type)
            ),
        )),
    }
}

/// An array of strings (`components = ["dram", "l2"]`).
fn string_list(src: &Src, name: &str, item: &Item) -> Result<Vec<String>, SpecError> {
    let Some(Value::Array(a)) = item.as_value() else {
        return Err(src.err(src.loc(item.span()), name, "must be an array of strings"));
    };
    a.iter()
        .enumerate()
        .map(|(i, v)| match v {
            Value::String(s) => Ok(s.value().clone()),
            other => Err(src.err(
                src.loc(v.span()).or(src.loc(item.span())),
                &format!("{name}[{i}]"),
                format!("must be a string, found {}", value_type(other)),
            )),
        })
        .collect()
}

/// Whether `s` is a name (of a sweep, a plot): it becomes a file or directory name, so it
/// is letters, digits, `-`, `_` and `.`, not first `.`, at most 100 characters.
pub fn is_name(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 100
        && !s.starts_with('.')
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
}

/// `s` made a name ([`is_name`]): other characters and a leading `.` become `_`.
pub fn safe_name(s: &str) -> String {
    let mut n: String = s
        .chars()
        .take(100)
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if n.is_empty() || n.starts_with('.') {
        n.replace_range(..n.len().min(1), "_");
    }
    n
}

/// A string item that must be a name ([`is_name`]): names are not paths.
fn name_item(src: &Src, name: &str, item: &Item) -> Result<String, SpecError> {
    let s = string_item(src, name, item)?;
    if is_name(&s) {
        Ok(s)
    } else {
        Err(src.err(
            src.loc(item.span()),
            name,
            format!(
                "{s:?} is not a name: it names files in the results directory, so it is 1 to 100 letters, digits, `-`, `_` and `.` (not first), not a path"
            ),
        ))
    }
}

fn int_item(src: &Src, name: &str, item: &Item, min: i64, max: i64) -> Result<i64, SpecError> {
    match item.as_value() {
        Some(Value::Integer(i)) if (min..=max).contains(i.value()) => Ok(*i.value()),
        Some(Value::Integer(i)) => Err(src.err(
            src.loc(item.span()),
            name,
            format!("{} is out of range {min}..={max}", i.value()),
        )),
        other => Err(src.err(
            src.loc(item.span()),
            name,
            format!(
                "must be an integer, found {}",
                other.map_or("a table", value_type)
            ),
        )),
    }
}

/// A key of a table, its item and the key's position.
type Entry<'a> = (&'a str, Item, Option<Loc>);

/// The `(key, item)` pairs of a table item, with the key's position.
fn table_entries<'a>(
    src: &Src,
    name: &str,
    item: &'a Item,
    kloc: Option<Loc>,
) -> Result<Vec<Entry<'a>>, SpecError> {
    match item {
        Item::Table(t) => Ok(t
            .iter()
            .map(|(k, it)| {
                (
                    k,
                    it.clone(),
                    src.loc(t.key(k).and_then(|k| k.span())).or(kloc),
                )
            })
            .collect()),
        Item::Value(Value::InlineTable(t)) => Ok(t
            .iter()
            .map(|(k, v)| {
                (
                    k,
                    Item::Value(v.clone()),
                    src.loc(t.key(k).and_then(|k| k.span())).or(kloc),
                )
            })
            .collect()),
        _ => Err(src.err(kloc, name, "must be a table")),
    }
}

fn parse_slurm(src: &Src, item: &Item, kloc: Option<Loc>) -> Result<SlurmSettings, SpecError> {
    let mut s = SlurmSettings::default();
    for (k, it, l) in table_entries(src, "slurm", item, kloc)? {
        let field = format!("slurm.{k}");
        let it = &it;
        let at = |e: SpecError| SpecError {
            loc: e.loc.or(l),
            ..e
        };
        match k {
            "partition" => s.partition = Some(string_item(src, &field, it).map_err(at)?),
            "time" => s.time = Some(string_item(src, &field, it).map_err(at)?),
            "account" => s.account = Some(string_item(src, &field, it).map_err(at)?),
            "per_task" => {
                s.per_task = Some(int_item(src, &field, it, 1, 1_000_000).map_err(at)? as u32)
            }
            "max_running" => {
                s.max_running = Some(int_item(src, &field, it, 1, 1_000_000).map_err(at)? as u32)
            }
            "cpus_per_task" => {
                s.cpus_per_task = Some(int_item(src, &field, it, 1, 4096).map_err(at)? as u32)
            }
            _ => {
                return Err(src.err(
                    l,
                    &field,
                    "unknown field (expected partition, time, account, per_task, max_running, cpus_per_task)",
                ))
            }
        }
    }
    Ok(s)
}

fn parse_plots(src: &Src, item: &Item, kloc: Option<Loc>) -> Result<Vec<PlotSpec>, SpecError> {
    let Item::ArrayOfTables(a) = item else {
        return Err(src.err(kloc, "plot", "must be an array of tables (`[[plot]]`)"));
    };
    let mut plots = Vec::new();
    for (i, t) in a.iter().enumerate() {
        let tloc = src.loc(t.span()).or(kloc);
        let mut x = None;
        let mut y = None;
        let mut by = None;
        let mut kind = PlotKind::Line;
        let mut title = None;
        let mut name = None;
        let mut filter = Vec::new();
        let (mut xlabel, mut ylabel, mut log_x, mut log_y) = (None, None, None, None);
        let mut components = Vec::new();
        let table_item = Item::Table(t.clone());
        for (k, it, l) in table_entries(src, "plot", &table_item, tloc)? {
            let field = format!("plot[{i}].{k}");
            let it = &it;
            let at = |e: SpecError| SpecError {
                loc: e.loc.or(l),
                ..e
            };
            match k {
                "x" => x = Some(string_item(src, &field, it).map_err(at)?),
                "y" => y = Some(string_item(src, &field, it).map_err(at)?),
                "by" => by = Some(string_item(src, &field, it).map_err(at)?),
                "title" => title = Some(string_item(src, &field, it).map_err(at)?),
                "xlabel" => xlabel = Some(string_item(src, &field, it).map_err(at)?),
                "ylabel" => ylabel = Some(string_item(src, &field, it).map_err(at)?),
                "log_x" => log_x = Some(bool_item(src, &field, it).map_err(at)?),
                "log_y" => log_y = Some(bool_item(src, &field, it).map_err(at)?),
                "components" => components = string_list(src, &field, it).map_err(at)?,
                "name" => name = Some(name_item(src, &field, it).map_err(at)?),
                "kind" => {
                    let s = string_item(src, &field, it).map_err(at)?;
                    kind = match s.as_str() {
                        "line" => PlotKind::Line,
                        "bar" => PlotKind::Bar,
                        "energy" => PlotKind::Energy,
                        _ => {
                            return Err(src.err(
                                src.loc(it.span()).or(l),
                                &field,
                                format!("unknown kind {s:?} (expected line, bar or energy)"),
                            ))
                        }
                    };
                }
                "where" => {
                    for (fk, fit, fl) in table_entries(src, &field, it, l)? {
                        let v = match fit.as_value() {
                            Some(v) => scalar(src, &format!("{field}.{fk}"), v)?,
                            None => {
                                return Err(src.err(
                                    fl,
                                    &format!("{field}.{fk}"),
                                    "must be a value",
                                ))
                            }
                        };
                        filter.push((fk.to_string(), v.v.plain()));
                    }
                }
                _ => {
                    return Err(src.err(
                        l,
                        &field,
                        "unknown field (expected x, y, by, kind, title, name, where, xlabel, \
                         ylabel, log_x, log_y, components)",
                    ))
                }
            }
        }
        let Some(x) = x else {
            return Err(src.err(tloc, &format!("plot[{i}]"), "needs `x` (a parameter)"));
        };
        let y = match (y, kind) {
            (Some(y), _) => y,
            (None, PlotKind::Energy) => "energy_j".to_string(),
            (None, _) => {
                return Err(src.err(tloc, &format!("plot[{i}]"), "needs `y` (a metric)"));
            }
        };
        let named = name.is_some();
        let name = name.unwrap_or_else(|| default_plot_name(&x, &y, by.as_deref()));
        // Two plots with one name would write one file, the second silently replacing the
        // first (plot names are file names under `plots/`).
        if let Some((j, _)) = plots
            .iter()
            .enumerate()
            .find(|(_, p): &(usize, &PlotSpec)| p.name == name)
        {
            let how = if named {
                "is named"
            } else {
                "gets the default name"
            };
            return Err(src.err(
                tloc,
                &format!("plot[{i}]"),
                format!(
                    "{how} {name:?}, as plot[{j}] is too: both would write plots/{name}.png; \
                     give one a different `name`"
                ),
            ));
        }
        plots.push(PlotSpec {
            name,
            x,
            y,
            by,
            kind,
            title,
            filter,
            xlabel,
            ylabel,
            log_x,
            log_y,
            components,
            loc: tloc,
        });
    }
    Ok(plots)
}

/// `Y_vs_X[_by_B]`.
pub fn default_plot_name(x: &str, y: &str, by: Option<&str>) -> String {
    let mut n = format!("{y}_vs_{x}");
    if let Some(b) = by {
        n.push_str("_by_");
        n.push_str(b);
    }
    safe_name(&n.replace('.', "_"))
}

/// Checks knob values, reserved names and parameters given twice.
fn check_names(src: &Src, spec: &SweepSpec) -> Result<(), SpecError> {
    let check = |name: &At<String>, v: &At<PVal>| -> Result<(), SpecError> {
        if RESERVED.contains(&name.v.as_str()) {
            return Err(src.err(
                Some(name.loc),
                &name.v,
                "can only be given at the top level",
            ));
        }
        check_knob(&name.v, &v.v).map_err(|m| src.err(Some(v.loc), &name.v, m))
    };
    let mut fixed: BTreeMap<&str, Loc> = BTreeMap::new();
    for (n, v) in &spec.fixed {
        check(n, v)?;
        if let Some(prev) = fixed.insert(&n.v, n.loc) {
            return Err(twice(src, n, prev));
        }
    }
    let mut axes: BTreeMap<&str, Loc> = BTreeMap::new();
    for a in &spec.axes {
        for v in &a.values {
            check(&a.name, v)?;
        }
        if let Some(prev) = axes
            .insert(&a.name.v, a.name.loc)
            .or(fixed.get(a.name.v.as_str()).copied())
        {
            return Err(twice(src, &a.name, prev));
        }
    }
    for case in &spec.cases {
        let mut seen: BTreeMap<&str, Loc> = BTreeMap::new();
        for (n, v) in case {
            check(n, v)?;
            if let Some(prev) = seen.insert(&n.v, n.loc) {
                return Err(twice(src, n, prev));
            }
            if let Some(prev) = axes.get(n.v.as_str()) {
                return Err(src.err(
                    Some(n.loc),
                    &n.v,
                    format!("is an axis (line {}); a case can't set it too", prev.line),
                ));
            }
        }
    }
    Ok(())
}

fn twice(src: &Src, n: &At<String>, prev: Loc) -> SpecError {
    src.err(
        Some(n.loc),
        &n.v,
        format!("given twice (also at line {})", prev.line),
    )
}

/// Checks a knob's value (other names are config fields, checked when points are built).
pub fn check_knob(name: &str, v: &PVal) -> Result<(), String> {
    let Some(k) = knob_named(name) else {
        return Ok(());
    };
    match (k.kind, v) {
        (KnobKind::Str, PVal::Str(_)) => Ok(()),
        (KnobKind::OneOf(allowed), PVal::Str(s)) => {
            if allowed.contains(&s.as_str()) {
                Ok(())
            } else {
                Err(format!("{s:?} is not one of {}", allowed.join(", ")))
            }
        }
        (KnobKind::Int(lo, hi), PVal::Int(i)) => {
            if (lo..=hi).contains(i) {
                Ok(())
            } else {
                Err(format!("{i} is out of range {lo}..={hi}"))
            }
        }
        (KnobKind::Int(..), other) => Err(format!(
            "type mismatch: expected an integer, found a {} ({})",
            other.type_name(),
            other.canonical()
        )),
        (_, other) => Err(format!(
            "type mismatch: expected a string, found a {} ({})",
            other.type_name(),
            other.canonical()
        )),
    }
}

/// The points of a sweep as data: every case crossed with every grid combination (the last
/// axis varying fastest), each `repetitions` times. Points are made one at a time from their
/// index ([`Grid::point`]); none is stored, so planning and running a sweep take memory for
/// the sweep file, not for its points (a results directory's `plan.json` holds the grid).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Grid {
    /// Parameters every point shares.
    pub fixed: Vec<(String, At<PVal>)>,
    /// Axes: name and values.
    pub axes: Vec<(String, Vec<At<PVal>>)>,
    /// Cases (at least one, possibly empty).
    pub cases: Vec<Vec<(String, At<PVal>)>>,
    /// Runs of each point.
    pub repetitions: u32,
    /// Indices of combinations whose parameters repeat an earlier one's (sorted): they are
    /// not points of the sweep.
    pub merged: Vec<u64>,
}

/// Points a sweep may have at most.
pub const MAX_POINTS: u64 = 1_000_000;

impl Grid {
    /// The grid of a parsed sweep file, its size checked against [`MAX_POINTS`] (before
    /// anything is made) and repeated points found.
    pub fn new(spec: &SweepSpec) -> Result<Grid, SpecError> {
        let err = |msg: String| SpecError {
            file: spec.file.display().to_string(),
            loc: None,
            field: String::new(),
            msg,
        };
        let factors = std::iter::once(spec.cases.len().max(1) as u64)
            .chain(spec.axes.iter().map(|a| a.values.len() as u64))
            .chain(std::iter::once(u64::from(spec.repetitions)));
        let size = factors.clone().try_fold(1u64, |acc, f| acc.checked_mul(f));
        if size.is_none_or(|n| n > MAX_POINTS) {
            let sizes: Vec<String> = factors.map(|f| f.to_string()).collect();
            let shown = size.map_or_else(|| "more than 2^64".to_string(), |n| n.to_string());
            return Err(err(format!(
                "{shown} points (cases x axis values x repetitions: {}): a sweep may have at most {MAX_POINTS}",
                sizes.join(" x ")
            )));
        }
        let at = |(n, v): &Param| (n.v.clone(), v.clone());
        let mut grid = Grid {
            fixed: spec.fixed.iter().map(at).collect(),
            axes: spec
                .axes
                .iter()
                .map(|a| (a.name.v.clone(), a.values.clone()))
                .collect(),
            cases: if spec.cases.is_empty() {
                vec![Vec::new()]
            } else {
                spec.cases
                    .iter()
                    .map(|c| c.iter().map(at).collect())
                    .collect()
            },
            repetitions: spec.repetitions,
            merged: Vec::new(),
        };
        // Repeated points: sort (id, index) pairs (16 bytes a point, freed on return).
        let mut ids: Vec<(u64, u64)> = Vec::with_capacity(grid.combinations() as usize);
        for i in 0..grid.combinations() {
            let p = grid.point(i);
            if !p.params.contains_key("kernel") {
                return Err(SpecError {
                    field: "kernel".into(),
                    ..err("no kernel: give `kernel = \"PATH\"` (at the top level, as an axis or in every case)".into())
                });
            }
            ids.push((p.id_bits, i));
        }
        ids.sort_unstable();
        grid.merged = ids
            .windows(2)
            .filter(|w| w[0].0 == w[1].0)
            .map(|w| w[1].1)
            .collect();
        grid.merged.sort_unstable();
        Ok(grid)
    }

    /// Combinations (points before merging repeated ones).
    pub fn combinations(&self) -> u64 {
        let grid: u64 = self.axes.iter().map(|(_, v)| v.len() as u64).product();
        self.cases.len() as u64 * grid * u64::from(self.repetitions)
    }

    /// Points of the sweep.
    pub fn point_count(&self) -> u64 {
        self.combinations() - self.merged.len() as u64
    }

    /// The combination indices of the points, in sweep order.
    pub fn indices(&self) -> impl Iterator<Item = u64> + '_ {
        let mut skip = self.merged.iter().peekable();
        (0..self.combinations()).filter(move |i| {
            if skip.peek() == Some(&i) {
                skip.next();
                false
            } else {
                true
            }
        })
    }

    /// The point of combination `i` (`i` < [`Grid::combinations`]): case-major, then the grid
    /// (last axis fastest), then the repetition.
    pub fn point(&self, i: u64) -> Point {
        let reps = u64::from(self.repetitions);
        let rep = i % reps;
        let mut rest = i / reps;
        let mut chosen = Vec::with_capacity(self.axes.len());
        for (name, values) in self.axes.iter().rev() {
            let n = values.len() as u64;
            chosen.push((name, &values[(rest % n) as usize]));
            rest /= n;
        }
        let case = &self.cases[rest as usize];
        let mut params = BTreeMap::new();
        let mut locs = BTreeMap::new();
        for (n, v) in self.fixed.iter().chain(case.iter()) {
            params.insert(n.clone(), v.v.clone());
            locs.insert(n.clone(), v.loc);
        }
        for (n, v) in chosen.into_iter().rev() {
            params.insert(n.clone(), v.v.clone());
            locs.insert(n.clone(), v.loc);
        }
        for k in KNOBS {
            if let (false, Some(d)) = (params.contains_key(k.name), k.default) {
                let v = match d {
                    DefaultVal::Str(s) => PVal::Str(s.to_string()),
                    DefaultVal::Int(i) => PVal::Int(i),
                };
                params.insert(k.name.to_string(), v);
            }
        }
        if self.repetitions > 1 {
            params.insert("rep".into(), PVal::Int(rep as i64));
        }
        let id_bits = point_id_bits(&params);
        Point {
            id: format!("{id_bits:016x}"),
            id_bits,
            index: i,
            params,
            locs,
        }
    }

    /// The point with id `id` at combination `i`, if that is its id and it is a point.
    pub fn point_at(&self, i: u64, id: &str) -> Option<Point> {
        if i >= self.combinations() || self.merged.binary_search(&i).is_ok() {
            return None;
        }
        Some(self.point(i)).filter(|p| p.id == id)
    }
}

/// The stable id of a point's parameters (see the module documentation), as a number (the
/// id is its 16 hex digits).
fn point_id_bits(params: &BTreeMap<String, PVal>) -> u64 {
    let mut h = Sha256::new();
    h.update(b"trax-sweep-point/1\n");
    for (k, v) in params {
        if k == "rep" && *v == PVal::Int(0) {
            continue;
        }
        h.update(format!("{k}={}\n", v.canonical()).as_bytes());
    }
    let digest = h.finalize();
    let mut b = [0u8; 8];
    b.copy_from_slice(&digest[..8]);
    u64::from_be_bytes(b)
}

/// The parameter columns of the table, in order: axes (file order), case parameters, fixed
/// parameters, knobs (knob order: those with a default, and those the file gives), then
/// `rep`.
pub fn columns(spec: &SweepSpec) -> Vec<String> {
    let mut cols: Vec<String> = Vec::new();
    let mut add = |n: &str| {
        if !cols.iter().any(|c| c == n) {
            cols.push(n.to_string());
        }
    };
    for a in &spec.axes {
        add(&a.name.v);
    }
    for c in &spec.cases {
        for (n, _) in c {
            add(&n.v);
        }
    }
    for (n, _) in &spec.fixed {
        add(&n.v);
    }
    for k in KNOBS {
        if k.default.is_some() {
            add(k.name);
        }
    }
    if spec.repetitions > 1 {
        add("rep");
    }
    cols
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plots(body: &str) -> Result<Vec<PlotSpec>, String> {
        let text = format!("kernel = \"k.rs\"\n[axes]\ntms = [1, 2]\n[[plot]]\n{body}");
        parse(&text, Path::new("s.toml"))
            .map(|s| s.plots)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn two_plots_writing_one_file_are_refused() {
        // Same x and y, no names: the second chart would replace the first's file.
        let e =
            plots("x = \"tms\"\ny = \"fps\"\n[[plot]]\nx = \"tms\"\ny = \"fps\"\nkind = \"bar\"\n")
                .unwrap_err();
        assert!(
            e.contains("plot[1]")
                && e.contains("plot[0]")
                && e.contains("fps_vs_tms")
                && e.contains(":7:"),
            "{e}"
        );
        // An explicit name equal to another plot's default name is the same clash.
        let e = plots("x = \"tms\"\ny = \"fps\"\n[[plot]]\nx = \"tms\"\ny = \"cycles\"\nname = \"fps_vs_tms\"\n")
            .unwrap_err();
        assert!(e.contains("is named \"fps_vs_tms\""), "{e}");
        // Distinct names are fine.
        let p = plots("x = \"tms\"\ny = \"fps\"\n[[plot]]\nx = \"tms\"\ny = \"fps\"\nkind = \"bar\"\nname = \"fps_bars\"\n")
            .unwrap();
        assert_eq!(p.len(), 2);
    }

    #[test]
    fn plot_keys_of_the_command_line_are_sweep_file_keys_too() {
        let p = plots(
            "x = \"tms\"\ny = \"energy_j\"\nkind = \"energy\"\nxlabel = \"TMs\"\n\
             ylabel = \"Energy (J)\"\nlog_x = true\nlog_y = false\n\
             components = [\"dram\", \"l2\"]\n",
        )
        .unwrap();
        assert_eq!(p[0].xlabel.as_deref(), Some("TMs"));
        assert_eq!(p[0].ylabel.as_deref(), Some("Energy (J)"));
        assert_eq!((p[0].log_x, p[0].log_y), (Some(true), Some(false)));
        assert_eq!(p[0].components, ["dram", "l2"]);
        // Left out: chosen when drawing.
        let p = plots("x = \"tms\"\ny = \"fps\"\n").unwrap();
        assert_eq!((p[0].xlabel.clone(), p[0].log_x), (None, None));
        assert!(p[0].components.is_empty());
        // Wrong types name the field and its line.
        for (body, field, line, msg) in [
            (
                "x = \"tms\"\ny = \"fps\"\nlog_x = \"yes\"\n",
                "plot[0].log_x",
                ":7",
                "true or false",
            ),
            (
                "x = \"tms\"\ny = \"fps\"\ncomponents = \"dram\"\n",
                "plot[0].components",
                ":7",
                "array",
            ),
            (
                "x = \"tms\"\ny = \"fps\"\ncomponents = [1]\n",
                "plot[0].components[0]",
                ":7",
                "string",
            ),
            (
                "x = \"tms\"\ny = \"fps\"\nxlabel = 3\n",
                "plot[0].xlabel",
                ":7",
                "string",
            ),
        ] {
            let e = plots(body).unwrap_err();
            assert!(
                e.contains(field) && e.contains(line) && e.contains(msg),
                "{body}: {e}"
            );
        }
    }
}
