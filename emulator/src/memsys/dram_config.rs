//! DRAM configuration: the simple and detailed models, timing, energy, and the named presets.

use super::timespec::TimeSpec;
use super::MemSysError;
use serde::{Deserialize, Serialize};

/// Which DRAM model runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DramModel {
    /// Fixed latency plus a bandwidth limit ([`SimpleDramConfig`]).
    Simple,
    /// Channels, ranks, banks, rows, FR-FCFS scheduling ([`DetailedDramConfig`]).
    Detailed,
}

/// Main-memory configuration. Use `preset = "gddr5-thesis" | "gddr5-usimm" | "ddr4-2400" |
/// "hbm2" | "simple"` in TOML to start from a named preset.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DramConfig {
    /// Model to run. Default `detailed`.
    pub model: DramModel,
    /// Parameters of the simple model (used when `model = "simple"`).
    pub simple: SimpleDramConfig,
    /// Parameters of the detailed model (used when `model = "detailed"`).
    pub detailed: DetailedDramConfig,
}

impl Default for DramConfig {
    fn default() -> Self {
        DramConfig::gddr5_thesis()
    }
}

/// Chips per rank in simtrax's USIMM 1.3 power model: `usimm_setup` hard-codes
/// `chips_per_rank = 16` whatever the device width of the `.vi` file (reference notes §2.3).
pub const USIMM_CHIPS_PER_RANK: u32 = 16;

/// USIMM 1.3's read I/O termination power per chip, mW (`pds_dq = 3.2 * 10`, Micron TN-41-01).
pub const USIMM_READ_TERMINATION_MW: f64 = 32.0;

/// Names of the DRAM presets, for help texts.
pub const DRAM_PRESETS: &[&str] = &["gddr5-thesis", "gddr5-usimm", "ddr4-2400", "hbm2", "simple"];

/// Longest simple-DRAM latency, core cycles: 10^6 (1 ms at 1 GHz, ten thousand times a
/// DRAM access; far memories of a few microseconds fit).
pub const MAX_SIMPLE_LATENCY: u32 = 1_000_000;

/// Largest DRAM request (`dram.simple.line_bytes`), bytes.
pub const MAX_LINE_BYTES: u32 = 4096;

/// Fastest DRAM command clock, MHz (100 GHz).
pub const MAX_CLOCK_MHZ: u32 = 100_000;

/// Most entries of a detailed DRAM channel's read or write queue.
pub const MAX_QUEUE: u32 = 65_536;

/// Longest DRAM timing constraint except `tREFI`, ns: 10 µs (the longest of the JEDEC
/// standards, `tRFC` of large DDR5 parts, is under 1 µs).
pub const MAX_TIMING_NS: u32 = 10_000;

/// Longest refresh interval `tREFI`, ns: 1 ms (standards use 3.9 or 7.8 µs; longer ones
/// model refresh-reduction studies).
pub const MAX_REFRESH_INTERVAL_NS: u32 = 1_000_000;

/// Fixed-latency, bandwidth-limited memory (the original's `--disable-usimm` model, minus its
/// per-L2 bandwidth split).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimpleDramConfig {
    /// Latency in core cycles from the request to the data, on top of transfer time, 0 to
    /// [`MAX_SIMPLE_LATENCY`]. Default 100 (original `MEMORY 100`).
    pub latency: u32,
    /// Peak transfer rate in bytes per core cycle (>= 1). Default 512 (512 GB/s at 1 GHz, the
    /// thesis GDDR5 peak).
    pub bandwidth_bytes_per_cycle: u32,
    /// Bytes moved per request (one cache line), 1 to [`MAX_LINE_BYTES`]. Default 64.
    pub line_bytes: u32,
    /// Requests in flight at most (0 = unlimited); more are refused (the caller stalls). Default 0.
    pub max_outstanding: u32,
    /// Energy per access in nJ. Default 16.3 (thesis Table 3.3, off-chip DRAM).
    pub energy_per_access_nj: f64,
}

impl Default for SimpleDramConfig {
    fn default() -> Self {
        SimpleDramConfig {
            latency: 100,
            bandwidth_bytes_per_cycle: 512,
            line_bytes: 64,
            max_outstanding: 0,
            energy_per_access_nj: 16.3,
        }
    }
}

