//! The plan of a sweep (`DIR/plan.json`): the grid of points ([`Grid`]: each point is made
//! from its index when needed, none is stored), the kernels built for them and how a point
//! becomes a `trax run` command ([`Plan::point`]). Whatever runs the points (this machine,
//! Slurm array tasks) and `trax sweep collect`/`status` read it.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::pipeline::{chip_config, KernelFile};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use trax_emulator::timing::sample::{DEFAULT_WARMUP, DEFAULT_WINDOW};
use trax_emulator::timing::ChipConfig;

use super::spec::{self, Grid, Limits, PVal, PlotSpec, Point, SpecError, SweepSpec, KNOBS};

/// Format tag of `plan.json`.
pub const PLAN_FORMAT: &str = "trax-sweep-plan/2";

/// A sweep's plan.
#[derive(Debug, Serialize, Deserialize)]
pub struct Plan {
    /// [`PLAN_FORMAT`].
    pub format: String,
    /// Sweep name.
    pub name: String,
    /// The sweep file as given (errors name it).
    pub sweep_file: String,
    /// The directory its relative paths are resolved against (absolute).
    pub base_dir: String,
    /// Parameter columns of the table, in order.
    pub columns: Vec<String>,
    /// Kernels, built once each.
    pub kernels: Vec<Kernel>,
    /// The points.
    pub grid: Grid,
    /// Plots `collect` draws.
    pub plots: Vec<PlotSpec>,
    /// Slurm defaults from the sweep file.
    pub slurm: spec::SlurmSettings,
    /// Per-point limits from the sweep file.
    pub limits: Limits,
}

/// A kernel of the sweep.
#[derive(Debug, Serialize, Deserialize)]
pub struct Kernel {
    /// Source file, or a prebuilt executable (absolute).
    pub source: String,
    /// Optimisation level.
    pub opt_level: u8,
    /// The executable the points run: `DIR/build/STEM-O<level>-<SHA-256 prefix>.elf`, named
    /// by its content, so a rebuild never changes the file a running point reads.
    pub elf: String,
    /// SHA-256 of the source file.
    pub source_sha256: String,
    /// SHA-256 of the executable (covers every source file, header and `mod` file it was
    /// built from, and the compiler).
    pub elf_sha256: String,
}

/// One point of the plan, as it runs.
#[derive(Debug)]
pub struct PlanPoint {
    /// Combination index in the grid.
    pub index: u64,
    /// Stable id.
    pub id: String,
    /// Parameters.
    pub params: BTreeMap<String, PVal>,
    /// Index into [`Plan::kernels`].
    pub kernel: usize,
    /// Arguments of `trax` after `run ELF` (without `--stats-json` and `--host-threads`,
    /// which the runner adds).
    pub args: Vec<String>,
    /// Chip config preset or file (absolute).
    pub config: String,
    /// Config field overrides.
    pub sets: Vec<(String, PVal)>,
    /// `--threads`.
    pub threads: Option<u32>,
    /// `--l2s`.
    pub l2s: Option<u32>,
}

impl PlanPoint {
    /// The `trax` arguments of this point.
    pub fn command(&self, plan: &Plan) -> Vec<String> {
        let mut v = vec!["run".to_string(), plan.kernels[self.kernel].elf.clone()];
        v.extend(self.args.iter().cloned());
        v
    }

    /// The chip this point simulates (as `trax run` builds it).
    pub fn chip(&self) -> Result<ChipConfig, String> {
        let sets: Vec<(String, toml::Value)> = self
            .sets
            .iter()
            .map(|(k, v)| (k.clone(), v.to_toml()))
            .collect();
        chip_config(&self.config, &sets, None, self.threads, self.l2s)
    }
}

/// Hex SHA-256 of bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// What planning checks once per distinct value, so a sweep of many points checks each
/// file and chip once (16 bytes a distinct chip).
#[derive(Default)]
struct Checks {
    files: HashMap<PathBuf, bool>,
    configs: BTreeMap<String, Result<ChipConfig, String>>,
    chips: HashSet<[u8; 16]>,
}

