//! From what a user names (a kernel source or a linked ELF, a scene, image parameters, a
//! chip) to the machine's initial memory: compile, link, load the scene, lay out memory.
//! `trax run`, `trax annotate`, `trax native`, `trax build`, the sweep (through its `trax
//! run` points), the tests and the benchmarks all prepare their programs here.
//!
//! [`prepare`] does every stage for a [`Request`]; the stages are public too
//! ([`executable`], [`load_scene`], [`lay_out`]) for callers that bring their own scene.
//! A [`Prepared`] program turns into a run request for the emulator with
//! [`Prepared::run_request`], and reads its framebuffer back from the run with
//! [`Prepared::framebuffer`].

use std::path::{Path, PathBuf};

use trax_assembler::bvh::{TreeletLayout, TreeletOptions};
use trax_assembler::image::{
    build_image, build_image_from_symbols, on_demand_components, ImageError, RenderOptions,
    SceneImage, StreamShape,
};
use trax_assembler::link::{link, Input, LinkOptions};
use trax_assembler::scene::{LoadOptions, Scene};
use trax_compiler::{compile_file, CompileError, CompileOptions, Emit, Prelude};
use trax_emulator::memsys::dram_config::{DramConfig, DramModel};
use trax_emulator::timing::{ChipConfig, TreeletForm, DEFAULT_CHIP};
use trax_emulator::{Mode, RunReport, RunRequest, Segment};
use trax_runtime::abi::PIXEL_BYTES;
use trax_runtime::exe::Executable;

use crate::clang::{self, ClangError, Lang};
use crate::native::check::{self, CheckError, RustcCheck, Verdict};

/// The optimisation level kernels are built at by default.
pub const DEFAULT_OPT_LEVEL: u8 = 2;

/// What a kernel file is, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelFile {
    /// TRaX-Rust source (`.rs`): compiled by the trax compiler and linked with the runtime.
    Rust,
    /// C (`.c`) or C++ (`.cpp`, `.cc`, `.cxx`) source: compiled by clang-14 against the
    /// generated `trax.h` (see [`crate::clang`]) and linked with the runtime.
    C(Lang),
    /// A relocatable object (`.o`), linked with the others.
    Object,
    /// A linked executable (any other name): read as it is.
    Executable,
}

impl KernelFile {
    /// The kind of `path`.
    pub fn of(path: &Path) -> KernelFile {
        if let Some(lang) = clang::lang_of(path) {
            return KernelFile::C(lang);
        }
        match path.extension().and_then(|e| e.to_str()) {
            Some("rs") => KernelFile::Rust,
            Some("o") => KernelFile::Object,
            _ => KernelFile::Executable,
        }
    }

    /// True for files that are compiled (source), false for objects and executables.
    pub fn is_source(self) -> bool {
        matches!(self, KernelFile::Rust | KernelFile::C(_))
    }
}

/// Everything a program is prepared from.
#[derive(Clone, Debug)]
pub struct Request {
    /// The kernel: source or a linked executable (see [`KernelFile`]).
    pub kernel: PathBuf,
    /// Further sources and objects linked with a kernel source (C, C++, TRaX-Rust, `.o`).
    pub more: Vec<PathBuf>,
    /// Optimisation level when building from source (0..=3).
    pub opt_level: u8,
    /// Scene spec (see [`trax_assembler::scene::load_scene`]; `trax scene --help`).
    pub scene: String,
    /// Camera and light files and the scene scale.
    pub load: LoadOptions,
    /// Image and header parameters. Its `stack_size` and `treelets` are replaced by the
    /// chip's ([`image_options`]).
    pub render: RenderOptions,
    /// The chip the program will run on.
    pub chip: ChipConfig,
    /// A directory of loaded scenes to read the scene from, or keep it in
    /// (`trax_assembler::scene::cache`; `None`: load it).
    pub scene_cache: Option<PathBuf>,
}

impl Request {
    /// `kernel` at the default optimisation level on the Cornell box, default image
    /// parameters, the default chip.
    pub fn new(kernel: impl Into<PathBuf>) -> Request {
        Request {
            kernel: kernel.into(),
            more: Vec::new(),
            opt_level: DEFAULT_OPT_LEVEL,
            scene: "cornell".into(),
            load: LoadOptions::default(),
            render: RenderOptions::default(),
            chip: ChipConfig::preset(DEFAULT_CHIP).expect("the default chip is a preset"),
            scene_cache: None,
        }
    }