/// How a line address is split into DRAM coordinates (fields listed most- to least-significant).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum AddressMapping {
    /// Consecutive lines stay in one row; consecutive rows go to consecutive channels, then
    /// banks (USIMM mapping 0; the thesis's STRaTA+ layout).
    #[serde(rename = "row:rank:bank:channel:column")]
    RowRankBankChannelColumn,
    /// Consecutive lines go to consecutive channels, then banks, then ranks (USIMM mapping 1;
    /// bank/channel interleaved).
    #[serde(rename = "row:column:rank:bank:channel")]
    RowColumnRankBankChannel,
}

/// Timing constraints, each in DRAM command-clock cycles (integer) or nanoseconds (`"13.75ns"`),
/// each at most [`MAX_TIMING_NS`] (`tREFI`: [`MAX_REFRESH_INTERVAL_NS`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DramTimingSpec {
    /// ACT to column command, same bank.
    #[serde(rename = "tRCD")]
    pub t_rcd: TimeSpec,
    /// PRE to ACT, same bank.
    #[serde(rename = "tRP")]
    pub t_rp: TimeSpec,
    /// Read command to first data (CL).
    #[serde(rename = "tCAS")]
    pub t_cas: TimeSpec,
    /// ACT to PRE, same bank.
    #[serde(rename = "tRAS")]
    pub t_ras: TimeSpec,
    /// ACT to ACT, same bank.
    #[serde(rename = "tRC")]
    pub t_rc: TimeSpec,
    /// ACT to ACT, different banks of one rank.
    #[serde(rename = "tRRD")]
    pub t_rrd: TimeSpec,
    /// Window in which at most four ACTs may issue to one rank.
    #[serde(rename = "tFAW")]
    pub t_faw: TimeSpec,
    /// End of write data to PRE (write recovery).
    #[serde(rename = "tWR")]
    pub t_wr: TimeSpec,
    /// End of write data to a read command, same rank.
    #[serde(rename = "tWTR")]
    pub t_wtr: TimeSpec,
    /// Read command to PRE.
    #[serde(rename = "tRTP")]
    pub t_rtp: TimeSpec,
    /// Column command to column command, same rank.
    #[serde(rename = "tCCD")]
    pub t_ccd: TimeSpec,
    /// Write command to first write data (CWL).
    #[serde(rename = "tCWD")]
    pub t_cwd: TimeSpec,
    /// Data-bus turnaround between ranks (and read to write).
    #[serde(rename = "tRTRS")]
    pub t_rtrs: TimeSpec,
    /// Data-bus cycles one line occupies (burst length / data rate per command clock).
    #[serde(rename = "tBURST")]
    pub t_burst: TimeSpec,
    /// Refresh command duration (REF to ACT).
    #[serde(rename = "tRFC")]
    pub t_rfc: TimeSpec,
    /// Average refresh interval per rank; 0 disables refresh.
    #[serde(rename = "tREFI")]
    pub t_refi: TimeSpec,
}

/// DRAM energy parameters: datasheet currents (USIMM / Micron power-calculator method), with
/// optional direct per-operation overrides.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DramEnergyConfig {
    /// Supply voltage in volts.
    pub vdd: f64,
    /// One-bank ACT-PRE current, mA per device.
    pub idd0: f64,
    /// Precharge standby current, mA per device.
    pub idd2n: f64,
    /// Active standby current, mA per device.
    pub idd3n: f64,
    /// Burst read current, mA per device.
    pub idd4r: f64,
    /// Burst write current, mA per device.
    pub idd4w: f64,
    /// Burst refresh current, mA per device.
    pub idd5: f64,
    /// Devices (chips) per rank; the currents are multiplied by this.
    pub devices_per_rank: u32,
    /// Read I/O termination power, mW per device while a read burst is on the bus (USIMM
    /// 1.3 `pds_dq = 3.2 * 10`, from Micron TN-41-01). Added to each read burst's energy.
    /// Default 0 (not in the TOML of older configs). The other-rank termination terms of
    /// USIMM (`pds_termRoth`, `pds_termWoth`) are not modelled: every preset has one rank.
    #[serde(default)]
    pub read_termination_mw: f64,
    /// Override: energy per ACT (with its PRE) in nJ per rank. Default: from IDD values.
    #[serde(default)]
    pub act_nj: Option<f64>,
    /// Override: energy per read burst in nJ per rank. Default: from IDD values.
    #[serde(default)]
    pub read_nj: Option<f64>,
    /// Override: energy per write burst in nJ per rank. Default: from IDD values.
    #[serde(default)]
    pub write_nj: Option<f64>,
    /// Override: energy per refresh in nJ per rank. Default: from IDD values.
    #[serde(default)]
    pub refresh_nj: Option<f64>,
}

