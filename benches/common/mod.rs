//! Helpers shared by the root package's benches (`timing_pathtracer`, `timing_strata`,
//! `functional_pathtracer`).

use std::path::Path;
use std::time::Instant;

use trax::pipeline::{prepare, Prepared, Request};
use trax_emulator::timing::{ChipConfig, TimingStats};
use trax_emulator::{run, Limits, Mode};

#[allow(dead_code)] // not every bench uses it
/// One measured timing run of `prepared` (`name` in the failure message) on `host_threads`
/// host threads, capped at `max_cycles`: its statistics, host wall seconds and CPU seconds
/// (if known). Panics, after printing the summary, if the run did not finish.
pub fn simulate(
    name: &str,
    prepared: &Prepared,
    chip: &ChipConfig,
    host_threads: usize,
    max_cycles: u64,
    stats_interval: Option<u64>,
) -> (TimingStats, f64, Option<f64>) {
    let mut req = prepared.run_request(chip, Mode::Timing);
    req.host_threads = Some(host_threads);
    req.stats_interval = stats_interval;
    // The intervals are computed and dropped (their cost is what is measured).
    let mut drop_it = |_: &trax_emulator::timing::Interval| {};
    if stats_interval.is_some() {
        req.interval_sink = Some(&mut drop_it);
    }
    req.limits = Limits {
        max_cycles: Some(max_cycles),
        ..Limits::default()
    };
    let cpu0 = process_cpu_seconds();
    let t = Instant::now();
    let r = run(req, &mut std::io::sink()).expect("timing run starts");
    let secs = t.elapsed().as_secs_f64();
    let cpu = cpu0.zip(process_cpu_seconds()).map(|(a, b)| b - a);
    let stats = r.timing.clone().expect("timing statistics");
    if !r.finished() {
        println!("{}", stats.summary());
        panic!("{name} did not finish: {:?}", r.failure);
    }
    (stats, secs, cpu)
}

/// `examples/{kernel}.rs` on `scene` (`None`: the default, the Cornell box), `size` x
/// `size`, 1 sample, depth 4, for `chip`: built and laid out as `trax run` does.
#[allow(dead_code)] // not every bench uses it
pub fn prepare_example(
    kernel: &str,
    scene: Option<&str>,
    size: u32,
    chip: &ChipConfig,
) -> Prepared {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut request = Request::new(root.join(format!("examples/{kernel}.rs")));
    if let Some(s) = scene {
        request.scene = s.into();
    }
    request.render.width = size;
    request.render.height = size;
    request.render.spp = 1;
    request.render.max_depth = 4;
    request.chip = chip.clone();
    prepare(&request).unwrap_or_else(|e| panic!("{kernel}: {e}"))
}

/// `name` from the environment as a number, or `default` when unset.
pub fn env_u64(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(v) => v
            .parse()
            .unwrap_or_else(|_| panic!("{name}={v:?} is not a number")),
        Err(_) => default,
    }
}

#[allow(dead_code)] // not every bench uses it
/// CPU seconds this process has used so far (all its threads, live or finished), from
/// `/proc/self/stat` (Linux; `None` elsewhere). Fields 14 and 15 count user and system
/// time in USER_HZ ticks, which Linux fixes at 100 per second for user space.
pub fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is parenthesised and may hold spaces: split after it.
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // `rest` starts at field 3, so field n is fields[n - 3].
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// `cargo bench` passes `--bench` and perhaps a filter: false when a filter is given that
/// does not match `name` (the bench is then skipped).
pub fn selected(name: &str) -> bool {
    std::env::args()
        .skip(1)
        .find(|a| !a.starts_with('-'))
        .is_none_or(|filter| name.contains(&filter))
}
