//! `trax scene`: inspect scenes (triangles, materials, bounds, BVH, treelets, memory bytes).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, Subcommand};
use trax::pipeline::{chip_config, image_options, lay_out_scene};
use trax_assembler::bvh::{Bvh, BvhOptions};
use trax_assembler::image::{on_demand_components, RenderOptions};
use trax_assembler::scene::{load_scene, LoadOptions};
use trax_emulator::timing::DEFAULT_CHIP;
use trax_runtime::abi::BvhNode;

/// Arguments of `trax scene`.
#[derive(Args, Debug)]
#[command(after_long_help = SPEC_HELP)]
pub struct SceneArgs {
    #[command(subcommand)]
    command: SceneCommand,
}

/// The scene spec syntax, printed after `trax scene --help`.
const SPEC_HELP: &str = "\
Scene specs (wherever a scene is taken: trax run/annotate/native/scene, sweep files):
  cornell               the Cornell box (embedded), 32 triangles
  procedural:N          spheres in a room, about N triangles
  icosphere:N           a closed sphere mesh, 20·4^N triangles (N <= 10)
  hairball:N[:SEED]     a dense ball of thin random tubes (thesis Hairball stand-in),
                        exactly N triangles; SEED defaults to 1
  vegetation:N[:SEED]   a wide field of instanced leaves on a ground quad (thesis
                        Vegetation stand-in), exactly N triangles; SEED defaults to 1
  box:SCENE             SCENE enclosed in a closed box holding its camera and lights
                        (+12 triangles; thesis Dragon Box / Buddha Box)
  subdivide:N:SCENE     every triangle of SCENE split in four at its edge midpoints,
                        N times: exactly 4^N times the triangles, same surface
  PATH.obj | PATH.objl  a file; .view/.light beside it give the camera and light
Wrappers nest (at most 8): box:subdivide:2:../shared/scenes/dragon/dragon-100k.obj";

#[derive(Subcommand, Debug)]
enum SceneCommand {
    /// Print triangles, materials, bounds, BVH figures, treelets and bytes per component.
    Info(InfoArgs),
}

#[derive(Args, Debug)]
struct InfoArgs {
    /// Scene spec: `cornell`, `procedural:N`, `icosphere:N`, `hairball:N[:SEED]`,
    /// `vegetation:N[:SEED]`, `box:SCENE`, `subdivide:N:SCENE`, or an .obj/.objl file
    /// (details: `trax scene --help`).
    scene: String,
    /// Scale the whole scene by this factor (vertices, camera eye, point lights), after the
    /// .view/.light files are applied; see `trax run --help`.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    scene_scale: Option<f64>,
    /// Camera file (simtrax .view); default: one beside the scene file.
    #[arg(long)]
    view: Option<PathBuf>,
    /// Light file (simtrax .light); default: one beside the scene file.
    #[arg(long)]
    light: Option<PathBuf>,
    /// Largest BVH leaf (triangles).
    #[arg(long, default_value_t = BvhOptions::default().max_leaf)]
    max_leaf: u32,
    /// SAH bins per axis.
    #[arg(long, default_value_t = BvhOptions::default().bins)]
    bins: u32,
    /// The chip whose `[treelets]` table lays out the BVH (size, alignment; the memory
    /// section shows a kernel that reads every component): a preset or a TOML file.
    #[arg(long, default_value = DEFAULT_CHIP)]
    config: String,
    /// Set a chip config field, as `trax run --set` does (`--set treelets.align=dram-row`).
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = super::run::parse_set)]
    set: Vec<(String, toml::Value)>,
    /// Treelet size in bytes: sets the chip's `treelets.bytes` (0 = its L1's capacity).
    #[arg(long, value_name = "BYTES")]
    treelet_bytes: Option<u32>,
    /// Treelet alignment: sets the chip's `treelets.align` (`none`, `dram-row` or bytes).
    #[arg(long, value_name = "none|dram-row|BYTES")]
    treelet_align: Option<String>,
    /// Image width (for the framebuffer size).
    #[arg(long, default_value_t = RenderOptions::default().width)]
    width: u32,
    /// Image height (for the framebuffer size).
    #[arg(long, default_value_t = RenderOptions::default().height)]
    height: u32,
}

/// Runs `trax scene`.
pub fn run(args: SceneArgs) -> ExitCode {
    match args.command {
        SceneCommand::Info(a) => match info(&a) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                let _ = writeln!(std::io::stderr(), "error: {e}");
                ExitCode::FAILURE
            }
        },
    }
}