/// Channels, ranks, banks, rows and columns with an FR-FCFS open-row controller per channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DetailedDramConfig {
    /// DRAM command-clock frequency in MHz (timing cycles count this clock), 1 to
    /// [`MAX_CLOCK_MHZ`].
    pub clock_mhz: u32,
    /// Independent channels (power of two).
    pub channels: u32,
    /// Ranks per channel (power of two).
    pub ranks: u32,
    /// Banks per rank (power of two; ranks x banks <= 64).
    pub banks: u32,
    /// Rows per bank (power of two); higher address bits wrap.
    pub rows: u32,
    /// Columns per row, counted in lines (power of two): row size = columns x line_bytes.
    pub columns: u32,
    /// Bytes per request and per burst (power of two). Must equal the cache line size.
    pub line_bytes: u32,
    /// Address mapping policy.
    pub mapping: AddressMapping,
    /// Read-queue entries per channel, 1 to [`MAX_QUEUE`]; a full queue refuses requests (the
    /// caller stalls).
    pub read_queue: u32,
    /// Write-queue entries per channel, 1 to [`MAX_QUEUE`].
    pub write_queue: u32,
    /// Write drain starts when a channel holds this many writes.
    pub write_high_watermark: u32,
    /// Write drain stops when a channel holds this many writes or fewer.
    pub write_low_watermark: u32,
    /// Timing constraints.
    pub timing: DramTimingSpec,
    /// Energy parameters.
    pub energy: DramEnergyConfig,
}

/// Timing resolved to DRAM cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub struct DramTiming {
    pub t_rcd: u64,
    pub t_rp: u64,
    pub t_cas: u64,
    pub t_ras: u64,
    pub t_rc: u64,
    pub t_rrd: u64,
    pub t_faw: u64,
    pub t_wr: u64,
    pub t_wtr: u64,
    pub t_rtp: u64,
    pub t_ccd: u64,
    pub t_cwd: u64,
    pub t_rtrs: u64,
    pub t_burst: u64,
    pub t_rfc: u64,
    pub t_refi: u64,
}

impl DramTiming {
    /// Every constraint with its config name (`tRCD`, ...).
    pub fn named(&self) -> [(&'static str, u64); 16] {
        [
            ("tRCD", self.t_rcd),
            ("tRP", self.t_rp),
            ("tCAS", self.t_cas),
            ("tRAS", self.t_ras),
            ("tRC", self.t_rc),
            ("tRRD", self.t_rrd),
            ("tFAW", self.t_faw),
            ("tWR", self.t_wr),
            ("tWTR", self.t_wtr),
            ("tRTP", self.t_rtp),
            ("tCCD", self.t_ccd),
            ("tCWD", self.t_cwd),
            ("tRTRS", self.t_rtrs),
            ("tBURST", self.t_burst),
            ("tRFC", self.t_rfc),
            ("tREFI", self.t_refi),
        ]
    }
}

impl DramTimingSpec {
    /// Resolves every value to DRAM cycles at `clock_mhz`.
    pub fn resolve(&self, clock_mhz: u32) -> DramTiming {
        let c = |t: TimeSpec| u64::from(t.cycles(clock_mhz));
        DramTiming {
            t_rcd: c(self.t_rcd),
            t_rp: c(self.t_rp),
            t_cas: c(self.t_cas),
            t_ras: c(self.t_ras),
            t_rc: c(self.t_rc),
            t_rrd: c(self.t_rrd),
            t_faw: c(self.t_faw),
            t_wr: c(self.t_wr),
            t_wtr: c(self.t_wtr),
            t_rtp: c(self.t_rtp),
            t_ccd: c(self.t_ccd),
            t_cwd: c(self.t_cwd),
            t_rtrs: c(self.t_rtrs),
            t_burst: c(self.t_burst),
            t_rfc: c(self.t_rfc),
            t_refi: c(self.t_refi),
        }
    }
}

impl DetailedDramConfig {
    /// Bytes of one row: `columns x line_bytes`.
    pub fn row_bytes(&self) -> u32 {
        self.columns * self.line_bytes
    }