impl Plan {
    /// Plans a sweep: checks every point (its files exist; its chip config builds, an
    /// unknown field, a wrong type or a value out of range being an error naming the field
    /// and its line) and lists the kernels to build ([`build_kernels`]). Memory: the sweep
    /// file and 16 bytes a point while repeated points are found ([`Grid::new`]).
    pub fn new(spec: &SweepSpec) -> Result<Plan, SpecError> {
        let base = std::path::absolute(&spec.dir).unwrap_or_else(|_| spec.dir.clone());
        let mut plan = Plan {
            format: PLAN_FORMAT.into(),
            name: spec.name.clone(),
            sweep_file: spec.file.display().to_string(),
            base_dir: base.display().to_string(),
            columns: spec::columns(spec),
            kernels: Vec::new(),
            grid: Grid::new(spec)?,
            plots: spec.plots.clone(),
            slurm: spec.slurm.clone(),
            limits: spec.limits.clone(),
        };
        let mut checks = Checks::default();
        for i in 0..plan.grid.combinations() {
            if plan.grid.merged.binary_search(&i).is_ok() {
                continue;
            }
            let p = plan.grid.point(i);
            let mut kernels = std::mem::take(&mut plan.kernels);
            let r = plan.derive(
                &p,
                &mut |src, opt| Ok(kernel_slot(&mut kernels, src, opt)),
                Some(&mut checks),
            );
            plan.kernels = kernels;
            r?;
        }
        Ok(plan)
    }

    /// The point of combination `index` as it runs.
    pub fn point(&self, index: u64) -> Result<PlanPoint, String> {
        let p = self.grid.point(index);
        self.derive(
            &p,
            &mut |src, opt| {
                self.kernels
                    .iter()
                    .position(|k| k.source == src && k.opt_level == opt)
                    .ok_or_else(|| format!("kernel {src} (-O{opt}) is not in the plan"))
            },
            None,
        )
        .map_err(|e| e.to_string())
    }

