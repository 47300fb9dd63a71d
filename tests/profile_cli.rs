//! End-to-end tests of `trax run --profile` (functional and timing), the folded output,
//! `trax annotate` and `--gdb` address checks.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("profile-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn trax(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trax"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run trax")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The `# N unit in total` header of a printed tree.
fn tree_total(stdout: &str, unit: &str) -> u64 {
    let head = stdout
        .lines()
        .find(|l| l.starts_with("# ") && l.contains(&format!(" {unit} in total")))
        .unwrap_or_else(|| panic!("no tree header in\n{stdout}"));
    head[2..].split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn functional_profile_tree_names_kernel_and_prelude() {
    let out = trax(&[
        "run",
        "examples/pathtracer.rs",
        "--functional",
        "--profile",
        "--width",
        "16",
        "--height",
        "16",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(tree_total(&stdout, "instructions") > 0);
    // The root line (right after the header) is the whole run: 100%.
    let root_line = stdout
        .lines()
        .skip_while(|l| !l.starts_with("# "))
        .nth(1)
        .unwrap();
    assert!(root_line.contains(" 100.00 "), "root: {root_line}");
    assert!(stdout.contains("trax_main "), "no trax_main in\n{stdout}");
    // Prelude functions (e.g. `Vec3::dot`, `trax::...`) appear as `Type::method`.
    let prelude = ["Vec3::", "Ray::", "trax::", "Bvh", "Triangle::"];
    assert!(
        stdout
            .lines()
            .any(|l| l.starts_with("| ") && prelude.iter().any(|p| l.contains(p))),
        "no prelude function in\n{stdout}"
    );
}

#[test]
fn folded_profile_counts_sum_to_instructions() {
    let dir = scratch("folded");
    let folded = dir.join("p.folded");
    let stats = dir.join("stats.json");
    let out = trax(&[
        "run",
        "examples/gradient.rs",
        "--functional",
        "--width",
        "8",
        "--height",
        "8",
        "--profile",
        "--profile-format",
        "folded",
        "--profile-out",
        folded.to_str().unwrap(),
        "--stats-json",
        stats.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let body = std::fs::read_to_string(&folded).unwrap();
    let mut sum = 0u64;
    let mut saw_main = false;
    for line in body.lines() {
        let (stack, n) = line.rsplit_once(' ').expect("`stack count` line");
        assert!(!stack.is_empty(), "{line}");
        saw_main |= stack.split(';').any(|f| f == "trax_main");
        sum += n.parse::<u64>().expect("count");
    }
    assert!(saw_main, "no trax_main frame in\n{body}");
    let n = json(&stats)["instructions"].as_u64().unwrap();
    assert_eq!(sum, n);
}

#[test]
fn timing_profile_total_is_the_live_thread_cycles() {
    let dir = scratch("timing");
    let stats = dir.join("stats.json");
    let out = trax(&[
        "run",
        "examples/gradient.rs",
        "--config",
        "tiny",
        "--width",
        "8",
        "--height",
        "8",
        "--profile",
        "--stats-json",
        stats.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let total = tree_total(&stdout, "thread-cycles");
    assert!(
        stdout.contains("thread-cycles in total (cycles summed over the hardware threads)"),
        "{stdout}"
    );
    let st = json(&stats);
    let tc = st["timing"]["thread_cycles"].as_object().unwrap();
    // Every thread-cycle is charged except those of threads that already halted.
    let live: u64 = tc
        .iter()
        .filter(|(k, _)| k.as_str() != "halted")
        .map(|(_, v)| v.as_u64().unwrap())
        .sum();
    assert_eq!(total, live, "{stdout}");
    let root_line = stdout
        .lines()
        .skip_while(|l| !l.starts_with("# "))
        .nth(1)
        .unwrap();
    let issued = st["instructions"].as_u64().unwrap();
    assert!(
        root_line.contains(&format!("issue {issued}")),
        "root {root_line} vs {issued} issued"
    );
    assert!(
        root_line.contains("stall"),
        "no stall breakdown: {root_line}"
    );
}

/// Every cost is on a labelled row: no bare `0 |` row for code without a source line
/// (once printed as an empty "line 0"), and the rows add up to the whole run.
#[test]
fn annotate_labels_costs_without_a_source_line() {
    let dir = scratch("annotate-line0");
    let stats = dir.join("stats.json");
    let out = trax(&[
        "annotate",
        "examples/pathtracer.rs",
        "--functional",
        "--width",
        "8",
        "--height",
        "8",
        "--stats-json",
        stats.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let mut sum = 0u64;
    let mut labelled = 0;
    for l in stdout.lines().filter(|l| l.contains(" | ")) {
        let (head, src) = l.split_once(" | ").unwrap();
        let cols: Vec<&str> = head.split_whitespace().collect();
        assert_eq!(cols.len(), 3, "row: {l}");
        assert_ne!(cols[2], "0", "bare line-0 row: {l}");
        if cols[2] == "-" {
            assert!(src.starts_with('(') && src.ends_with(')'), "{l}");
            labelled += 1;
        }
        sum += cols[0].parse::<u64>().unwrap();
    }
    assert!(
        labelled > 0,
        "the path tracer has code without a line:\n{stdout}"
    );
    assert_eq!(sum, json(&stats)["instructions"].as_u64().unwrap());
    assert!(!stdout.contains("??"), "{stdout}");
}

#[test]
fn annotate_prints_kernel_lines_with_costs() {
    let out = trax(&[
        "annotate",
        "examples/gradient.rs",
        "--functional",
        "--width",
        "8",
        "--height",
        "8",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let line = stdout
        .lines()
        .find(|l| l.contains(" | ") && l.ends_with("let g = (y as f32 + 0.5) * inv_h;"))
        .unwrap_or_else(|| panic!("kernel line missing in\n{stdout}"));
    let cost: u64 = line.split_whitespace().next().unwrap().parse().unwrap();
    // One evaluation per pixel at least.
    assert!(cost >= 64, "{line}");
}

#[test]
fn gdb_refuses_remote_addresses_and_timing_mode() {
    let out = trax(&[
        "run",
        "examples/hello.rs",
        "--functional",
        "--gdb",
        "0.0.0.0:0",
    ]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("not a loopback"),
        "{}",
        text(&out.stderr)
    );
    let out = trax(&["run", "examples/hello.rs", "--gdb", "127.0.0.1:0"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("--functional"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn gdb_session_continues_the_run_to_its_end() {
    use std::io::{BufRead, BufReader, Read};
    use std::process::Stdio;
    let dir = scratch("gdb");
    let elf = dir.join("hello.elf");
    let out = trax(&["build", "examples/hello.rs", "-o", elf.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mut child = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args([
            "run",
            elf.to_str().unwrap(),
            "--functional",
            "--tms",
            "1",
            "--threads",
            "2",
        ])
        .args(["--gdb", "127.0.0.1:0"])
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn trax");
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    let addr = line
        .trim()
        .strip_prefix("waiting for gdb on ")
        .unwrap_or_else(|| panic!("unexpected first line {line:?}"))
        .to_string();
    let g = Command::new("gdb-multiarch")
        .arg("-batch")
        .arg("-nx")
        .arg(&elf)
        .args(["-ex", &format!("target remote {addr}"), "-ex", "continue"])
        .output()
        .expect("run gdb-multiarch");
    let gdb_out = text(&g.stdout) + &text(&g.stderr);
    let status = child.wait().unwrap();
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    let mut stdout = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut stdout)
        .unwrap();
    assert!(status.success(), "trax: {rest}\ngdb: {gdb_out}");
    assert!(gdb_out.contains("exited normally"), "{gdb_out}");
    assert!(stdout.contains("hello from thread 1 of 2"), "{stdout}");
}