fn info(a: &InfoArgs) -> Result<(), Box<dyn std::error::Error>> {
    // Output is gathered and written at the end, so a closed pipe (`| head`) is not an error.
    let out = info_text(a)?;
    match std::io::stdout().lock().write_all(out.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// The text `trax scene info` prints.
fn info_text(a: &InfoArgs) -> Result<String, Box<dyn std::error::Error>> {
    let mut out = String::new();
    macro_rules! outln {
        ($($t:tt)*) => {{
            let _ = writeln!(out, $($t)*);
        }};
    }
    let t0 = Instant::now();
    let scene = load_scene(
        &a.scene,
        &LoadOptions {
            view: a.view.clone(),
            light: a.light.clone(),
            scale: a.scene_scale,
            max_triangles: None,
        },
    )?;
    let load_time = t0.elapsed();
    for w in &scene.warnings {
        let _ = writeln!(std::io::stderr(), "warning: {w}");
    }
    let mut sets = a.set.clone();
    if let Some(b) = a.treelet_bytes {
        sets.push(("treelets.bytes".into(), toml::Value::Integer(b.into())));
    }
    if let Some(v) = &a.treelet_align {
        let value = match v.parse::<u32>() {
            Ok(b) => toml::Value::Integer(b.into()),
            Err(_) => toml::Value::String(v.clone()),
        };
        sets.push(("treelets.align".into(), value));
    }
    let chip = chip_config(&a.config, &sets, None, None, None)?;
    let opts = image_options(
        &RenderOptions {
            width: a.width,
            height: a.height,
            bvh: BvhOptions {
                max_leaf: a.max_leaf,
                bins: a.bins,
                ..BvhOptions::default()
            },
            ..RenderOptions::default()
        },
        &chip,
    )?;
    // The BVH as a kernel that reads `treelet_ids` gets it.
    let bvh_opts = BvhOptions {
        treelets: Some(opts.treelets.options.clone()),
        ..opts.bvh.clone()
    };
    let t1 = Instant::now();
    let bvh = Bvh::build(&scene.triangles, &bvh_opts)?;
    let build_time = t1.elapsed();
    let stats = bvh.stats();
    let b = scene.bounds();
    outln!("scene        {}", scene.name);
    outln!("triangles    {}", scene.len());
    outln!("materials    {}", scene.materials.len());
    outln!("emitters     {}", scene.emitters().len());
    outln!("point lights {}", scene.point_lights.len());
    let [x0, y0, z0] = b.min.map(show);
    let [x1, y1, z1] = b.max.map(show);
    outln!("bounds       [{x0} {y0} {z0}] .. [{x1} {y1} {z1}]");
    // Treelet layouts pad node and triangle arrays to their alignment: say so.
    let padding = match stats.nodes - stats.tree_nodes {
        0 => String::new(),
        pad => format!(
            " ({} slots in memory with {pad} treelet padding)",
            stats.nodes
        ),
    };
    outln!(
        "bvh          {} nodes{padding}, {} leaves, depth {}, largest leaf {}, SAH cost {:.3}",
        stats.tree_nodes,
        stats.leaves,
        stats.depth,
        stats.max_leaf,
        stats.sah_cost
    );
    match &bvh.treelets {
        Some(t) => {
            let fill: f64 = t
                .node_ranges
                .iter()
                .map(|r| (r.end - r.start) as f64 * size_of::<BvhNode>() as f64)
                .sum::<f64>()
                / (t.node_ranges.len() as f64 * t.options.budget_bytes as f64);
            outln!(
                "treelets     {} node treelets ({:.0}% full on average), {} triangle treelets, budget {} bytes, align {}, formed {} (chip {})",
                t.node_ranges.len(),
                100.0 * fill,
                t.tri_ranges.len(),
                t.options.budget_bytes,
                t.options.align_bytes,
                if opts.treelets.always { "always" } else { "when read" },
                chip.name
            );
        }
        None => outln!("treelets     none"),
    }
    let t2 = Instant::now();
    let image = lay_out_scene(&scene, &on_demand_components(), &opts, &chip)?;
    let image_time = t2.elapsed();
    outln!("memory (all components referenced):");
    // Per-node and per-triangle components hold a slot per node or triangle slot of the
    // treelet layout, padding included.
    let slots = |name: &str| {
        image
            .components
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.count)
    };
    let node_pad = slots("bvh_nodes").map_or(0, |n| n.saturating_sub(stats.tree_nodes as u32));
    let tri_slots = slots("triangles");
    let tri_pad = tri_slots.map_or(0, |n| n.saturating_sub(scene.len() as u32));
    for c in &image.components {
        let pad = if node_pad > 0 && c.count == stats.nodes as u32 {
            node_pad
        } else if tri_pad > 0 && Some(c.count) == tri_slots {
            tri_pad
        } else {
            0
        };
        let pad = match pad {
            0 => String::new(),
            p => format!("  ({p} of them treelet padding)"),
        };
        outln!(
            "  {:<13} {:>12} bytes  {:>10} elements  at {:#010x}{pad}",
            c.name,
            c.bytes,
            c.count,
            c.addr
        );
    }
    outln!("  {:<13} {:>12} bytes", "total", image.scene_bytes());
    outln!(
        "time         load {:.3} s, BVH build {:.3} s ({:.2} M triangles/s), image {:.3} s",
        load_time.as_secs_f64(),
        build_time.as_secs_f64(),
        scene.len() as f64 / build_time.as_secs_f64().max(1e-9) / 1e6,
        image_time.as_secs_f64()
    );
    Ok(out)
}

/// A coordinate as written by a person: plain for moderate magnitudes, else `1.5e20`.
fn show(x: f32) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(scene: &str) -> InfoArgs {
        InfoArgs {
            scene: scene.into(),
            scene_scale: None,
            view: None,
            light: None,
            max_leaf: 4,
            bins: 256,
            config: DEFAULT_CHIP.into(),
            set: Vec::new(),
            treelet_bytes: Some(4096),
            treelet_align: Some("2048".into()),
            width: 16,
            height: 16,
        }
    }

    #[test]
    fn info_on_builtin_scenes() {
        info(&args("cornell")).unwrap();
        info(&args("procedural:2000")).unwrap();
    }

    /// Node and triangle counts say how much of them is treelet padding.
    #[test]
    fn info_names_treelet_padding() {
        let text = info_text(&args("procedural:2000")).unwrap();
        let bvh = text.lines().find(|l| l.starts_with("bvh ")).unwrap();
        let num = |s: &str| s.parse::<u32>().unwrap();
        let w: Vec<&str> = bvh.split_whitespace().collect();
        // bvh N nodes (M slots in memory with P treelet padding), ...
        assert_eq!((w[2], w[4], w[7]), ("nodes", "slots", "with"), "{bvh}");
        let (nodes, slots, pad) = (num(w[1]), num(&w[3][1..]), num(w[8]));
        assert!(pad > 0 && slots == nodes + pad, "{bvh}");
        let row = text.lines().find(|l| l.starts_with("  bvh_nodes")).unwrap();
        assert!(
            row.contains(&format!(" {slots} elements"))
                && row.ends_with(&format!("({pad} of them treelet padding)")),
            "{row}"
        );
        let tris = text.lines().find(|l| l.starts_with("triangles ")).unwrap();
        let tris = num(tris.split_whitespace().nth(1).unwrap());
        let row = text
            .lines()
            .find(|l| l.starts_with("  triangles "))
            .unwrap();
        let tri_slots = num(row.split_whitespace().nth(3).unwrap());
        assert!(tri_slots > tris, "{row}");
        assert!(row.ends_with(&format!("({} of them treelet padding)", tri_slots - tris)));
        // Without alignment no treelet is padded, and nothing is said.
        let plain = InfoArgs {
            treelet_align: Some("none".into()),
            ..args("procedural:2000")
        };
        let text = info_text(&plain).unwrap();
        assert!(!text.contains("padding"), "{text}");
    }

    #[test]
    fn info_reports_bad_input() {
        let e = info(&args("no-such-scene.obj")).unwrap_err();
        assert!(e.to_string().contains("no-such-scene.obj"), "{e}");
        let e = info(&args("procedural:1")).unwrap_err();
        assert!(e.to_string().contains("procedural"), "{e}");
        let bad = InfoArgs {
            treelet_align: Some("100".into()),
            ..args("cornell")
        };
        let e = info(&bad).unwrap_err().to_string();
        assert!(e.contains("treelets.align = 100"), "{e}");
        let bad = InfoArgs {
            treelet_align: Some("rows".into()),
            ..args("cornell")
        };
        let e = info(&bad).unwrap_err().to_string();
        assert!(
            e.contains("treelets.align") && e.contains("dram-row"),
            "{e}"
        );
        // The tiny chip's DRAM is the simple model: it has no rows to align to.
        let bad = InfoArgs {
            treelet_align: Some("dram-row".into()),
            ..args("cornell")
        };
        let e = info(&bad).unwrap_err().to_string();
        assert!(e.contains("needs the detailed DRAM"), "{e}");
    }
}
