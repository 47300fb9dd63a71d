//! Cacti-style area and energy-per-access figures for caches (65 nm, Cacti 6.5, as in the thesis).
//!
//! Sources: the original simtrax `dcacheparams.txt` rows quoted in the reference (§2.2), the
//! thesis Table 3.3 (L2 energy per access by capacity) and Table 2.2 (a 4 MB, 32-bank data cache
//! of 33.5 mm²), and `icacheparams.txt` end points (4 KB I-cache, 1..64 banks). A configuration
//! that matches no row is scaled from the nearest row by capacity (area linear in capacity,
//! energy with its square root, as Cacti's trends for these sizes) and is reported as
//! [`Source::Scaled`].

/// Where a figure came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Given in the configuration.
    Config,
    /// An exact table row.
    Table,
    /// Scaled from the nearest row.
    Scaled,
}

/// Area and read energy of one cache instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CacheCost {
    /// Area in mm².
    pub area_mm2: f64,
    /// Energy per read access in nJ.
    pub energy_nj: f64,
    /// Provenance.
    pub source: Source,
}

/// (capacity bytes, banks, line bytes, area mm², energy nJ).
const DCACHE: &[(u32, u32, u32, f64, f64)] = &[
    // dcacheparams.txt (reference §2.2): default L1 and default L2.
    (32768, 4, 64, 0.391508, 0.165190),
    (524288, 8, 64, 4.575878, 0.559878),
    // Thesis Table 2.2: 4 MB, 32 banks, total area 33.5 mm²; energy from Table 3.3 (4 MB).
    (4 << 20, 32, 64, 33.5, 0.901),
];

/// Thesis Table 3.3: energy per access (nJ) of L2/stream memories by capacity.
const L2_ENERGY: &[(u32, f64)] = &[
    (512 << 10, 0.524),
    (1 << 20, 0.579),
    (2 << 20, 0.686),
    (4 << 20, 0.901),
    (8 << 20, 1.17),
    (16 << 20, 1.61),
];

/// Area and energy of a data cache of this geometry.
pub fn dcache(capacity: u32, banks: u32, line: u32) -> CacheCost {
    if let Some(r) = DCACHE
        .iter()
        .find(|r| r.0 == capacity && r.1 == banks && r.2 == line)
    {
        return CacheCost {
            area_mm2: r.3,
            energy_nj: r.4,
            source: Source::Table,
        };
    }
    // Nearest row by log-capacity distance, then scale.
    let lc = f64::from(capacity.max(1)).log2();
    let near = DCACHE
        .iter()
        .min_by(|a, b| {
            let da = (f64::from(a.0).log2() - lc).abs();
            let db = (f64::from(b.0).log2() - lc).abs();
            da.total_cmp(&db)
        })
        .copied()
        .unwrap_or(DCACHE[0]);
    let ratio = f64::from(capacity) / f64::from(near.0);
    let energy = L2_ENERGY
        .iter()
        .find(|e| e.0 == capacity)
        .map(|e| e.1)
        .unwrap_or(near.4 * ratio.sqrt());
    CacheCost {
        area_mm2: near.3 * ratio,
        energy_nj: energy,
        source: Source::Scaled,
    }
}

/// Area and energy of a 4 KB instruction cache with `banks` banks (`icacheparams.txt` end
/// points: 1 bank 0.090296 mm² / 0.013130 nJ, 64 banks 0.247576 mm² / 0.016584 nJ;
/// log-linear in between).
pub fn icache_4k(banks: u32) -> CacheCost {
    let (a1, e1, a64, e64) = (0.090296, 0.013130, 0.247576, 0.016584);
    let f = (f64::from(banks.clamp(1, 64)).log2() / 6.0).clamp(0.0, 1.0);
    let exact = banks == 1 || banks == 64;
    CacheCost {
        area_mm2: a1 + (a64 - a1) * f,
        energy_nj: e1 + (e64 - e1) * f,
        source: if exact { Source::Table } else { Source::Scaled },
    }
}

/// `dcache` unless the configuration gives both figures.
pub fn resolve(
    capacity: u32,
    banks: u32,
    line: u32,
    area: Option<f64>,
    energy: Option<f64>,
) -> CacheCost {
    let t = dcache(capacity, banks, line);
    match (area, energy) {
        (Some(a), Some(e)) => CacheCost {
            area_mm2: a,
            energy_nj: e,
            source: Source::Config,
        },
        (Some(a), None) => CacheCost { area_mm2: a, ..t },
        (None, Some(e)) => CacheCost { energy_nj: e, ..t },
        (None, None) => t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_rows() {
        let l1 = dcache(32768, 4, 64);
        assert_eq!(
            (l1.area_mm2, l1.energy_nj, l1.source),
            (0.391508, 0.165190, Source::Table)
        );
        let l2 = dcache(524288, 8, 64);
        assert_eq!((l2.area_mm2, l2.energy_nj), (4.575878, 0.559878));
        let s = dcache(1 << 20, 16, 64);
        assert_eq!(s.source, Source::Scaled);
        assert_eq!(s.energy_nj, 0.579);
        assert!((icache_4k(1).energy_nj - 0.013130).abs() < 1e-12);
        assert!((icache_4k(64).area_mm2 - 0.247576).abs() < 1e-12);
    }
}
