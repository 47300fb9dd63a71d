//! The plan of a sweep (`DIR/plan.json`): every point with its parameters and the exact
//! `trax run` command, and the kernels built for them. Whatever runs the points (this machine,
//! Slurm array tasks) and `trax sweep collect` read it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use trax_emulator::timing::ChipConfig;

use super::spec::{self, PVal, PlotSpec, Point, SpecError, SweepSpec, KNOBS};
use trax::pipeline::chip_config;

/// Format tag of `plan.json`.
pub const PLAN_FORMAT: &str = "trax-sweep-plan/1";

/// A sweep's plan.
#[derive(Debug, Serialize, Deserialize)]
pub struct Plan {
    /// [`PLAN_FORMAT`].
    pub format: String,
    /// Sweep name.
    pub name: String,
    /// The sweep file (absolute).
    pub sweep_file: String,
    /// Parameter columns of the table, in order.
    pub columns: Vec<String>,
    /// Kernels, built once each.
    pub kernels: Vec<Kernel>,
    /// Points, in sweep order.
    pub points: Vec<PlanPoint>,
    /// Plots `collect` draws.
    pub plots: Vec<PlotSpec>,
    /// Slurm defaults from the sweep file.
    pub slurm: spec::SlurmSettings,
}

/// A kernel built for the sweep.
#[derive(Debug, Serialize, Deserialize)]
pub struct Kernel {
    /// Source file (absolute).
    pub source: String,
    /// Optimisation level.
    pub opt_level: u8,
    /// The executable under `DIR/build/` (absolute).
    pub elf: String,
    /// SHA-256 of the source file.
    pub source_sha256: String,
    /// SHA-256 of the executable (covers every source file and the compiler).
    pub elf_sha256: String,
}

/// One point of the plan.
#[derive(Debug, Serialize, Deserialize)]
pub struct PlanPoint {
    /// Stable id.
    pub id: String,
    /// Parameters.
    pub params: BTreeMap<String, PVal>,
    /// Index into [`Plan::kernels`].
    pub kernel: usize,
    /// Arguments of `trax` after the executable: `run ELF ARGS..` (without `--stats-json`
    /// and `--host-threads`, which the runner adds).
    pub args: Vec<String>,
    /// Chip config preset or file (absolute).
    pub config: String,
    /// Config field overrides.
    pub sets: Vec<(String, PVal)>,
    /// `--threads`, `--l2s`.
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

/// A path from the sweep file, relative to its directory, made absolute.
fn resolve_path(spec: &SweepSpec, p: &str) -> PathBuf {
    let path = Path::new(p);
    let joined = if path.is_absolute() {
        path.to_path_buf()
    } else {
        spec.dir.join(path)
    };
    std::path::absolute(&joined).unwrap_or(joined)
}

fn err_at(spec: &SweepSpec, p: &Point, field: &str, msg: String) -> SpecError {
    SpecError {
        file: spec.file.display().to_string(),
        loc: p.locs.get(field).copied(),
        field: field.to_string(),
        msg,
    }
}

/// Builds the plan: resolves every point's paths, checks its chip config (an unknown field,
/// a wrong type or a value out of range is an error naming the field and its line), and
/// lists the kernels to build (under `build_dir`).
pub fn make_plan(spec: &SweepSpec, points: &[Point], build_dir: &Path) -> Result<Plan, SpecError> {
    let mut kernels: Vec<Kernel> = Vec::new();
    let mut configs: BTreeMap<String, Result<ChipConfig, String>> = BTreeMap::new();
    let mut out = Vec::with_capacity(points.len());
    for p in points {
        let s = |k: &str| match p.params.get(k) {
            Some(PVal::Str(s)) => Some(s.clone()),
            _ => None,
        };
        let int = |k: &str| match p.params.get(k) {
            Some(PVal::Int(i)) => Some(*i),
            _ => None,
        };
        // Kernel.
        let kernel_rel = s("kernel").unwrap_or_default();
        let source = resolve_path(spec, &kernel_rel);
        if !source.is_file() {
            return Err(err_at(
                spec,
                p,
                "kernel",
                format!("{}: no such file", source.display()),
            ));
        }
        let opt = int("opt_level").unwrap_or(2) as u8;
        let src_str = source.display().to_string();
        let kernel = match kernels
            .iter()
            .position(|k| k.source == src_str && k.opt_level == opt)
        {
            Some(i) => i,
            None => {
                let stem = source
                    .file_stem()
                    .map_or_else(|| "kernel".into(), |s| s.to_string_lossy().into_owned());
                let tag = &sha256_hex(src_str.as_bytes())[..8];
                let elf = build_dir.join(format!("{stem}-O{opt}-{tag}.elf"));
                kernels.push(Kernel {
                    source: src_str,
                    opt_level: opt,
                    elf: elf.display().to_string(),
                    source_sha256: String::new(),
                    elf_sha256: String::new(),
                });
                kernels.len() - 1
            }
        };
        // Chip config: the base, then each field (so an error names its line).
        let config_rel = s("config").unwrap_or_else(|| "tiny".into());
        let config = if ChipConfig::preset(&config_rel).is_some() {
            config_rel.clone()
        } else {
            resolve_path(spec, &config_rel).display().to_string()
        };
        let base = configs
            .entry(config.clone())
            .or_insert_with(|| ChipConfig::load(&config).map_err(|e| e.to_string()))
            .clone()
            .map_err(|e| err_at(spec, p, "config", e))?;
        let mut sets = Vec::new();
        let mut chip = base;
        for (k, v) in &p.params {
            if k == "rep" || spec::is_label(k) || KNOBS.iter().any(|kn| kn.name == k) {
                continue;
            }
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
                err_at(spec, p, k, msg)
            })?;
            sets.push((k.clone(), v.clone()));
        }
        let threads = int("threads").map(|t| t as u32);
        let l2s = int("l2s").map(|t| t as u32);
        let toml_sets: Vec<(String, toml::Value)> =
            sets.iter().map(|(k, v)| (k.clone(), v.to_toml())).collect();
        if let Err(e) = chip_config(&config, &toml_sets, None, threads, l2s) {
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
                file: spec.file.display().to_string(),
                loc: p.locs.get(&field).copied(),
                field,
                msg: format!("{e} (point {})", describe(p)),
            });
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
            let path = resolve_path(spec, innermost);
            if !path.is_file() {
                return Err(err_at(
                    spec,
                    p,
                    "scene",
                    format!("{}: no such file", path.display()),
                ));
            }
            format!("{wrappers}{}", path.display())
        };
        args.extend(["--scene".into(), scene_arg]);
        for k in ["view", "light"] {
            if let Some(v) = s(k) {
                let path = resolve_path(spec, &v);
                if !path.is_file() {
                    return Err(err_at(
                        spec,
                        p,
                        k,
                        format!("{}: no such file", path.display()),
                    ));
                }
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
        ] {
            if let Some(v) = int(k) {
                args.extend([format!("--{}", k.replace('_', "-")), v.to_string()]);
            }
        }
        if s("mode").as_deref() == Some("functional") {
            args.push("--functional".into());
        }
        out.push(PlanPoint {
            id: p.id.clone(),
            params: p.params.clone(),
            kernel,
            args,
            config,
            sets,
            threads,
            l2s,
        });
    }
    let sweep_file = std::path::absolute(&spec.file).unwrap_or_else(|_| spec.file.clone());
    Ok(Plan {
        format: PLAN_FORMAT.into(),
        name: spec.name.clone(),
        sweep_file: sweep_file.display().to_string(),
        columns: spec::columns(spec, points),
        kernels,
        points: out,
        plots: spec.plots.clone(),
        slurm: spec.slurm.clone(),
    })
}

