//! Cost collection: interned call stacks and per-(stack, pc) counters.
//!
//! Each thread's shadow call stack ([`Thread::calls`]) is mirrored as a path in a trie of
//! call sites; a trie node id names a whole stack, so a sample costs one hash update
//! keyed by (stack id, pc). Functional runs go through [`ProfileExec`], which runs a
//! thread in basic-block chunks (control transfers only end a chunk, so every
//! instruction of a chunk ran under the stack at its start) and charges a whole chunk
//! with one update. PCs are resolved to source frames only in [`crate::profile::report`].

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::decode::{Cti, Inst};
use crate::exec::Stop;
use crate::program::Program;
use crate::thread::{CallFrame, Shared, Thread};

use crate::sched::Executor;

/// What a unit of cost is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CostKind {
    /// A retired instruction (functional mode).
    Instruction,
    /// A cycle in which the thread issued an instruction.
    Issue,
    /// A cycle stalled on a data dependence (operand not ready).
    DataStall,
    /// A cycle stalled on a busy shared resource (execution unit, cache bank, port).
    ResourceStall,
    /// A cycle stalled on memory (load/store latency beyond the data dependence).
    MemoryStall,
    /// Any other stall cycle.
    OtherStall,
}

/// Number of [`CostKind`]s.
pub const KINDS: usize = 6;

impl CostKind {
    /// Every kind, in index order.
    pub const ALL: [CostKind; KINDS] = [
        CostKind::Instruction,
        CostKind::Issue,
        CostKind::DataStall,
        CostKind::ResourceStall,
        CostKind::MemoryStall,
        CostKind::OtherStall,
    ];

    /// Index into a `[u64; KINDS]` cost vector.
    pub fn index(self) -> usize {
        self as usize
    }

    /// Short name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            CostKind::Instruction => "instructions",
            CostKind::Issue => "issue",
            CostKind::DataStall => "data-stall",
            CostKind::ResourceStall => "resource-stall",
            CostKind::MemoryStall => "memory-stall",
            CostKind::OtherStall => "other-stall",
        }
    }

    /// True for the cycle kinds (everything but [`CostKind::Instruction`]).
    pub fn is_cycle(self) -> bool {
        self != CostKind::Instruction
    }
}

/// A small, fast, non-cryptographic hasher for integer keys (FxHash-style).
#[derive(Default, Clone, Copy)]
pub struct FastHasher(u64);

impl Hasher for FastHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

/// Hash map with [`FastHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<FastHasher>>;

/// Longest chunk charged with one update.
const MAX_CHUNK: u64 = 1 << 12;

/// Per text word: instructions from it to the end of its basic block (inclusive of a
/// delay slot). Anything that may transfer control ends a block.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockTable {
    base: u32,
    lens: Vec<u16>,
}

impl BlockTable {
    pub(crate) fn new(p: &Program) -> BlockTable {
        let n = p.insts.len();
        let mut lens = vec![1u16; n];
        for i in (0..n).rev() {
            lens[i] = match ends_block(&p.insts[i]) {
                End::No => lens
                    .get(i + 1)
                    .map_or(1, |l| l.saturating_add(1).min(MAX_CHUNK as u16)),
                End::Here => 1,
                End::AfterSlot => 2,
            };
        }
        BlockTable { base: p.base, lens }
    }

    #[inline(always)]
    pub(crate) fn len_at(&self, pc: u32) -> u64 {
        let idx = pc.wrapping_sub(self.base).rotate_right(2) as usize;
        self.lens.get(idx).map_or(1, |&l| l as u64)
    }
}

enum End {
    No,
    Here,
    AfterSlot,
}

fn ends_block(i: &Inst) -> End {
    match i.cti() {
        Cti::DelaySlot => End::AfterSlot,
        Cti::CompactBranch | Cti::CompactJump => End::Here,
        // TRaX operations may block, halt or redirect the thread; traps may fault.
        Cti::None if matches!(i, Inst::Trax { .. } | Inst::Reserved(_)) => End::Here,
        Cti::None => End::No,
    }
}

/// One thread's view of its interned stack.
#[derive(Clone, Debug, Default)]
struct Cursor {
    /// Node id per shadow-stack depth (`ids[d]` = stack of the first `d + 1` frames).
    ids: Vec<u32>,
    /// Call pc per depth, to detect changes.
    pcs: Vec<u32>,
}

/// Collects costs per (interned call stack, pc).
///
/// Feed it either through [`ProfileExec`] (functional runs) or by calling
/// [`Profiler::charge`] per thread and cycle (timing runs). Then
/// [`crate::profile::Profile::build`] resolves and aggregates.
#[derive(Clone, Debug, Default)]
pub struct Profiler {
    blocks: BlockTable,
    cursors: Vec<Cursor>,
    /// Trie nodes: (parent node, call pc). Node 0 is the empty stack.
    pub(crate) nodes: Vec<(u32, u32)>,
    children: FastMap<(u32, u32), u32>,
    /// Whole-chunk instruction counts keyed by (node, first pc, instructions).
    chunks: FastMap<(u32, u32, u32), u64>,
    /// Individual charges keyed by (node, pc, kind).
    single: FastMap<(u32, u32, u8), u64>,
}