    /// The kernel and the files linked with it.
    pub fn files(&self) -> Vec<PathBuf> {
        std::iter::once(self.kernel.clone())
            .chain(self.more.iter().cloned())
            .collect()
    }
}

/// The image options for `render` on `chip`: the chip's local-store size as each thread's
/// stack window, its ray stream memory's shape (scene header `stream_*`), its pipeline
/// modes (`pipe_modes`) and the chip's treelet layout (`[treelets]`: form, size, alignment). Every
/// image that runs on a chip, or that `trax native` runs over, is laid out with these
/// ([`lay_out`], [`scene_image`], [`lay_out_scene`]), so run and native lay out alike.
pub fn image_options(render: &RenderOptions, chip: &ChipConfig) -> Result<RenderOptions, String> {
    let align_bytes = chip.treelet_align_bytes().map_err(|e| e.to_string())?;
    let sm = &chip.stream_memory;
    let stream = if sm.capacity_bytes > 0 {
        StreamShape {
            rays: sm.geometry().capacity_rays(),
            ray_bytes: sm.ray_bytes,
            buffers: sm.buffers,
        }
    } else {
        StreamShape::default()
    };
    Ok(RenderOptions {
        stack_size: chip.local_store.bytes,
        stream,
        pipe_modes: u32::from(chip.pipe_modes()),
        treelets: TreeletLayout {
            always: chip.treelets.form == TreeletForm::Always,
            options: TreeletOptions {
                budget_bytes: chip.treelet_bytes(),
                align_bytes,
            },
        },
        ..render.clone()
    })
}

/// A program ready to run: its executable and initial memory.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Name used in reports (the kernel path).
    pub name: String,
    /// The linked executable (kept for debug information).
    pub elf: Vec<u8>,
    /// The initial memory (program segments, scene header, components, framebuffer).
    pub image: SceneImage,
    /// Warnings from loading the scene (to show the user).
    pub warnings: Vec<String>,
    /// The files the scene was loaded from (and looked for): `Scene::sources`.
    pub scene_sources: Vec<trax_assembler::scene::Source>,
}

/// Why a program could not be prepared; the message names the file or flag at fault.
#[derive(Debug, thiserror::Error)]
pub enum PrepareError {
    /// A file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        source: std::io::Error,
    },
    /// Compile errors, already rendered with source spans.
    #[error("{0}")]
    Compile(CompileError),
    /// clang could not build a C or C++ file (its diagnostics, or why it did not run).
    #[error("{0}")]
    Clang(ClangError),
    /// rustc's check of a TRaX-Rust kernel could not run (see [`crate::native::check`]).
    #[error("{0}")]
    RustcCheck(CheckError),
    /// The linker failed.
    #[error("linking {path}: {source}")]
    Link {
        /// The kernel.
        path: String,
        /// What went wrong.
        source: Box<trax_assembler::link::LinkError>,
    },
    /// The scene could not be loaded.
    #[error("{}", scene_message(scene, source))]
    Scene {
        /// The scene as named.
        scene: String,
        /// What went wrong.
        source: trax_assembler::scene::SceneError,
    },
    /// The memory image could not be laid out.
    #[error("{path}: {source}")]
    Image {
        /// The kernel.
        path: String,
        /// What went wrong.
        source: trax_assembler::image::ImageError,
    },
    /// A parameter out of range (the message names the flag).
    #[error("{0}")]
    Flag(String),
}

impl PrepareError {
    /// Process exit code: 101 for internal compiler errors, 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        match self {
            PrepareError::Compile(e) => e.exit_code(),
            _ => 1,
        }
    }

    /// The whole text to print on stderr, ending in a newline. Compile diagnostics are
    /// already rendered (`error[id]: ...`) and printed as they are; every other error gets
    /// one `error: ` prefix, and an internal compiler error a note asking for a report.
    pub fn render(&self) -> String {
        let mut s = match self {
            PrepareError::Compile(e @ CompileError::Diagnostics(_)) => e.to_string(),
            PrepareError::Clang(e @ ClangError::Diagnostics { .. }) => e.to_string(),
            PrepareError::Compile(e @ CompileError::Internal(_)) => {
                format!("error: {e}\nnote: this is a bug in the trax compiler; please report it")
            }
            e => format!("error: {e}"),
        };
        if !s.ends_with('\n') {
            s.push('\n');
        }
        s
    }
}