    /// Bytes of consecutive addresses the address mapping keeps in one row: the whole row
    /// for `row:rank:bank:channel:column` (consecutive lines fill a row, the next row goes to
    /// the next channel), one line for `row:column:rank:bank:channel` (consecutive lines go
    /// to consecutive channels). Data aligned to this and no larger is read from the fewest
    /// rows (`[treelets] align = "dram-row"`).
    pub fn row_span_bytes(&self) -> u32 {
        match self.mapping {
            AddressMapping::RowRankBankChannelColumn => self.row_bytes(),
            AddressMapping::RowColumnRankBankChannel => self.line_bytes,
        }
    }

    /// Peak data bandwidth in GB/s (all channels, one line per `tBURST`).
    pub fn peak_gbps(&self) -> f64 {
        let t = self.timing.resolve(self.clock_mhz);
        let per_cycle =
            f64::from(self.channels) * f64::from(self.line_bytes) / t.t_burst.max(1) as f64;
        per_cycle * f64::from(self.clock_mhz) * 1e6 / 1e9
    }
}

impl DramConfig {
    /// A named preset (see [`DRAM_PRESETS`]).
    pub fn preset(name: &str) -> Option<DramConfig> {
        match name {
            "gddr5-thesis" => Some(Self::gddr5_thesis()),
            "gddr5-usimm" => Some(Self::gddr5_usimm()),
            "ddr4-2400" => Some(Self::ddr4_2400()),
            "hbm2" => Some(Self::hbm2()),
            "simple" => Some(DramConfig {
                model: DramModel::Simple,
                ..Self::gddr5_thesis()
            }),
            _ => None,
        }
    }

    /// The thesis GDDR5 system (§5.1): 8 x 64-bit channels, 2 GHz command clock, 8 Gb/s per pin,
    /// 512 GB/s peak. A 64-byte line is one BL8 burst = 2 command cycles on a 64-bit channel.
    /// Core timing is the USIMM GDDR5 chip file the thesis used (`1Gb_x16_amd2GHz.vi`); rows are
    /// 8 KB (a 16 KB treelet maps to two rows, §5).
    ///
    /// Energy reproduces the accounting behind the thesis's DRAM energies (Table 5.1): simtrax's
    /// USIMM 1.3 with its default `gddr5_8ch.cfg` (16 channels x 1 rank, `T_DATA_TRANS` 4) and
    /// `chips_per_rank = 16` hard-coded in `usimm_setup` (see [`Self::gddr5_usimm`]). Each
    /// 64-bit channel here stands for two of those 32-bit channels, so per line moved and per
    /// unit of time it charges the same chip-cycles: 32 devices per rank (2 x 16; a burst of 2
    /// cycles x 32 = USIMM's 4 x 16; standby 8 x 32 = USIMM's 16 x 16 chips), while an ACT opens
    /// one 8 KB row as USIMM's does, charged for 16 devices (`act_nj`). With these, Table 5.1's
    /// accesses, row-buffer hit rates and frame times give its energies within 10% (test
    /// `memsys_dram::thesis_table_5_1_energy`); the earlier 4 physical x16 devices per 64-bit
    /// rank gave 4-6x less. (USIMM's 16 chips are not physical for x16 parts, but they are what
    /// the thesis's comparisons were measured with.)
    pub fn gddr5_thesis() -> DramConfig {
        let mut d = Self::gddr5_usimm().detailed;
        d.channels = 8;
        d.rows = 8192;
        d.timing.t_burst = TimeSpec::Cycles(2);
        d.timing.t_ccd = TimeSpec::Cycles(2);
        let usimm_rank = super::dram::DramOpEnergy::from_config(
            &d.energy,
            &d.timing.resolve(d.clock_mhz),
            d.clock_mhz,
        );
        d.energy.devices_per_rank = 2 * USIMM_CHIPS_PER_RANK;
        d.energy.act_nj = Some(usimm_rank.act_nj);
        d.mapping = AddressMapping::RowRankBankChannelColumn;
        DramConfig {
            model: DramModel::Detailed,
            simple: SimpleDramConfig::default(),
            detailed: d,
        }
    }