impl Profiler {
    /// A profiler for a machine running `program` with `threads` hardware threads.
    pub fn new(program: &Program, threads: usize) -> Profiler {
        Profiler {
            blocks: BlockTable::new(program),
            cursors: vec![Cursor::default(); threads],
            nodes: vec![(u32::MAX, 0)],
            ..Profiler::default()
        }
    }

    /// The interned id of thread `idx`'s current shadow stack `calls`. An instruction in
    /// a delay slot (`in_slot`) belongs to the stack of its branch: a call has already
    /// pushed (a return popped) when the slot runs, so the stack seen last is kept.
    #[inline(always)]
    pub fn stack_id(&mut self, idx: usize, calls: &[CallFrame], in_slot: bool) -> u32 {
        if idx >= self.cursors.len() {
            self.cursors.resize(idx + 1, Cursor::default());
        }
        let c = &self.cursors[idx];
        if in_slot {
            return c.ids.last().copied().unwrap_or(0);
        }
        let n = calls.len();
        if n == c.ids.len() && (n == 0 || c.pcs[n - 1] == calls[n - 1].call_pc) {
            return if n == 0 { 0 } else { c.ids[n - 1] };
        }
        self.resync(idx, calls)
    }

    #[cold]
    fn resync(&mut self, idx: usize, calls: &[CallFrame]) -> u32 {
        let c = &mut self.cursors[idx];
        // Keep the common prefix (only the top changes between samples), then intern.
        let mut k = c.ids.len().min(calls.len());
        while k > 0 && c.pcs[k - 1] != calls[k - 1].call_pc {
            k -= 1;
        }
        c.ids.truncate(k);
        c.pcs.truncate(k);
        let mut node = if k == 0 { 0 } else { c.ids[k - 1] };
        for f in &calls[k..] {
            let parent = node;
            let next = self.nodes.len() as u32;
            node = *self.children.entry((parent, f.call_pc)).or_insert(next);
            if node == next {
                self.nodes.push((parent, f.call_pc));
            }
            c.ids.push(node);
            c.pcs.push(f.call_pc);
        }
        node
    }

    /// Charges `amount` units of `kind` to thread `idx` (index in `Machine::threads`)
    /// at its current pc and shadow stack. The timing model calls this per thread and
    /// cycle for the instruction issuing or stalled at `t.pc`.
    pub fn charge(&mut self, idx: usize, t: &Thread, kind: CostKind, amount: u64) {
        let in_slot = t.npc != t.pc.wrapping_add(4);
        let node = self.stack_id(idx, &t.calls, in_slot);
        *self.single.entry((node, t.pc, kind as u8)).or_insert(0) += amount;
    }

    /// Charges one instruction to each of the `n` words from `pc` under stack `node`.
    #[inline(always)]
    fn charge_chunk(&mut self, node: u32, pc: u32, n: u64) {
        *self.chunks.entry((node, pc, n as u32)).or_insert(0) += 1;
    }

    /// Every (node, pc, costs) collected so far.
    pub(crate) fn samples(&self) -> FastMap<(u32, u32), [u64; super::KINDS]> {
        let mut out: FastMap<(u32, u32), [u64; super::KINDS]> = FastMap::default();
        for (&(node, pc, n), &count) in &self.chunks {
            for i in 0..n {
                out.entry((node, pc.wrapping_add(4 * i)))
                    .or_insert([0; super::KINDS])[0] += count;
            }
        }
        for (&(node, pc, kind), &v) in &self.single {
            out.entry((node, pc)).or_insert([0; super::KINDS])[kind as usize] += v;
        }
        out
    }

    /// The call pcs of stack `node`, outermost first.
    pub(crate) fn call_pcs(&self, mut node: u32) -> Vec<u32> {
        let mut v = Vec::new();
        while node != 0 {
            let (parent, pc) = self.nodes[node as usize];
            v.push(pc);
            node = parent;
        }
        v.reverse();
        v
    }
}

/// An [`Executor`] that runs threads in basic-block chunks and charges every retired
/// instruction to its thread's stack.
#[derive(Debug)]
pub struct ProfileExec<'a> {
    /// The profiler fed.
    pub profiler: &'a mut Profiler,
}

impl Executor for ProfileExec<'_> {
    #[inline]
    fn exec(&mut self, idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop {
        let p = &mut *self.profiler;
        let end = t.retired.saturating_add(budget);
        loop {
            let left = end - t.retired;
            if left == 0 {
                return Stop::Budget;
            }
            let pc = t.pc;
            // In a delay slot (the turn ended after its branch) the next pc is not
            // pc + 4: run the slot alone, under its branch's stack.
            let in_slot = t.npc != pc.wrapping_add(4);
            let len = if in_slot { 1 } else { p.blocks.len_at(pc) };
            let len = len.min(left);
            let node = p.stack_id(idx, &t.calls, in_slot);
            let before = t.retired;
            let stop = t.run(sh, len);
            let n = t.retired - before;
            if n > 0 {
                p.charge_chunk(node, pc, n);
            }
            if stop != Stop::Budget {
                return stop;
            }
        }
    }
}