/// Builds or reads the kernel, loads the scene and lays out the memory image.
pub fn prepare(req: &Request) -> Result<Prepared, PrepareError> {
    for (flag, v) in [("width", req.render.width), ("height", req.render.height)] {
        if v == 0 {
            return Err(PrepareError::Flag(format!("--{flag} must be at least 1")));
        }
    }
    let elf = executable_of(&req.files(), req.opt_level)?;
    let referenced = Executable::parse("program ELF", &elf)
        .map(|e| e.referenced)
        .unwrap_or_default();
    let scene = request_scene(req, &referenced)?;
    lay_out(
        &req.kernel.display().to_string(),
        elf,
        &scene,
        &req.render,
        &req.chip,
    )
}

/// The linked executable of `kernel`: built from source, or read as it is.
pub fn executable(kernel: &Path, opt_level: u8) -> Result<Vec<u8>, PrepareError> {
    executable_of(&[kernel.to_path_buf()], opt_level)
}

/// The linked executable of `files`: one executable read as it is, or sources and objects
/// built and linked together.
pub fn executable_of(files: &[PathBuf], opt_level: u8) -> Result<Vec<u8>, PrepareError> {
    match files {
        [one] if KernelFile::of(one) == KernelFile::Executable => {
            std::fs::read(one).map_err(|source| PrepareError::Io {
                path: one.display().to_string(),
                source,
            })
        }
        _ => build_executable_of(files, opt_level),
    }
}

/// The rustc check chosen by `TRAX_RUSTC_CHECK` ([`RustcCheck::from_env`]).
fn rustc_check() -> Result<RustcCheck, PrepareError> {
    RustcCheck::from_env().map_err(PrepareError::RustcCheck)
}

/// Compiles a kernel source file to an object (ELF relocatable with DWARF), assembly or
/// LLVM IR: TRaX-Rust with the trax compiler (checked by rustc as `TRAX_RUSTC_CHECK`
/// says, see [`crate::native::check`]), C and C++ with clang-14.
pub fn compile_object(kernel: &Path, opt_level: u8, emit: Emit) -> Result<Vec<u8>, PrepareError> {
    compile_object_checked(kernel, opt_level, emit, rustc_check()?)
}

/// [`compile_object`] with the rustc check given. A TRaX-Rust kernel is checked by rustc
/// while the trax compiler builds it; when rustc rejects it, rustc's errors are the
/// errors (the kernel is not Rust), else the trax compiler's result stands (errors then
/// name what the subset lacks).
pub fn compile_object_checked(
    kernel: &Path,
    opt_level: u8,
    emit: Emit,
    rustc: RustcCheck,
) -> Result<Vec<u8>, PrepareError> {
    if let KernelFile::C(lang) = KernelFile::of(kernel) {
        return clang::compile(kernel, lang, opt_level, emit).map_err(PrepareError::Clang);
    }
    let opts = CompileOptions {
        opt_level,
        emit,
        prelude: Some(Prelude::runtime()),
    };
    let pending = check::start(kernel, rustc).map_err(PrepareError::RustcCheck)?;
    let ours = compile_file(kernel, &opts);
    match pending.finish().map_err(PrepareError::RustcCheck)? {
        Verdict::Rejected(errors) => Err(PrepareError::Compile(CompileError::Diagnostics(errors))),
        Verdict::Accepted | Verdict::Skipped => {
            ours.map(|o| o.bytes).map_err(PrepareError::Compile)
        }
    }
}

/// Compiles and links a kernel source file with the runtime start-up code.
pub fn build_executable(kernel: &Path, opt_level: u8) -> Result<Vec<u8>, PrepareError> {
    build_executable_of(&[kernel.to_path_buf()], opt_level)
}