/// `name=value, ...` of a point's parameters.
pub fn describe(p: &Point) -> String {
    p.params
        .iter()
        .map(|(k, v)| format!("{k}={}", v.plain()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Builds every kernel of the plan with `trax build` (this executable) and records the
/// hashes; the executable goes to a temporary name first, so a kernel is never half there.
pub fn build_kernels(plan: &mut Plan, exe: &Path) -> Result<(), String> {
    for k in &mut plan.kernels {
        let elf = PathBuf::from(&k.elf);
        if let Some(dir) = elf.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let tmp = elf.with_extension(format!("elf.tmp.{}", std::process::id()));
        eprintln!("building {} (-O{})", k.source, k.opt_level);
        let out = Command::new(exe)
            .arg("build")
            .arg(&k.source)
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
        std::fs::rename(&tmp, &elf).map_err(|e| format!("{}: {e}", elf.display()))?;
        let src = std::fs::read(&k.source).map_err(|e| format!("{}: {e}", k.source))?;
        let bin = std::fs::read(&elf).map_err(|e| format!("{}: {e}", elf.display()))?;
        k.source_sha256 = sha256_hex(&src);
        k.elf_sha256 = sha256_hex(&bin);
    }
    Ok(())
}

impl Plan {
    /// Reads `DIR/plan.json`.
    pub fn load(dir: &Path) -> Result<Plan, String> {
        let path = dir.join("plan.json");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            format!(
                "{}: {e} (is {} a sweep results directory?)",
                path.display(),
                dir.display()
            )
        })?;
        let plan: Plan =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        if plan.format != PLAN_FORMAT {
            return Err(format!(
                "{}: format {:?}, expected {PLAN_FORMAT:?}",
                path.display(),
                plan.format
            ));
        }
        Ok(plan)
    }

    /// Writes `DIR/plan.json` (atomically).
    pub fn save(&self, dir: &Path) -> Result<(), String> {
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        write_atomic(&dir.join("plan.json"), (text + "\n").as_bytes())
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
