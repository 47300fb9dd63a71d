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
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
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
#[derive(Clone, Debug)]
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
}

/// One expanded point.
#[derive(Clone, Debug)]
pub struct Point {
    /// Stable id (see the module documentation).
    pub id: String,
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
            .map_or_else(|| "sweep".into(), |s| s.to_string_lossy().into_owned()),
        fixed: Vec::new(),
        axes: Vec::new(),
        cases: Vec::new(),
        repetitions: 1,
        slurm: SlurmSettings::default(),
        plots: Vec::new(),
    };
    let root = doc.as_table();
    for (key, item) in root.iter() {
        let kloc = src.loc(root.key(key).and_then(|k| k.span()));
        match key {
            "name" => spec.name = string_item(&src, key, item)?,
            "repetitions" => {
                spec.repetitions = int_item(&src, key, item, 1, 1_000_000)? as u32;
            }
            "axes" => spec.axes = parse_axes(&src, item, kloc)?,
            "cases" => spec.cases = parse_cases(&src, item, kloc)?,
            "slurm" => spec.slurm = parse_slurm(&src, item, kloc)?,
            "plot" => spec.plots = parse_plots(&src, item, kloc)?,
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
                "name" => name = Some(string_item(src, &field, it).map_err(at)?),
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
                        "unknown field (expected x, y, by, kind, title, name, where)",
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
        let name = name.unwrap_or_else(|| default_plot_name(&x, &y, by.as_deref()));
        plots.push(PlotSpec {
            name,
            x,
            y,
            by,
            kind,
            title,
            filter,
            xlabel: None,
            ylabel: None,
            log_x: None,
            log_y: None,
            components: Vec::new(),
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
    n.replace(['/', '\\', ' ', '.'], "_")
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

/// The points of a sweep: every case crossed with every grid combination (the last axis
/// varying fastest), each `repetitions` times; identical points are merged. Also returns how
/// many were merged.
pub fn expand(spec: &SweepSpec) -> Result<(Vec<Point>, usize), SpecError> {
    let src_err = |loc: Option<Loc>, field: &str, msg: String| SpecError {
        file: spec.file.display().to_string(),
        loc,
        field: field.to_string(),
        msg,
    };
    let empty = Vec::new();
    let cases: Vec<&Vec<Param>> = if spec.cases.is_empty() {
        vec![&empty]
    } else {
        spec.cases.iter().collect()
    };
    let grid_size: usize = spec.axes.iter().map(|a| a.values.len()).product();
    let total = cases.len() * grid_size * spec.repetitions as usize;
    if total > MAX_POINTS {
        return Err(src_err(
            None,
            "",
            format!("{total} points is more than the {MAX_POINTS} a sweep may have"),
        ));
    }
    let mut points = Vec::with_capacity(total);
    let mut seen = std::collections::HashSet::new();
    let mut merged = 0;
    for case in cases {
        for g in 0..grid_size {
            for rep in 0..spec.repetitions {
                let mut params = BTreeMap::new();
                let mut locs = BTreeMap::new();
                for (n, v) in spec.fixed.iter().chain(case.iter()) {
                    params.insert(n.v.clone(), v.v.clone());
                    locs.insert(n.v.clone(), v.loc);
                }
                let mut rest = g;
                for a in spec.axes.iter().rev() {
                    let v = &a.values[rest % a.values.len()];
                    rest /= a.values.len();
                    params.insert(a.name.v.clone(), v.v.clone());
                    locs.insert(a.name.v.clone(), v.loc);
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
                if !params.contains_key("kernel") {
                    return Err(src_err(
                        None,
                        "kernel",
                        "no kernel: give `kernel = \"PATH\"` (at the top level, as an axis or in every case)".into(),
                    ));
                }
                if spec.repetitions > 1 {
                    params.insert("rep".into(), PVal::Int(rep as i64));
                }
                let id = point_id(&params);
                if seen.insert(id.clone()) {
                    points.push(Point { id, params, locs });
                } else {
                    merged += 1;
                }
            }
        }
    }
    Ok((points, merged))
}

/// Points a sweep may have at most.
pub const MAX_POINTS: usize = 1_000_000;

/// The stable id of a point's parameters (see the module documentation).
pub fn point_id(params: &BTreeMap<String, PVal>) -> String {
    let mut h = Sha256::new();
    h.update(b"trax-sweep-point/1\n");
    for (k, v) in params {
        if k == "rep" && *v == PVal::Int(0) {
            continue;
        }
        h.update(format!("{k}={}\n", v.canonical()).as_bytes());
    }
    let digest = h.finalize();
    digest[..8].iter().map(|b| format!("{b:02x}")).collect()
}

/// The parameter columns of the table, in order: axes (file order), case parameters, fixed
/// parameters, knob defaults (knob order), then `rep`.
pub fn columns(spec: &SweepSpec, points: &[Point]) -> Vec<String> {
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
        if points.iter().any(|p| p.params.contains_key(k.name)) {
            add(k.name);
        }
    }
    if spec.repetitions > 1 {
        add("rep");
    }
    cols
}