/// Compiles every source of `files` (objects are taken as they are) and links them, in
/// order, with the runtime start-up code. Memory functions and 64-bit helpers that C or
/// C++ objects call are linked in from the trax C runtime when no input defines them.
/// TRaX-Rust sources are checked by rustc as `TRAX_RUSTC_CHECK` says.
pub fn build_executable_of(files: &[PathBuf], opt_level: u8) -> Result<Vec<u8>, PrepareError> {
    build_executable_checked(files, opt_level, rustc_check()?)
}

/// [`build_executable_of`] with the rustc check given.
pub fn build_executable_checked(
    files: &[PathBuf],
    opt_level: u8,
    rustc: RustcCheck,
) -> Result<Vec<u8>, PrepareError> {
    let name = files
        .iter()
        .map(|f| f.display().to_string())
        .collect::<Vec<_>>()
        .join(" + ");
    let mut inputs = Vec::new();
    for f in files {
        let bytes = match KernelFile::of(f) {
            KernelFile::Rust | KernelFile::C(_) => {
                compile_object_checked(f, opt_level, Emit::Obj, rustc)?
            }
            KernelFile::Object => std::fs::read(f).map_err(|source| PrepareError::Io {
                path: f.display().to_string(),
                source,
            })?,
            KernelFile::Executable => {
                return Err(PrepareError::Flag(format!(
                    "{}: only sources (.rs, .c, .cpp, .cc) and objects (.o) can be linked together; an executable is run alone",
                    f.display()
                )))
            }
        };
        inputs.push(Input {
            name: f.display().to_string(),
            bytes,
        });
    }
    let mut added: Vec<String> = Vec::new();
    loop {
        match link(&inputs, &LinkOptions::default()) {
            Ok(l) => return Ok(l.elf),
            Err(trax_assembler::link::LinkError::UndefinedSymbol { symbol, .. })
                if files
                    .iter()
                    .any(|f| matches!(KernelFile::of(f), KernelFile::C(_)))
                    && clang::runtime_provides(&symbol) =>
            {
                let (rt_name, bytes) = clang::runtime_object_for(&symbol)
                    .expect("checked above")
                    .map_err(PrepareError::Clang)?;
                if added.contains(&rt_name) {
                    // The runtime was linked and did not define it: report as undefined.
                    return Err(PrepareError::Link {
                        path: name,
                        source: Box::new(trax_assembler::link::LinkError::UndefinedSymbol {
                            symbol,
                            file: rt_name,
                            section: String::new(),
                        }),
                    });
                }
                added.push(rt_name.clone());
                inputs.push(Input {
                    name: rt_name,
                    bytes,
                });
            }
            Err(trax_assembler::link::LinkError::UndefinedSymbol { symbol, .. })
                if symbol == "trax_main"
                    && files
                        .iter()
                        .all(|f| matches!(KernelFile::of(f), KernelFile::C(_))) =>
            {
                // C and C++ sources without an entry point: say what to write.
                let cpp = inputs
                    .iter()
                    .any(|i| clang::entry_point(&i.bytes) == clang::EntryPoint::CppLinkage);
                return Err(PrepareError::Flag(clang::no_entry_message(&name, cpp)));
            }
            Err(trax_assembler::link::LinkError::UndefinedSymbol { symbol, file, .. })
                if symbol != "trax_main"
                    && files
                        .iter()
                        .any(|f| matches!(KernelFile::of(f), KernelFile::C(_))) =>
            {
                // A libc call (`malloc`, `printf`, ...) in C code: say there is no libc.
                return Err(PrepareError::Flag(format!(
                    "linking {name}: undefined symbol `{symbol}`, referenced from `{file}`: TRaX kernels have no C library (no heap, no stdio, no system calls); define it in one of the linked files, or use trax.h (`trax_print_*` for printf, `trax_sinf`, `trax_powf`, ... for <math.h>)"
                )));
            }
            Err(source) => {
                return Err(PrepareError::Link {
                    path: name,
                    source: Box::new(source),
                })
            }
        }
    }
}

/// A scene error, prefixed with the scene's name unless the message already names it
/// (most name the file, and the line, themselves).
fn scene_message(scene: &str, e: &trax_assembler::scene::SceneError) -> String {
    let msg = e.to_string();
    if msg.contains(scene) {
        msg
    } else {
        format!("scene `{scene}`: {msg}")
    }
}

