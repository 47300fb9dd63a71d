//! The per-thread deterministic random-number generator behind `trax.rand` and
//! `trax.seed`.
//!
//! PCG32 (XSH-RR output, 64-bit LCG state). Each hardware thread owns one generator. At
//! start-up it holds the thread's own stream ([`Rng::new`]: the stream selector is the
//! thread's global id, the initial state comes from `SceneHeader::seed`). `trax.seed`
//! replaces it with the stream of one (pixel, sample) pair ([`Rng::for_sample`]), which
//! depends on nothing else but the run's seed — so a kernel that seeds before each sample
//! draws the same numbers for that sample whichever thread, TM or chip renders it, and in
//! `trax native`. A draw returns the top 24 bits of the next 32-bit output scaled by 2^-24:
//! an exactly representable f32 in `[0, 1)`.
//!
//! Mixing of `(seed, pixel, sample)`: the 64-bit key `pixel << 32 | sample` is XORed with a
//! hash of the seed and put through the SplitMix64 finaliser (Stafford's "Mix13"), a
//! bijection of 64-bit words with full avalanche (every input bit flips every output bit
//! with probability close to 1/2). That gives PCG's initial state; a second finaliser pass
//! with another constant gives the stream selector. So for one seed, distinct (pixel,
//! sample) pairs always get distinct initial states, and neighbouring pixels or samples —
//! keys one bit apart — get unrelated states and streams (PCG streams are only known to
//! correlate when their states are related, which the hash rules out). The tests below check
//! mean, variance, neighbour correlation and pair uniformity of the first draws.
//!
//! This file is shared verbatim by the emulator (through `trax_runtime::rng`) and the
//! host implementation of the kernel prelude (`prelude/hw_host.rs` includes it with
//! `#[path]`), so both produce bit-identical sequences. It must stay free of
//! dependencies and of crate-relative paths.

/// LCG multiplier of PCG32.
const PCG_MULT: u64 = 6364136223846793005;

/// Salt of the seed hash (PCG's demo constant, also used by [`Rng::new`]).
const SEED_SALT: u64 = 0x853C_49E6_748F_EA9B;
/// Salt that makes the stream selector's hash differ from the state's.
const STREAM_SALT: u64 = 0xDA3E_39CB_94B9_5BDB;

/// The SplitMix64 finaliser (Stafford's Mix13): a bijection of `u64` with full avalanche.
pub const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// One thread's random generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rng {
    state: u64,
    inc: u64,
    /// The run's seed, kept for [`Rng::reseed`].
    seed: u32,
}

impl Rng {
    /// The stream of thread `global_id` for scene seed `seed` (the generator at start-up).
    pub fn new(seed: u32, global_id: u32) -> Rng {
        // Spread the 32-bit seed over the 64-bit state.
        Rng::pcg_srandom((seed as u64) ^ SEED_SALT, global_id as u64, seed)
    }

    /// The stream of sample `sample` of pixel `pixel` for scene seed `seed`: what
    /// `trax.seed` installs. Independent of the thread and the chip.
    pub fn for_sample(seed: u32, pixel: u32, sample: u32) -> Rng {
        let key = ((pixel as u64) << 32 | sample as u64) ^ mix64(seed as u64 ^ SEED_SALT);
        let initstate = mix64(key);
        let initseq = mix64(key ^ STREAM_SALT);
        Rng::pcg_srandom(initstate, initseq, seed)
    }

    /// `trax.seed`: replaces this generator with [`Rng::for_sample`] of its run's seed.
    pub fn reseed(&mut self, pixel: u32, sample: u32) {
        *self = Rng::for_sample(self.seed, pixel, sample);
    }

    /// PCG32's reference seeding (`pcg32_srandom_r(initstate, initseq)`).
    fn pcg_srandom(initstate: u64, initseq: u64, seed: u32) -> Rng {
        let mut r = Rng {
            state: 0,
            inc: (initseq << 1) | 1,
            seed,
        };
        r.step();
        r.state = r.state.wrapping_add(initstate);
        r.step();
        r
    }

    fn step(&mut self) {
        self.state = self.state.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
    }

