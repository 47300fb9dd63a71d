//! The statistics counters a kernel bumps with `trax::stat::add` (`trax.statadd`,
//! `trax.stat`): how many there are and the one text line that reports them, shared by
//! `trax run` and the host runner of `trax native` (which includes this file).

/// Number of statistics counters (`0..NUM_STATS`); counter 0 counts rays.
pub const NUM_STATS: usize = 32;

/// The report line of the counters a kernel set (`counters: [1] 120, [5] 7`): the
/// non-zero counters other than counter 0, which the runs report as rays on their own;
/// `None` when there are none.
pub fn summary(counters: &[u64]) -> Option<String> {
    let set: Vec<String> = counters
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, &n)| n != 0)
        .map(|(i, n)| format!("[{i}] {n}"))
        .collect();
    (!set.is_empty()).then(|| format!("counters: {}", set.join(", ")))
}

#[cfg(test)]
mod tests {
    #[test]
    fn summary_lists_the_set_counters_but_rays() {
        assert_eq!(super::summary(&[5, 0, 0]), None);
        assert_eq!(
            super::summary(&[5, 120, 0, 7]).as_deref(),
            Some("counters: [1] 120, [3] 7")
        );
    }
}