/// Loads a scene (see `trax_assembler::scene::load_scene`); errors name the scene.
pub fn load_scene(scene: &str, opts: &LoadOptions) -> Result<Scene, PrepareError> {
    trax_assembler::scene::load_scene(scene, opts).map_err(|source| PrepareError::Scene {
        scene: scene.to_string(),
        source,
    })
}

/// The scene of a request (loaded, or read from its scene cache), refusing one larger
/// than a program that reads the header fields `referenced` can lay out, before it is
/// built (`image::max_triangles`).
pub fn request_scene(req: &Request, referenced: &[String]) -> Result<Scene, PrepareError> {
    let refs: Vec<&str> = referenced.iter().map(String::as_str).collect();
    let opts = image_options(&req.render, &req.chip).map_err(PrepareError::Flag)?;
    let load = LoadOptions {
        max_triangles: Some(trax_assembler::image::max_triangles(&refs, &opts)),
        ..req.load.clone()
    };
    match &req.scene_cache {
        None => load_scene(&req.scene, &load),
        Some(dir) => trax_assembler::scene::cache::load_scene_cached(&req.scene, &load, dir)
            .map(|(scene, _)| scene)
            .map_err(|source| PrepareError::Scene {
                scene: req.scene.clone(),
                source,
            }),
    }
}

/// Lays out the memory image of the executable `elf` (named `name` in messages) with
/// `scene` for `chip` ([`image_options`]): only the components the program references.
pub fn lay_out(
    name: &str,
    elf: Vec<u8>,
    scene: &Scene,
    render: &RenderOptions,
    chip: &ChipConfig,
) -> Result<Prepared, PrepareError> {
    let opts = image_options(render, chip).map_err(PrepareError::Flag)?;
    let image = build_image(&elf, scene, &opts).map_err(|source| PrepareError::Image {
        path: name.to_string(),
        source,
    })?;
    Ok(Prepared {
        name: name.to_string(),
        elf,
        image,
        warnings: scene.warnings.clone(),
        scene_sources: scene.sources.clone(),
    })
}

/// The memory image `trax native` runs over: the scene components the kernel references
/// as `trax run` would lay them out (no program). The kernel is built with the trax
/// compiler at the default level to read its references (not checked by rustc again:
/// `trax native` has built it with rustc); if that fails, every component is laid out
/// and the second value says why.
pub fn scene_image(req: &Request) -> Result<(SceneImage, Vec<String>), PrepareError> {
    let mut warnings = Vec::new();
    let referenced = match build_executable_checked(
        &req.files(),
        DEFAULT_OPT_LEVEL,
        RustcCheck::Off,
    )
    .map_err(|e| e.to_string())
    .and_then(|elf| Executable::parse("program ELF", &elf).map_err(|e| e.to_string()))
    {
        Ok(p) => p.referenced,
        Err(e) => {
            let first = e.lines().next().unwrap_or("").trim();
            warnings.push(format!(
                "{}: the trax compiler cannot build this kernel ({first}); laying out every scene component",
                req.kernel.display()
            ));
            on_demand_components()
                .into_iter()
                .map(String::from)
                .collect()
        }
    };
    let scene = request_scene(req, &referenced)?;
    warnings.splice(0..0, scene.warnings.iter().cloned());
    let referenced: Vec<&str> = referenced.iter().map(String::as_str).collect();
    let image = lay_out_scene(&scene, &referenced, &req.render, &req.chip).map_err(|source| {
        PrepareError::Image {
            path: req.kernel.display().to_string(),
            source,
        }
    })?;
    Ok((image, warnings))
}

/// The memory image of `scene` alone (no program) for `chip` ([`image_options`]), with the
/// optional components in `referenced` (camera and framebuffer always).
pub fn lay_out_scene(
    scene: &Scene,
    referenced: &[&str],
    render: &RenderOptions,
    chip: &ChipConfig,
) -> Result<SceneImage, ImageError> {
    let opts = image_options(render, chip).map_err(ImageError::BadOption)?;
    build_image_from_symbols(
        Vec::new(),
        trax_runtime::abi::TEXT_BASE,
        referenced,
        scene,
        &opts,
    )
}