    /// Next 32-bit output.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.step();
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Next f32 in `[0, 1)`: the top 24 bits of [`Rng::next_u32`] times 2^-24 (exact).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_in_unit_interval_and_well_spread() {
        let mut r = Rng::new(1, 0);
        let mut sum = 0.0f64;
        let mut buckets = [0u32; 10];
        let n = 100_000;
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x), "{x}");
            sum += x as f64;
            buckets[(x * 10.0) as usize] += 1;
        }
        let mean = sum / n as f64;
        assert!((mean - 0.5).abs() < 0.01, "mean {mean}");
        for b in buckets {
            assert!((9_000..11_000).contains(&b), "bucket {b}");
        }
    }

    #[test]
    fn deterministic() {
        let a: Vec<u32> = {
            let mut r = Rng::new(42, 7);
            (0..16).map(|_| r.next_u32()).collect()
        };
        let b: Vec<u32> = {
            let mut r = Rng::new(42, 7);
            (0..16).map(|_| r.next_u32()).collect()
        };
        assert_eq!(a, b);
    }

    #[test]
    fn matches_pcg32_reference_vector() {
        // Output of the PCG reference implementation's demo, pcg32_srandom(42, 54).
        let mut r = Rng::pcg_srandom(42, 54, 0);
        let got: Vec<u32> = (0..6).map(|_| r.next_u32()).collect();
        assert_eq!(
            got,
            [0xa15c02b7, 0x7b47f409, 0xba1d3330, 0x83d2f293, 0xbfa4784b, 0xcbed606e]
        );
    }

    #[test]
    fn pinned_first_values() {
        // Pin the algorithm: the emulator and the host runner must agree forever.
        let mut r = Rng::new(0, 0);
        let first: Vec<u32> = (0..3).map(|_| r.next_u32()).collect();
        let mut r2 = Rng::new(0, 0);
        assert_eq!(r2.next_f32(), (first[0] >> 8) as f32 / 16_777_216.0);
        assert_eq!(first, PINNED);
    }
    const PINNED: [u32; 3] = [1774745655, 1721023772, 2742778566];

    #[test]
    fn distinct_streams_per_thread_and_seed() {
        let seq = |seed, id| {
            let mut r = Rng::new(seed, id);
            (0..8).map(|_| r.next_u32()).collect::<Vec<_>>()
        };
        let base = seq(1, 0);
        for id in 1..64 {
            assert_ne!(seq(1, id), base, "thread {id}");
        }
        assert_ne!(seq(2, 0), base);
        // Adjacent threads' first draws are not trivially related.
        let firsts: std::collections::HashSet<u32> = (0..256).map(|id| seq(1, id)[0]).collect();
        assert_eq!(firsts.len(), 256);
    }
    /// First draw of each of `n` keys.
    fn firsts(n: u32, mut rng: impl FnMut(u32) -> Rng) -> Vec<f64> {
        (0..n).map(|k| rng(k).next_f32() as f64).collect()
    }

    fn mean(x: &[f64]) -> f64 {
        x.iter().sum::<f64>() / x.len() as f64
    }

    fn variance(x: &[f64]) -> f64 {
        let m = mean(x);
        x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64
    }

    /// Pearson correlation of two equally long samples.
    fn correlation(a: &[f64], b: &[f64]) -> f64 {
        let (ma, mb) = (mean(a), mean(b));
        let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
        cov / (variance(a) * variance(b)).sqrt() / a.len() as f64
    }

    /// Chi-square of the pairs `(a[k], b[k])` over a 16 x 16 grid of `[0,1)^2`.
    fn pair_chi_square(a: &[f64], b: &[f64]) -> f64 {
        let mut cells = [0u32; 256];
        for (x, y) in a.iter().zip(b) {
            cells[(x * 16.0) as usize * 16 + (y * 16.0) as usize] += 1;
        }
        let e = a.len() as f64 / 256.0;
        cells.iter().map(|&c| (c as f64 - e).powi(2) / e).sum()
    }

    // Bounds: under independence a sample mean of n uniform draws has standard deviation
    // sqrt(1/12/n), a sample variance sqrt((1/80 - 1/144)/n), a correlation 1/sqrt(n), and
    // a 255-degree chi-square sqrt(510) around 255. Each test allows 5 standard deviations
    // (a false alarm is a ~1e-6 event; the draws are deterministic, so a pass stays a pass).
    const N: u32 = 256 * 256;
    const WIDTH: u32 = 256;

    fn assert_independent(what: &str, a: &[f64], b: &[f64]) {
        let n = a.len() as f64;
        let r = correlation(a, b);
        assert!(r.abs() < 5.0 / n.sqrt(), "{what}: correlation {r}");
        let chi = pair_chi_square(a, b);
        assert!(
            chi < 255.0 + 5.0 * 510f64.sqrt(),
            "{what}: pair chi-square {chi}"
        );
    }

    #[test]
    fn sample_streams_first_draws_are_uniform() {
        for seed in [0, 1, 12345] {
            let x = firsts(N, |p| Rng::for_sample(seed, p, 0));
            let n = N as f64;
            let m = mean(&x);
            assert!((m - 0.5).abs() < 5.0 * (1.0 / 12.0 / n).sqrt(), "mean {m}");
            let v = variance(&x);
            let sd = ((1.0 / 80.0 - 1.0 / 144.0) / n).sqrt();
            assert!((v - 1.0 / 12.0).abs() < 5.0 * sd, "variance {v}");
        }
    }

    #[test]
    fn neighbouring_pixels_and_samples_are_uncorrelated() {
        let at = |seed, p, s| Rng::for_sample(seed, p, s).next_f32() as f64;
        let x: Vec<f64> = (0..N).map(|p| at(1, p, 0)).collect();
        let right: Vec<f64> = (0..N).map(|p| at(1, p + 1, 0)).collect();
        let below: Vec<f64> = (0..N).map(|p| at(1, p + WIDTH, 0)).collect();
        let next_sample: Vec<f64> = (0..N).map(|p| at(1, p, 1)).collect();
        let next_seed: Vec<f64> = (0..N).map(|p| at(2, p, 0)).collect();
        assert_independent("pixel vs right neighbour", &x, &right);
        assert_independent("pixel vs pixel below", &x, &below);
        assert_independent("sample 0 vs sample 1", &x, &next_sample);
        assert_independent("seed 1 vs seed 2", &x, &next_seed);
        // Samples of one pixel, as a path tracer walks them.
        let samples: Vec<f64> = (0..N).map(|s| at(1, 77, s)).collect();
        let samples_next: Vec<f64> = (0..N).map(|s| at(1, 77, s + 1)).collect();
        assert_independent("consecutive samples of a pixel", &samples, &samples_next);
        // Second draws too (the first dimension is not special).
        let second = |p, s| {
            let mut r = Rng::for_sample(1, p, s);
            r.next_f32();
            r.next_f32() as f64
        };
        let a: Vec<f64> = (0..N).map(|p| second(p, 0)).collect();
        let b: Vec<f64> = (0..N).map(|p| second(p + 1, 0)).collect();
        assert_independent("second draws of neighbours", &a, &b);
    }

    #[test]
    fn the_independence_checks_catch_an_unmixed_seeding() {
        // Without the hash (state = pixel number, one stream) neighbouring pixels' first
        // draws are nearly equal: the checks above must reject that.
        let naive = |p: u32| Rng {
            state: p as u64,
            inc: 1,
            seed: 0,
        };
        let x = firsts(N, naive);
        let right = firsts(N, |p| naive(p + 1));
        let r = correlation(&x, &right);
        let chi = pair_chi_square(&x, &right);
        assert!(
            r.abs() >= 5.0 / (N as f64).sqrt() || chi >= 255.0 + 5.0 * 510f64.sqrt(),
            "r {r}, chi {chi}"
        );
    }

    #[test]
    fn sample_streams_are_distinct_and_pinned() {
        // A bijective key hash: distinct (pixel, sample) pairs never share a state.
        let mut states = std::collections::HashSet::new();
        for p in 0..512 {
            for s in 0..64 {
                assert!(states.insert(Rng::for_sample(1, p, s).state), "({p}, {s})");
            }
        }
        // Reseeding keeps the run's seed and forgets the thread.
        let mut r = Rng::new(9, 5);
        r.next_u32();
        r.reseed(1000, 3);
        assert_eq!(r, Rng::for_sample(9, 1000, 3));
        let mut other = Rng::new(9, 6);
        other.reseed(1000, 3);
        assert_eq!(r, other);
        // Pin the algorithm: the emulator and the host prelude share it, and images
        // depend on it. Values from an independent Python transcription of the mixing
        // and of PCG32.
        let mut r = Rng::for_sample(1, 0, 0);
        let got: Vec<u32> = (0..3).map(|_| r.next_u32()).collect();
        assert_eq!(got, PINNED_SAMPLE);
    }
    const PINNED_SAMPLE: [u32; 3] = [3615295130, 3585914120, 4119729932];
}