    /// The original simtrax default: `gddr5_8ch.cfg` (really 16 channels, 1 rank, 16 banks,
    /// 8192 rows, 128 columns of 64 B, mapping 1, write queue 96) with `1Gb_x16_amd2GHz.vi`
    /// timing and currents (reference §2.3). T_DATA_TRANS 4 at 2 GHz on 16 channels = 512 GB/s.
    /// Energy as USIMM 1.3 computes it (`calculate_power` in `memory_controller.c`, Micron
    /// TN-41-01 method): IDD currents from the `.vi` file x VDD x [`USIMM_CHIPS_PER_RANK`]
    /// devices (hard-coded in simtrax's `usimm_setup`), plus read termination 3.2 x 10 mW per
    /// device during read bursts (`pds_dq`; `pds_termW` = 0).
    pub fn gddr5_usimm() -> DramConfig {
        let c = TimeSpec::Cycles;
        let d = DetailedDramConfig {
            clock_mhz: 2000,
            channels: 16,
            ranks: 1,
            banks: 16,
            rows: 8192,
            columns: 128,
            line_bytes: 64,
            mapping: AddressMapping::RowColumnRankBankChannel,
            read_queue: 64,
            write_queue: 96,
            write_high_watermark: 40,
            write_low_watermark: 20,
            timing: DramTimingSpec {
                t_rcd: c(28),
                t_rp: c(28),
                t_cas: c(28),
                t_ras: c(70),
                t_rc: c(98),
                t_rrd: c(13),
                t_faw: c(80),
                t_wr: c(30),
                t_wtr: c(15),
                t_rtp: c(15),
                t_ccd: c(4),
                t_cwd: c(13),
                t_rtrs: c(2),
                t_burst: c(4),
                t_rfc: c(220),
                t_refi: c(15600),
            },
            energy: DramEnergyConfig {
                vdd: 1.5,
                idd0: 120.0,
                idd2n: 70.0,
                idd3n: 67.0,
                idd4r: 250.0,
                idd4w: 250.0,
                idd5: 260.0,
                devices_per_rank: USIMM_CHIPS_PER_RANK,
                read_termination_mw: USIMM_READ_TERMINATION_MW,
                act_nj: None,
                read_nj: None,
                write_nj: None,
                refresh_nj: None,
            },
        };
        DramConfig {
            model: DramModel::Detailed,
            simple: SimpleDramConfig::default(),
            detailed: d,
        }
    }