impl Prepared {
    /// The initial memory as the emulator loads it.
    pub fn segments(&self) -> Vec<Segment> {
        self.image.memory.segments.clone()
    }

    /// A run of this program on `chip` in `mode` (other options at their defaults; set
    /// them on the returned request).
    pub fn run_request<'a>(&'a self, chip: &'a ChipConfig, mode: Mode) -> RunRequest<'a> {
        let mut req = RunRequest::new(&self.name, &self.elf, chip, mode);
        req.segments = Some(self.segments());
        req
    }

    /// The framebuffer after `run` (`width*height` pixels of 3 little-endian f32).
    pub fn framebuffer(&self, run: &RunReport) -> Option<Vec<u8>> {
        let fb = self.image.header.framebuffer;
        run.read_memory(fb.addr, fb.count * PIXEL_BYTES)
    }

    /// The optional scene components the image leaves out: the kernel never references
    /// them (components are linked on demand, see `trax_assembler::image`).
    pub fn left_out(&self) -> Vec<&'static str> {
        left_out(&self.image)
    }
}

/// The optional scene components `image` leaves out.
pub fn left_out(image: &SceneImage) -> Vec<&'static str> {
    on_demand_components()
        .into_iter()
        .filter(|c| image.component(c).is_none())
        .collect()
}

/// The scene-data lines of a run summary: every placed component's bytes, then what was
/// left out.
pub fn scene_report(image: &SceneImage) -> String {
    let mut s = format!(
        "scene data: {} bytes in {} components\n",
        image.scene_bytes(),
        image.components.len()
    );
    for c in &image.components {
        s += &format!(
            "   {:<13} {:>12} bytes {:>10} elements\n",
            c.name, c.bytes, c.count
        );
    }
    let out = left_out(image);
    if out.is_empty() {
        s += "   left out: none (the kernel references every component)\n";
    } else {
        s += &format!(
            "   left out (never referenced by the kernel): {}\n",
            out.join(", ")
        );
    }
    s
}

/// The chip: preset or TOML file `config` with the command-line overrides applied (`l2s`:
/// number of L2s, TMs split evenly among them). Errors name the flag or field.
/// What the run summary calls a chip: the preset's name, `FILE (preset P)` for a file
/// (`NAME (FILE, preset P)` when the file names the chip), then `+ N overrides (PATH=VALUE,
/// ...)` for `--set`, `--tms`, `--threads` and `--l2s`. [`chip_config`] puts it in
/// `ChipConfig::name`.
pub fn chip_label(
    config: &str,
    sets: &[(String, toml::Value)],
    tms: Option<u32>,
    threads: Option<u32>,
    l2s: Option<u32>,
) -> String {
    let named = ChipConfig::load(config).map_or_else(|_| config.to_string(), |c| c.name);
    chip_label_of(config, &named, sets, tms, threads, l2s)
}

/// [`chip_label`] for a config whose loaded name is `named`.
fn chip_label_of(
    config: &str,
    named: &str,
    sets: &[(String, toml::Value)],
    tms: Option<u32>,
    threads: Option<u32>,
    l2s: Option<u32>,
) -> String {
    let base = if ChipConfig::preset(config).is_some() {
        config.to_string()
    } else {
        // A file: its `preset` key, read as the loader reads it.
        let preset = std::fs::read_to_string(config)
            .ok()
            .and_then(|t| toml::from_str::<toml::Table>(&t).ok())
            .and_then(|t| t.get("preset").and_then(|p| p.as_str().map(str::to_string)));
        let default_name = preset.clone().unwrap_or_else(|| ChipConfig::default().name);
        match (preset, named != default_name) {
            (Some(p), false) => format!("{config} (preset {p})"),
            (Some(p), true) => format!("{named} ({config}, preset {p})"),
            (None, false) => config.to_string(),
            (None, true) => format!("{named} ({config})"),
        }
    };
    let mut overrides: Vec<String> = sets
        .iter()
        .map(|(p, v)| match v {
            toml::Value::String(s) => format!("{p}={s}"),
            v => format!("{p}={v}"),
        })
        .collect();
    for (flag, v) in [("tms", tms), ("threads", threads), ("l2s", l2s)] {
        if let Some(v) = v {
            overrides.push(format!("{flag}={v}"));
        }
    }
    match overrides.len() {
        0 => base,
        1 => format!("{base} + 1 override ({})", overrides[0]),
        n => format!("{base} + {n} overrides ({})", overrides.join(", ")),
    }
}

