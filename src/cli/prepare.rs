//! From what the user names on the command line (a kernel source or a linked ELF, a scene,
//! image parameters) to the machine's initial memory: compile, link, load the scene, lay out.

use std::path::Path;

use trax_assembler::image::{build_image, SceneImage};
use trax_assembler::link::{link, Input, LinkOptions};
use trax_assembler::scene::load_scene;
use trax_compiler::{compile_file, CompileError, CompileOptions, Emit, Prelude};

use super::common::RenderArgs;

/// A program ready to run: its executable and initial memory.
pub struct Prepared {
    /// Name used in reports (the kernel path).
    pub name: String,
    /// The linked executable (kept for debug information).
    pub elf: Vec<u8>,
    /// The initial memory (program segments, scene header, components, framebuffer).
    pub image: SceneImage,
}

/// Why a program could not be prepared; the message names the file or flag at fault.
#[derive(Debug, thiserror::Error)]
pub enum PrepareError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    /// Compile errors, already rendered with source spans.
    #[error("{0}")]
    Compile(CompileError),
    #[error("linking {path}: {source}")]
    Link {
        path: String,
        source: Box<trax_assembler::link::LinkError>,
    },
    #[error("{}", scene_message(scene, source))]
    Scene {
        scene: String,
        source: trax_assembler::scene::SceneError,
    },
    #[error("{path}: {source}")]
    Image {
        path: String,
        source: trax_assembler::image::ImageError,
    },
    #[error("{0}")]
    Flag(String),
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

/// Builds `kernel` if it is Rust source (`.rs`), else reads it as a linked executable, then
/// lays out memory for it with the scene and parameters of `render`.
pub fn prepare(
    kernel: &Path,
    opt_level: u8,
    render: &RenderArgs,
) -> Result<Prepared, PrepareError> {
    render.validate().map_err(PrepareError::Flag)?;
    let name = kernel.display().to_string();
    let elf = if kernel.extension().is_some_and(|e| e == "rs") {
        build_executable(kernel, opt_level)?
    } else {
        std::fs::read(kernel).map_err(|source| PrepareError::Io {
            path: name.clone(),
            source,
        })?
    };
    let scene = load_scene(&render.scene, &render.load_options()).map_err(|source| {
        PrepareError::Scene {
            scene: render.scene.clone(),
            source,
        }
    })?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let image = build_image(&elf, &scene, &render.render_options()).map_err(|source| {
        PrepareError::Image {
            path: name.clone(),
            source,
        }
    })?;
    Ok(Prepared { name, elf, image })
}

/// Compiles and links a kernel source file with the runtime start-up code.
pub fn build_executable(kernel: &Path, opt_level: u8) -> Result<Vec<u8>, PrepareError> {
    let opts = CompileOptions {
        opt_level,
        emit: Emit::Obj,
        prelude: Some(Prelude::runtime()),
    };
    let obj = compile_file(kernel, &opts).map_err(PrepareError::Compile)?;
    let name = kernel.display().to_string();
    let input = Input {
        name: name.clone(),
        bytes: obj.bytes,
    };
    link(&[input], &LinkOptions::default())
        .map(|l| l.elf)
        .map_err(|source| PrepareError::Link {
            path: name,
            source: Box::new(source),
        })
}