    /// DDR4-2400 (JEDEC JESD79-4, speed bin DDR4-2400R 16-16-16, tCK 0.833 ns): 2 channels of
    /// 64 bits (8 x8 devices per rank), 1 rank, 16 banks, 8 KB rows (x8 1 KB page x 8),
    /// 65536 rows (8 Gb devices). Values in ns from the standard's tables: tRCD = tRP = CL =
    /// 13.32 ns, tRAS 32 ns, tRC 45.32 ns, tRRD_S 3.3 ns (min 4 nCK), tFAW 21 ns (1 KB page),
    /// tWR 15 ns, tWTR_S 2.5 ns (min 2 nCK), tRTP 7.5 ns, tCCD_S 4 nCK, CWL 12, BL8 = 4 nCK,
    /// tRFC 350 ns (8 Gb), tREFI 7.8 us. Bank groups are not modelled (tCCD_S/tRRD_S/tWTR_S are
    /// used). Currents: representative 8 Gb x8 DDR4-2400 datasheet values (Micron MT40A1G8
    /// class), to be replaced by a specific part's datasheet for absolute energy studies.
    pub fn ddr4_2400() -> DramConfig {
        let c = TimeSpec::Cycles;
        let ns = TimeSpec::Ns;
        let d = DetailedDramConfig {
            clock_mhz: 1200,
            channels: 2,
            ranks: 1,
            banks: 16,
            rows: 65536,
            columns: 128,
            line_bytes: 64,
            mapping: AddressMapping::RowRankBankChannelColumn,
            read_queue: 64,
            write_queue: 64,
            write_high_watermark: 40,
            write_low_watermark: 20,
            timing: DramTimingSpec {
                t_rcd: ns(13.32),
                t_rp: ns(13.32),
                t_cas: ns(13.32),
                t_ras: ns(32.0),
                t_rc: ns(45.32),
                t_rrd: c(4),
                t_faw: ns(21.0),
                t_wr: ns(15.0),
                t_wtr: c(3),
                t_rtp: ns(7.5),
                t_ccd: c(4),
                t_cwd: c(12),
                t_rtrs: c(2),
                t_burst: c(4),
                t_rfc: ns(350.0),
                t_refi: ns(7800.0),
            },
            energy: DramEnergyConfig {
                vdd: 1.2,
                idd0: 57.0,
                idd2n: 37.0,
                idd3n: 52.0,
                idd4r: 150.0,
                idd4w: 145.0,
                idd5: 250.0,
                devices_per_rank: 8,
                read_termination_mw: 0.0,
                act_nj: None,
                read_nj: None,
                write_nj: None,
                refresh_nj: None,
            },
        };
        DramConfig {
            model: DramModel::Detailed,
            simple: SimpleDramConfig::default(),
            detailed: d,
        }
    }

    /// One HBM2 stack (JEDEC JESD235A): 8 channels of 128 bits at 2 Gb/s per pin (1 GHz clock,
    /// DDR) = 256 GB/s; a 64-byte line is one BL4 burst = 2 cycles. 16 banks per channel, 2 KB
    /// rows (32 columns of 64 B), 16384 rows (a 4-high stack of 8 Gb dies: 4 Gb per channel,
    /// hence tRFC 260 ns from the standard's per-density table). Timing in ns as
    /// commonly used for JESD235A-class 2 Gb/s parts: tRCD = tRP = CL = 14 ns, tRAS 34 ns,
    /// tRC 48 ns, tRRD 4 ns, tFAW 16 ns (per channel), tWR 16 ns, tWTR 4 ns, tRTP 4 ns,
    /// tCCD 2 nCK, WL 4 nCK, tRFC 260 ns, tREFI 3.9 us. Pseudo-channels and bank groups are not
    /// modelled. Currents: representative HBM values per channel (VDD 1.2 V).
    pub fn hbm2() -> DramConfig {
        let c = TimeSpec::Cycles;
        let ns = TimeSpec::Ns;
        let d = DetailedDramConfig {
            clock_mhz: 1000,
            channels: 8,
            ranks: 1,
            banks: 16,
            rows: 16384,
            columns: 32,
            line_bytes: 64,
            mapping: AddressMapping::RowRankBankChannelColumn,
            read_queue: 64,
            write_queue: 64,
            write_high_watermark: 40,
            write_low_watermark: 20,
            timing: DramTimingSpec {
                t_rcd: ns(14.0),
                t_rp: ns(14.0),
                t_cas: ns(14.0),
                t_ras: ns(34.0),
                t_rc: ns(48.0),
                t_rrd: ns(4.0),
                t_faw: ns(16.0),
                t_wr: ns(16.0),
                t_wtr: ns(4.0),
                t_rtp: ns(4.0),
                t_ccd: c(2),
                t_cwd: c(4),
                t_rtrs: c(1),
                t_burst: c(2),
                t_rfc: ns(260.0),
                t_refi: ns(3900.0),
            },
            energy: DramEnergyConfig {
                vdd: 1.2,
                idd0: 48.0,
                idd2n: 34.0,
                idd3n: 43.0,
                idd4r: 135.0,
                idd4w: 123.0,
                idd5: 250.0,
                devices_per_rank: 1,
                read_termination_mw: 0.0,
                act_nj: None,
                read_nj: None,
                write_nj: None,
                refresh_nj: None,
            },
        };
        DramConfig {
            model: DramModel::Detailed,
            simple: SimpleDramConfig::default(),
            detailed: d,
        }
    }