    /// The points, in sweep order.
    pub fn points(&self) -> impl Iterator<Item = Result<PlanPoint, String>> + '_ {
        self.grid.indices().map(|i| self.point(i))
    }

    /// The point with id `id` at combination `index` (from a Slurm task list).
    pub fn point_with_id(&self, index: u64, id: &str) -> Result<PlanPoint, String> {
        match self.grid.point_at(index, id) {
            Some(_) => self.point(index),
            None => Err(format!(
                "point {id} is not combination {index} of the plan (was the sweep planned again with another file?)"
            )),
        }
    }

    /// A path from the sweep file, relative to its directory, made absolute.
    fn resolve(&self, p: &str) -> PathBuf {
        let path = Path::new(p);
        if path.is_absolute() {
            path.to_path_buf()
        } else {
            Path::new(&self.base_dir).join(path)
        }
    }

    fn err_at(&self, p: &Point, field: &str, msg: String) -> SpecError {
        SpecError {
            file: self.sweep_file.clone(),
            loc: p.locs.get(field).copied(),
            field: field.to_string(),
            msg,
        }
    }

    /// A point's command and chip; with `checks`, also checks its files and chip config.
    fn derive(
        &self,
        p: &Point,
        kernel_of: &mut dyn FnMut(&str, u8) -> Result<usize, String>,
        mut checks: Option<&mut Checks>,
    ) -> Result<PlanPoint, SpecError> {
        let s = |k: &str| match p.params.get(k) {
            Some(PVal::Str(s)) => Some(s.clone()),
            _ => None,
        };
        let int = |k: &str| match p.params.get(k) {
            Some(PVal::Int(i)) => Some(*i),
            _ => None,
        };
        let must_exist = |checks: &mut Option<&mut Checks>, field: &str, path: &Path| {
            if let Some(c) = checks.as_deref_mut() {
                let ok = *c
                    .files
                    .entry(path.to_path_buf())
                    .or_insert_with(|| path.is_file());
                if !ok {
                    return Err(self.err_at(p, field, format!("{}: no such file", path.display())));
                }
            }
            Ok(())
        };
        // Kernel.
        let source = self.resolve(&s("kernel").unwrap_or_default());
        must_exist(&mut checks, "kernel", &source)?;
        let opt = int("opt_level").unwrap_or(2) as u8;
        let kernel = kernel_of(&source.display().to_string(), opt)
            .map_err(|e| self.err_at(p, "kernel", e))?;
        // Chip config: a preset, or a file relative to the sweep file.
        let config_rel = s("config").unwrap_or_else(|| "tiny".into());
        let config = if ChipConfig::preset(&config_rel).is_some() {
            config_rel.clone()
        } else {
            self.resolve(&config_rel).display().to_string()
        };
        let sets: Vec<(String, PVal)> = p
            .params
            .iter()
            .filter(|(k, _)| {
                *k != "rep" && !spec::is_label(k) && !KNOBS.iter().any(|kn| kn.name == *k)
            })
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        let threads = int("threads").map(|t| t as u32);
        let l2s = int("l2s").map(|t| t as u32);
        if let Some(c) = checks.as_deref_mut() {
            self.check_chip(p, c, &config, &sets, threads, l2s)?;
        }
        // The rest of the command line.
        let mut args = vec!["--config".to_string(), config.clone()];
        for (k, v) in &sets {
            args.push("--set".into());
            args.push(format!("{k}={}", v.to_toml()));
        }
        let scene = s("scene").unwrap_or_else(|| "cornell".into());
        // Built-in scenes as they are; a file, also inside `box:`/`subdivide:N:`, from here.
        let (wrappers, innermost, is_file) = trax_assembler::scene::split_spec(&scene);
        let scene_arg = if !is_file {
            scene.clone()
        } else {
            let path = self.resolve(innermost);
            must_exist(&mut checks, "scene", &path)?;
            format!("{wrappers}{}", path.display())
        };
        args.extend(["--scene".into(), scene_arg]);
        for k in ["view", "light"] {
            if let Some(v) = s(k) {
                let path = self.resolve(&v);
                must_exist(&mut checks, k, &path)?;
                args.extend([format!("--{k}"), path.display().to_string()]);
            }
        }
        for k in [
            "width",
            "height",
            "spp",
            "depth",
            "seed",
            "threads",
            "l2s",
            "quantum",
            "max_instructions",
            "max_cycles",
            "sample",
        ]
        .into_iter()
        .chain(spec::SAMPLE_KNOBS.iter().copied())
        {
            if let Some(v) = int(k) {
                args.extend([format!("--{}", k.replace('_', "-")), v.to_string()]);
            }
        }
        if s("mode").as_deref() == Some("functional") {
            args.push("--functional".into());
        }
        if checks.is_some() {
            self.check_sampling(p)?;
        }
        Ok(PlanPoint {
            index: p.index,
            id: p.id.clone(),
            params: p.params.clone(),
            kernel,
            args,
            config,
            sets,
            threads,
            l2s,
        })
    }

    /// Checks a point's sampling knobs against each other and its mode (what `trax run`
    /// would refuse before running; the work items against the chip are checked by the run).
    fn check_sampling(&self, p: &Point) -> Result<(), SpecError> {
        let given = |k: &str| p.params.get(k);
        let sampled = given("sample").is_some();
        if let Some(k) = spec::SAMPLE_KNOBS.iter().find(|k| given(k).is_some()) {
            if !sampled {
                return Err(self.err_at(
                    p,
                    k,
                    format!("`{k}` needs `sample = N` (a sampled run) for this point"),
                ));
            }
        }
        if sampled && given("mode") == Some(&PVal::Str("functional".into())) {
            return Err(self.err_at(
                p,
                "sample",
                "a sampled run is a timing run: `sample` needs `mode = \"timing\"`".into(),
            ));
        }
        let cycles = |k: &str, default: u64| match given(k) {
            Some(PVal::Int(i)) => *i as u64,
            _ => default,
        };
        let warmup = cycles("sample_warmup", DEFAULT_WARMUP);
        let window = cycles("sample_window", DEFAULT_WINDOW);
        if window < warmup {
            let field = if given("sample_window").is_some() {
                "sample_window"
            } else {
                "sample_warmup"
            };
            return Err(self.err_at(
                p,
                field,
                format!(
                    "the measured window ({window} cycles) is shorter than its warm-up ({warmup} cycles)"
                ),
            ));
        }
        Ok(())
    }

    /// Checks a point's chip config: the base, then each field (so an error names its
    /// line), then the whole (ranges and cross-field constraints). Each distinct chip once.
    fn check_chip(
        &self,
        p: &Point,
        c: &mut Checks,
        config: &str,
        sets: &[(String, PVal)],
        threads: Option<u32>,
        l2s: Option<u32>,
    ) -> Result<(), SpecError> {
        let mut key = Sha256::new();
        key.update(format!("{config}\n{threads:?}\n{l2s:?}\n").as_bytes());
        for (k, v) in sets {
            key.update(format!("{k}={}\n", v.canonical()).as_bytes());
        }
        let mut bits = [0u8; 16];
        bits.copy_from_slice(&key.finalize()[..16]);
        if c.chips.contains(&bits) {
            return Ok(());
        }
        let base = c
            .configs
            .entry(config.to_string())
            .or_insert_with(|| ChipConfig::load(config).map_err(|e| e.to_string()))
            .clone()
            .map_err(|e| self.err_at(p, "config", e))?;
        let mut chip = base;
        for (k, v) in sets {
            chip = chip.with_field(k, v.to_toml()).map_err(|e| {
                let msg = e.to_string();
                let prefix = format!("chip config: {k}: ");
                let mut msg = msg.strip_prefix(&prefix).unwrap_or(&msg).to_string();
                if !k.contains('.') && msg.starts_with("unknown field") {
                    let knobs: Vec<&str> = KNOBS.iter().map(|k| k.name).collect();
                    msg = format!(
                        "unknown parameter: not a run knob ({}), a label (`label.NAME`) nor a chip config field ({msg})",
                        knobs.join(", ")
                    );
                }
                self.err_at(p, k, msg)
            })?;
        }
        let toml_sets: Vec<(String, toml::Value)> =
            sets.iter().map(|(k, v)| (k.clone(), v.to_toml())).collect();
        if let Err(e) = chip_config(config, &toml_sets, None, threads, l2s) {
            // A range error: name the config field or knob the message mentions.
            let e = e.strip_prefix("chip config: ").unwrap_or(&e).to_string();
            let knobs = [
                ("threads", "threads_per_tm "),
                ("threads", "--threads"),
                ("l2s", "--l2s"),
            ];
            let field = sets
                .iter()
                .map(|(k, _)| {
                    (
                        k.as_str(),
                        format!("{} ", k.rsplit('.').next().unwrap_or(k)),
                    )
                })
                .chain(knobs.iter().map(|(k, pat)| (*k, pat.to_string())))
                .find(|(k, pat)| p.params.contains_key(*k) && e.contains(pat.as_str()))
                .map(|(k, _)| k.to_string())
                .unwrap_or_default();
            return Err(SpecError {
                file: self.sweep_file.clone(),
                loc: p.locs.get(&field).copied(),
                field,
                msg: format!("{e} (point {})", describe(p)),
            });
        }
        c.chips.insert(bits);
        Ok(())
    }
}

