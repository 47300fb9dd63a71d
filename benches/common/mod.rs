//! Helpers shared by the timing benches (`timing_pathtracer`, `timing_strata`).

/// `name` from the environment as a number, or `default` when unset.
pub fn env_u64(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(v) => v
            .parse()
            .unwrap_or_else(|_| panic!("{name}={v:?} is not a number")),
        Err(_) => default,
    }
}

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