pub fn chip_config(
    config: &str,
    sets: &[(String, toml::Value)],
    tms: Option<u32>,
    threads: Option<u32>,
    l2s: Option<u32>,
) -> Result<ChipConfig, String> {
    let mut chip = ChipConfig::load(config).map_err(|e| e.to_string())?;
    let base = (chip.tms, chip.memory.dram.clone());
    chip.apply_overrides(sets).map_err(|e| e.to_string())?;
    chip.name = chip_label_of(config, &chip.name, sets, tms, threads, l2s);
    for (flag, v) in [("tms", tms), ("threads", threads), ("l2s", l2s)] {
        if v == Some(0) {
            return Err(format!("--{flag} must be at least 1"));
        }
    }
    if let Some(t) = tms {
        chip.tms = t;
    }
    if let Some(t) = threads {
        chip.threads_per_tm = t;
    }
    if let Some(l2s) = l2s {
        if l2s > chip.tms {
            return Err(format!("--l2s {l2s} is more than the {} TMs", chip.tms));
        }
        chip.tms_per_l2 = chip.tms.div_ceil(l2s);
    }
    chip.validate().map_err(|e| e.to_string())?;
    if let Some(slice) = slice_note(&chip, base.0, &base.1) {
        chip.name = format!("{} [{slice}]", chip.name);
    }
    Ok(chip)
}

/// What a chip slice (fewer TMs than its config file) keeps of the memory system, for its
/// label (the summary's `chip:` line and the statistics' `chip.name`): the L2s it has, and
/// whether the DRAM system is the whole chip's (it is unless changed with `--set
/// memory.dram...`): a slice's DRAM energy and bandwidth are then the full system's.
fn slice_note(chip: &ChipConfig, base_tms: u32, base_dram: &DramConfig) -> Option<String> {
    if chip.tms >= base_tms {
        return None;
    }
    let d = &chip.memory.dram;
    let dram = match d.model {
        DramModel::Detailed => format!(
            "{} channel(s), {:.0} GB/s peak",
            d.detailed.channels,
            d.detailed.peak_gbps()
        ),
        DramModel::Simple => format!(
            "simple model, {} B/cycle",
            d.simple.bandwidth_bytes_per_cycle
        ),
    };
    let kept = if d == base_dram {
        "the full DRAM system"
    } else {
        "a DRAM system as set"
    };
    Some(format!(
        "slice of {} of {base_tms} TMs, {} L2(s), {kept}: {dram}",
        chip.tms,
        chip.tms.div_ceil(chip.tms_per_l2)
    ))
}

#[cfg(test)]
mod tests {
    use super::chip_config;
    use toml::Value;

    /// A chip with fewer TMs than its config says so in its label, with the L2s it keeps
    /// and whether its DRAM system is the whole chip's.
    #[test]
    fn a_chip_slice_states_its_dram_system() {
        let name = |sets: &[(&str, Value)], tms: Option<u32>| {
            let sets: Vec<(String, Value)> = sets
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect();
            chip_config("strata-plus", &sets, tms, None, None)
                .unwrap()
                .name
        };
        assert_eq!(
            name(&[], Some(32)),
            "strata-plus + 1 override (tms=32) [slice of 32 of 128 TMs, 1 L2(s), \
             the full DRAM system: 8 channel(s), 512 GB/s peak]"
        );
        let set = name(
            &[
                ("tms", Value::Integer(64)),
                ("memory.dram.detailed.channels", Value::Integer(4)),
            ],
            None,
        );
        assert!(
            set.ends_with("[slice of 64 of 128 TMs, 2 L2(s), a DRAM system as set: 4 channel(s), 256 GB/s peak]"),
            "{set}"
        );
        assert_eq!(name(&[], None), "strata-plus");
        assert!(!name(&[], Some(128)).contains("slice"));
    }
}