/// The kernel slot of `(source, opt)`, added (to be built) if new.
fn kernel_slot(kernels: &mut Vec<Kernel>, source: &str, opt: u8) -> usize {
    if let Some(i) = kernels
        .iter()
        .position(|k| k.source == source && k.opt_level == opt)
    {
        return i;
    }
    kernels.push(Kernel {
        source: source.to_string(),
        opt_level: opt,
        elf: String::new(),
        source_sha256: String::new(),
        elf_sha256: String::new(),
    });
    kernels.len() - 1
}

/// `name=value, ...` of a point's parameters.
pub fn describe(p: &Point) -> String {
    p.params
        .iter()
        .map(|(k, v)| format!("{k}={}", v.plain()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Builds every kernel of the plan with `trax build` (this executable) into the build
/// directory, named by the executable's content, and records the hashes. A prebuilt
/// executable (a kernel that is not a source file) is copied there as it is.
pub fn build_kernels(plan: &mut Plan, exe: &Path, build_dir: &Path) -> Result<(), String> {
    for k in &mut plan.kernels {
        build_kernel(k, exe, build_dir, false)?;
    }
    Ok(())
}

/// Builds one kernel ([`build_kernels`]); `quiet`: without saying so on stderr.
pub fn build_kernel(
    k: &mut Kernel,
    exe: &Path,
    build_dir: &Path,
    quiet: bool,
) -> Result<(), String> {
    std::fs::create_dir_all(build_dir).map_err(|e| format!("{}: {e}", build_dir.display()))?;
    {
        let source = Path::new(&k.source);
        let stem = source.file_stem().map_or_else(
            || "kernel".into(),
            |s| spec::safe_name(&s.to_string_lossy()),
        );
        let tmp = build_dir.join(format!(".{stem}.{}.tmp", std::process::id()));
        let src = std::fs::read(source).map_err(|e| format!("{}: {e}", k.source))?;
        if KernelFile::of(source).is_source() {
            if !quiet {
                eprintln!("building {} (-O{})", k.source, k.opt_level);
            }
            let out = Command::new(exe)
                .arg("build")
                .arg(source)
                .arg(format!("-O{}", k.opt_level))
                .arg("-o")
                .arg(&tmp)
                .stdin(Stdio::null())
                .output()
                .map_err(|e| format!("{}: {e}", exe.display()))?;
            if !out.status.success() {
                let _ = std::fs::remove_file(&tmp);
                return Err(format!(
                    "building {} failed:\n{}",
                    k.source,
                    String::from_utf8_lossy(&out.stderr).trim_end()
                ));
            }
        } else {
            // A linked executable: checked (a clear error now rather than in every point).
            if let Err(e) = trax_runtime::exe::Executable::parse("it", &src) {
                return Err(format!(
                    "{}: not a kernel source (.rs, .c, .cpp, .cc, .cxx) nor a TRaX executable ({e})",
                    k.source
                ));
            }
            std::fs::write(&tmp, &src).map_err(|e| format!("{}: {e}", tmp.display()))?;
        }
        let bin = std::fs::read(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?;
        k.source_sha256 = sha256_hex(&src);
        k.elf_sha256 = sha256_hex(&bin);
        let elf = build_dir.join(format!(
            "{stem}-O{}-{}.elf",
            k.opt_level,
            &k.elf_sha256[..16]
        ));
        std::fs::rename(&tmp, &elf).map_err(|e| format!("{}: {e}", elf.display()))?;
        k.elf = elf.display().to_string();
    }
    Ok(())
}

impl Plan {
    /// Reads `DIR/plan.json` (or another plan file of a results directory).
    pub fn load_file(path: &Path) -> Result<Plan, String> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            format!(
                "{}: {e} (is {} a sweep results directory?)",
                path.display(),
                path.parent().unwrap_or(Path::new(".")).display()
            )
        })?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let format = v.get("format").and_then(|f| f.as_str()).unwrap_or("");
        if format != PLAN_FORMAT {
            return Err(format!(
                "{}: format {format:?}, expected {PLAN_FORMAT:?} (planned by another version of trax: run the sweep again to plan it anew)",
                path.display(),
            ));
        }
        serde_json::from_value(v).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Reads `DIR/plan.json`.
    pub fn load(dir: &Path) -> Result<Plan, String> {
        Plan::load_file(&dir.join("plan.json"))
    }

    /// Writes `path` (atomically).
    pub fn save_to(&self, path: &Path) -> Result<(), String> {
        let text = serde_json::to_string(self).map_err(|e| e.to_string())?;
        write_atomic(path, (text + "\n").as_bytes())
    }

    /// Writes `DIR/plan.json` (atomically).
    pub fn save(&self, dir: &Path) -> Result<(), String> {
        self.save_to(&dir.join("plan.json"))
    }
}

/// Writes a file whole or not at all: a temporary file in the same directory, then a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.tmp.{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("{}: {e}", path.display())
    })
}