    /// Parses a `[dram]`-style TOML document (the table's keys at top level; `preset` allowed).
    pub fn from_toml_str(text: &str) -> Result<DramConfig, MemSysError> {
        let v: toml::Value = toml::from_str(text).map_err(|e| super::config::toml_err(text, e))?;
        let cfg: DramConfig =
            super::config::load_with_preset(v, DramConfig::preset, "dram", Some((text, &[])))?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks value ranges and cross-field constraints.
    pub fn validate(&self) -> Result<(), MemSysError> {
        let err = |m: String| Err(MemSysError::Config(m));
        let range = |field: &str, v: u32, r: std::ops::RangeInclusive<u32>, unit: &str| {
            super::config::check_range(
                field,
                v.into(),
                (*r.start()).into()..=(*r.end()).into(),
                unit,
            )
            .map_err(MemSysError::Config)
        };
        let s = &self.simple;
        if s.bandwidth_bytes_per_cycle == 0 {
            return err("dram.simple.bandwidth_bytes_per_cycle must be >= 1".into());
        }
        range(
            "dram.simple.latency",
            s.latency,
            0..=MAX_SIMPLE_LATENCY,
            "core cycles",
        )?;
        range(
            "dram.simple.line_bytes",
            s.line_bytes,
            1..=MAX_LINE_BYTES,
            "bytes",
        )?;
        let d = &self.detailed;
        range(
            "dram.detailed.clock_mhz",
            d.clock_mhz,
            1..=MAX_CLOCK_MHZ,
            "MHz",
        )?;
        range(
            "dram.detailed.read_queue",
            d.read_queue,
            1..=MAX_QUEUE,
            "entries",
        )?;
        range(
            "dram.detailed.write_queue",
            d.write_queue,
            1..=MAX_QUEUE,
            "entries",
        )?;
        for (name, v) in [
            ("channels", d.channels),
            ("ranks", d.ranks),
            ("banks", d.banks),
            ("rows", d.rows),
            ("columns", d.columns),
            ("line_bytes", d.line_bytes),
        ] {
            if v == 0 || !v.is_power_of_two() {
                return err(format!("dram.detailed.{name} = {v} must be a power of two"));
            }
        }
        if d.ranks * d.banks > 64 {
            return err(format!(
                "dram.detailed: ranks x banks = {} exceeds 64 per channel",
                d.ranks * d.banks
            ));
        }
        if d.write_low_watermark >= d.write_high_watermark || d.write_high_watermark > d.write_queue
        {
            return err(format!(
                "dram.detailed: need write_low_watermark ({}) < write_high_watermark ({}) <= write_queue ({})",
                d.write_low_watermark, d.write_high_watermark, d.write_queue
            ));
        }
        let t = d.timing.resolve(d.clock_mhz);
        for (name, cycles) in t.named() {
            let ns = if name == "tREFI" {
                MAX_REFRESH_INTERVAL_NS
            } else {
                MAX_TIMING_NS
            };
            let max = u64::from(ns) * u64::from(d.clock_mhz) / 1000;
            super::config::check_range(
                &format!("dram.detailed.timing.{name}"),
                cycles,
                0..=max,
                &format!(
                    "DRAM cycles ({} us at clock_mhz {})",
                    ns / 1000,
                    d.clock_mhz
                ),
            )
            .map_err(MemSysError::Config)?;
        }
        if t.t_burst == 0 {
            return err("dram.detailed.timing.tBURST must be >= 1".into());
        }
        if t.t_refi != 0 && t.t_rfc >= t.t_refi {
            return err("dram.detailed.timing: tRFC must be smaller than tREFI".into());
        }
        let e = &d.energy;
        if !(e.vdd.is_finite() && e.vdd >= 0.0) {
            return err("dram.detailed.energy.vdd must be a non-negative number".into());
        }
        if !(e.read_termination_mw.is_finite() && e.read_termination_mw >= 0.0) {
            return err(
                "dram.detailed.energy.read_termination_mw must be a non-negative number".into(),
            );
        }
        Ok(())
    }
}
