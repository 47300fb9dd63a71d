//! Resolving a [`Profiler`]'s samples to source call trees and printing them: the
//! indented tree (thesis Figure 6.1), folded stacks, speedscope JSON and per-line costs.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;

use crate::debuginfo::DebugInfo;
use crate::elf::Executable;

use super::collect::{CostKind, Profiler, KINDS};

/// A cost vector indexed by [`CostKind::index`].
pub type Costs = [u64; KINDS];

/// One resolved source frame.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Frame {
    /// Short function name (`Type::method`, C name, symbol or `0x...`).
    pub name: String,
    /// Source file, if known.
    pub file: Option<String>,
    /// Line, 0 if unknown.
    pub line: u32,
}

/// One node of the call tree.
#[derive(Clone, Debug)]
pub struct TreeNode {
    /// Function name (the root is `all`).
    pub name: String,
    /// Parent index (`usize::MAX` for the root).
    pub parent: usize,
    /// Children indices.
    pub children: Vec<usize>,
    /// Cost of this node and everything it called.
    pub inclusive: Costs,
    /// Cost of this node's own instructions.
    pub self_cost: Costs,
}

/// A resolved profile.
#[derive(Clone, Debug)]
pub struct Profile {
    /// Call tree; index 0 is the root (the whole run).
    pub tree: Vec<TreeNode>,
    /// Cost per (file, line) of the innermost source frame; code at DWARF line 0 is
    /// charged to its nearest located neighbour ([`ATTRIBUTION`]).
    pub lines: BTreeMap<(String, u32), Costs>,
    /// The part of each line's cost that is line-0 code charged to it.
    pub attributed: BTreeMap<(String, u32), Costs>,
    /// Cost per full stack (outermost first), for folded/speedscope output.
    pub stacks: BTreeMap<Vec<Frame>, Costs>,
    /// True if the costs are cycles (timing mode), false for instructions.
    pub cycles: bool,
}

impl Profile {
    /// Resolves `p`'s samples with `dbg` (inline frames, lines) and `exe` (symbols).
    pub fn build(p: &Profiler, dbg: Option<&DebugInfo>, exe: Option<&Executable>) -> Profile {
        let mut cache: HashMap<u32, Vec<Frame>> = HashMap::new();
        let mut resolve = |pc: u32| -> Vec<Frame> {
            cache
                .entry(pc)
                .or_insert_with(|| frames_at(pc, dbg, exe))
                .clone()
        };
        let mut stacks: BTreeMap<Vec<Frame>, Costs> = BTreeMap::new();
        let mut lines: BTreeMap<(String, u32), Costs> = BTreeMap::new();
        let mut attributed: BTreeMap<(String, u32), Costs> = BTreeMap::new();
        let mut node_frames: HashMap<u32, Vec<Frame>> = HashMap::new();
        for ((node, pc), costs) in p.samples() {
            let prefix = node_frames
                .entry(node)
                .or_insert_with(|| {
                    p.call_pcs(node)
                        .into_iter()
                        .flat_map(&mut resolve)
                        .collect()
                })
                .clone();
            let own = resolve(pc);
            if let Some(f) = own.last() {
                // Code without debug information is grouped by its function symbol.
                let file = f
                    .file
                    .clone()
                    .unwrap_or_else(|| format!("{NO_DEBUG_INFO} {}", f.name));
                let key = match (f.line, &f.file) {
                    (0, Some(_)) => nearest_line(pc, &own, &mut resolve).unwrap_or((file, 0)),
                    (l, _) => (file, l),
                };
                if f.line == 0 && key.1 != 0 {
                    add(attributed.entry(key.clone()).or_insert([0; KINDS]), &costs);
                }
                add(lines.entry(key).or_insert([0; KINDS]), &costs);
            }
            let mut stack = prefix;
            stack.extend(own);
            add(stacks.entry(stack).or_insert([0; KINDS]), &costs);
        }
        let mut tree = vec![TreeNode {
            name: "all".into(),
            parent: usize::MAX,
            children: Vec::new(),
            inclusive: [0; KINDS],
            self_cost: [0; KINDS],
        }];
        let mut index: HashMap<(usize, String), usize> = HashMap::new();
        for (stack, costs) in &stacks {
            let mut cur = 0;
            add(&mut tree[0].inclusive, costs);
            for f in stack {
                let next = match index.get(&(cur, f.name.clone())) {
                    Some(&n) => n,
                    None => {
                        let n = tree.len();
                        tree.push(TreeNode {
                            name: f.name.clone(),
                            parent: cur,
                            children: Vec::new(),
                            inclusive: [0; KINDS],
                            self_cost: [0; KINDS],
                        });
                        tree[cur].children.push(n);
                        index.insert((cur, f.name.clone()), n);
                        n
                    }
                };
                cur = next;
                add(&mut tree[cur].inclusive, costs);
            }
            add(&mut tree[cur].self_cost, costs);
        }
        let cycles = CostKind::ALL
            .iter()
            .any(|k| k.is_cycle() && tree[0].inclusive[k.index()] > 0);
        let mut prof = Profile {
            tree,
            lines,
            attributed,
            stacks,
            cycles,
        };
        // Children by decreasing inclusive cost, then name (deterministic output).
        for i in 0..prof.tree.len() {
            let mut ch = std::mem::take(&mut prof.tree[i].children);
            ch.sort_by(|&a, &b| {
                prof.weight(&prof.tree[b].inclusive)
                    .cmp(&prof.weight(&prof.tree[a].inclusive))
                    .then_with(|| prof.tree[a].name.cmp(&prof.tree[b].name))
            });
            prof.tree[i].children = ch;
        }
        prof
    }

    /// The single number a cost vector is ranked by: cycles (sum of the cycle kinds) in
    /// timing mode, instructions otherwise.
    pub fn weight(&self, c: &Costs) -> u64 {
        if self.cycles {
            CostKind::ALL
                .iter()
                .filter(|k| k.is_cycle())
                .map(|k| c[k.index()])
                .sum()
        } else {
            c[CostKind::Instruction.index()]
        }
    }

    /// Total weight of the run.
    pub fn total(&self) -> u64 {
        self.weight(&self.tree[0].inclusive)
    }

    /// `part` as a percentage of the whole run.
    pub fn percent(&self, part: u64) -> f64 {
        match self.total() {
            0 => 0.0,
            t => 100.0 * part as f64 / t as f64,
        }
    }

    /// Unit name of the weight: `thread-cycles` in timing mode (each hardware thread's
    /// cycles, summed over the threads: N live threads for C cycles weigh N x C), else
    /// `instructions`.
    pub fn unit(&self) -> &'static str {
        if self.cycles {
            "thread-cycles"
        } else {
            "instructions"
        }
    }

    /// Indices of the tree nodes named `name` (any depth).
    pub fn find(&self, name: &str) -> Vec<usize> {
        (0..self.tree.len())
            .filter(|&i| self.tree[i].name == name)
            .collect()
    }

    /// The indented call tree: `name inclusive%` per node, with self % and, in timing
    /// mode, the cost breakdown. Nodes under `min_percent` inclusive are left out.
    pub fn render_tree(&self, min_percent: f64) -> String {
        let mut s = String::new();
        let _ = write!(s, "# {} {} in total", self.total(), self.unit());
        if self.cycles {
            let _ = write!(s, " (cycles summed over the hardware threads)");
        }
        let _ = writeln!(s);
        self.render_node(&mut s, 0, 0, min_percent);
        s
    }

    fn render_node(&self, s: &mut String, i: usize, depth: usize, min: f64) {
        let n = &self.tree[i];
        let incl = self.percent(self.weight(&n.inclusive));
        if i != 0 && incl < min {
            return;
        }
        let _ = write!(
            s,
            "{}{} {:.2}  (self {:.2})",
            "| ".repeat(depth),
            n.name,
            incl,
            self.percent(self.weight(&n.self_cost))
        );
        if self.cycles {
            let parts: Vec<String> = CostKind::ALL
                .iter()
                .filter(|k| k.is_cycle() && n.inclusive[k.index()] > 0)
                .map(|k| format!("{} {}", k.name(), n.inclusive[k.index()]))
                .collect();
            let _ = write!(s, "  [{}]", parts.join(", "));
        }
        let _ = writeln!(s);
        for &c in &n.children {
            self.render_node(s, c, depth + 1, min);
        }
    }

    /// Folded stacks (`a;b;c weight` per line), the input of flame-graph tools.
    pub fn folded(&self) -> String {
        let mut agg: BTreeMap<String, u64> = BTreeMap::new();
        for (stack, c) in &self.stacks {
            let key: Vec<&str> = stack.iter().map(|f| f.name.as_str()).collect();
            *agg.entry(key.join(";")).or_insert(0) += self.weight(c);
        }
        let mut s = String::new();
        for (k, v) in agg.into_iter().filter(|(_, v)| *v > 0) {
            let k = if k.is_empty() { "??".to_string() } else { k };
            let _ = writeln!(s, "{k} {v}");
        }
        s
    }

    /// A speedscope "sampled" profile (https://www.speedscope.app file format).
    pub fn speedscope(&self, name: &str) -> String {
        let mut frames: Vec<&Frame> = Vec::new();
        let mut ids: HashMap<&Frame, usize> = HashMap::new();
        let mut samples = Vec::new();
        let mut weights = Vec::new();
        for (stack, c) in &self.stacks {
            let w = self.weight(c);
            if w == 0 {
                continue;
            }
            let idx: Vec<String> = stack
                .iter()
                .map(|f| {
                    let n = frames.len();
                    ids.entry(f)
                        .or_insert_with(|| {
                            frames.push(f);
                            n
                        })
                        .to_string()
                })
                .collect();
            samples.push(format!("[{}]", idx.join(",")));
            weights.push(w.to_string());
        }
        let frames: Vec<String> = frames
            .iter()
            .map(|f| match &f.file {
                Some(file) => format!(
                    "{{\"name\":{},\"file\":{},\"line\":{}}}",
                    json_str(&f.name),
                    json_str(file),
                    f.line
                ),
                None => format!("{{\"name\":{}}}", json_str(&f.name)),
            })
            .collect();
        format!(
            "{{\"$schema\":\"https://www.speedscope.app/file-format-schema.json\",\
             \"shared\":{{\"frames\":[{}]}},\"profiles\":[{{\"type\":\"sampled\",\
             \"name\":{},\"unit\":\"none\",\"startValue\":0,\"endValue\":{},\
             \"samples\":[{}],\"weights\":[{}]}}],\"name\":{},\"activeProfileIndex\":0,\
             \"exporter\":\"trax\"}}\n",
            frames.join(","),
            json_str(name),
            self.total(),
            samples.join(","),
            weights.join(","),
            json_str(name),
        )
    }

    /// Per-source-line costs next to the source text (files by decreasing cost; lines
    /// in order). `dbg` supplies the source text.
    pub fn annotate(&self, dbg: Option<&DebugInfo>) -> String {
        let mut per_file: BTreeMap<&str, Vec<(u32, u64)>> = BTreeMap::new();
        for ((file, line), c) in &self.lines {
            let w = self.weight(c);
            if w > 0 {
                per_file.entry(file).or_default().push((*line, w));
            }
        }
        let mut files: Vec<(&str, Vec<(u32, u64)>)> = per_file.into_iter().collect();
        files.sort_by_key(|(f, l)| (std::cmp::Reverse(l.iter().map(|x| x.1).sum::<u64>()), *f));
        let mut s = String::new();
        let moved: u64 = self.attributed.values().map(|c| self.weight(c)).sum();
        let _ = writeln!(
            s,
            "# {} per source line. {ATTRIBUTION} Lines marked * include such code ({:.2}% of \
             the {} in all).\n",
            self.unit(),
            self.percent(moved),
            self.unit()
        );
        for (file, lines) in files {
            let sum: u64 = lines.iter().map(|x| x.1).sum();
            let _ = writeln!(s, "{file}  ({:.2}% of {})", self.percent(sum), self.unit());
            for (line, w) in lines {
                if line == 0 {
                    // DWARF line 0: instructions the compiler ties to no source line
                    // (spills, merged blocks, jump tables), or code without line info.
                    let what = if file.starts_with(NO_DEBUG_INFO) {
                        "(no line information)"
                    } else {
                        "(line 0: code the compiler ties to no source line)"
                    };
                    let _ = writeln!(s, "{w:>12} {:>6.2}%      - | {what}", self.percent(w));
                    continue;
                }
                let text = dbg
                    .and_then(|d| d.source_line(file, line))
                    .unwrap_or_default();
                let key = (file.to_string(), line);
                let mark = if self.attributed.contains_key(&key) {
                    '*'
                } else {
                    ' '
                };
                let _ = writeln!(
                    s,
                    "{w:>12} {:>6.2}%{mark} {line:>5} | {}",
                    self.percent(w),
                    text.trim_end()
                );
            }
            let _ = writeln!(s);
        }
        s
    }
}

/// How line-0 code is attributed, as [`Profile::annotate`] states it.
pub const ATTRIBUTION: &str = "Code the compiler ties to no source line (DWARF line 0: \
register spills and reloads, constants, instructions the optimiser merged from several \
lines) is charged to the nearest instruction of the same inlined instance of the same \
function that has a line: the next one within 256 instructions, else the previous one within \
256; failing that, to the nearest such instruction of the same function in another instance \
(inlined elsewhere); failing that (a function without any located code, such as a \
derived method), to the line that calls or inlines it; what has none stays on `line 0`.";

/// Instructions [`nearest_line`] looks ahead and back.
const ATTRIBUTION_REACH: u32 = 256;

/// The (file, line) of the nearest instruction to `pc` (first ahead, then back, within
/// [`ATTRIBUTION_REACH`]) in the same function instance as `own` (the same inline chain:
/// function names and call-site lines), whose own line is not 0; else in the same function;
/// else the caller's call site ([`ATTRIBUTION`]).
fn nearest_line(
    pc: u32,
    own: &[Frame],
    resolve: &mut dyn FnMut(u32) -> Vec<Frame>,
) -> Option<(String, u32)> {
    let same_instance = |other: &[Frame]| {
        other.len() == own.len()
            && other.iter().zip(own).enumerate().all(|(i, (a, b))| {
                a.name == b.name && a.file == b.file && (i + 1 == own.len() || a.line == b.line)
            })
    };
    let inner = own.last()?;
    let same_function = |other: &[Frame]| {
        other
            .last()
            .is_some_and(|a| a.name == inner.name && a.file == inner.file)
    };
    let near = || {
        let ahead = (1..=ATTRIBUTION_REACH).map(move |k| pc.checked_add(4 * k));
        let back = (1..=ATTRIBUTION_REACH).map(move |k| pc.checked_sub(4 * k));
        ahead.chain(back).flatten()
    };
    let lined = |f: &[Frame]| f.last().map(|f| f.line).filter(|l| *l != 0);
    for strict in [true, false] {
        for p in near() {
            let f = resolve(p);
            let ok = if strict {
                same_instance(&f)
            } else {
                same_function(&f)
            };
            if let (true, Some(l)) = (ok, lined(&f)) {
                return Some((inner.file.clone()?, l));
            }
        }
    }
    // The enclosing statement: where the caller calls (or inlines) this function.
    let caller = own.len().checked_sub(2).map(|i| &own[i])?;
    Some((caller.file.clone()?, caller.line)).filter(|(_, l)| *l != 0)
}

/// How [`Profile::annotate`] names code without debug information (then its symbol).
pub const NO_DEBUG_INFO: &str = "(no debug information)";

fn add(a: &mut Costs, b: &Costs) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

/// Source frames at `pc`, outermost first.
fn frames_at(pc: u32, dbg: Option<&DebugInfo>, exe: Option<&Executable>) -> Vec<Frame> {
    let mut v: Vec<Frame> = Vec::new();
    if let Some(d) = dbg {
        let fs = d.frames(pc);
        for f in fs.iter().rev() {
            let name = match &f.function {
                Some(n) => short_name(n),
                None => symbol(pc, exe),
            };
            v.push(Frame {
                name,
                file: f.file.clone(),
                line: f.line,
            });
        }
    }
    if v.is_empty() {
        v.push(Frame {
            name: symbol(pc, exe),
            file: None,
            line: 0,
        });
    }
    v
}

fn symbol(pc: u32, exe: Option<&Executable>) -> String {
    exe.and_then(|e| e.symbol_at(pc))
        .map(|(s, _)| short_name(&crate::crash::demangle(&s.name)))
        .unwrap_or_else(|| format!("{pc:#010x}"))
}

/// `a::b::Type::method` -> `Type::method`; a trailing `::h<hash>` is dropped; `<...>`
/// groups are kept whole. Demangled C++ names (with a parameter list) are kept whole: their
/// namespaces are part of the name (a Rust path's first part is just the crate), and the
/// parameters tell overloads apart.
pub fn short_name(name: &str) -> String {
    if is_cpp_name(name) {
        return name.to_string();
    }
    let mut parts: Vec<&str> = Vec::new();
    let (mut depth, mut start) = (0i32, 0usize);
    let b = name.as_bytes();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'<' | b'(' => depth += 1,
            b'>' | b')' => depth -= 1,
            b':' if depth == 0 && b.get(i + 1) == Some(&b':') => {
                parts.push(&name[start..i]);
                start = i + 2;
                i += 1;
            }
            _ => {}
        }
        i += 1;
    }
    parts.push(&name[start..]);
    if let Some(last) = parts.last() {
        if parts.len() > 1
            && last.len() == 17
            && last.starts_with('h')
            && last[1..].bytes().all(|c| c.is_ascii_hexdigit())
        {
            parts.pop();
        }
    }
    let n = parts.len();
    parts[n.saturating_sub(2)..].join("::")
}

/// True for a demangled C++ function name: it ends in a parameter list `(...)`, maybe
/// followed by qualifiers (`const`, `&`, `&&`, `volatile`).
fn is_cpp_name(name: &str) -> bool {
    let mut n = name.trim_end();
    loop {
        let before = n;
        for q in ["const", "volatile", "&&", "&"] {
            n = n.strip_suffix(q).unwrap_or(n).trim_end();
        }
        if n == before {
            break;
        }
    }
    n.ends_with(')') && !n.starts_with('(')
}

fn json_str(s: &str) -> String {
    let mut o = String::with_capacity(s.len() + 2);
    o.push('"');
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            '\n' => o.push_str("\\n"),
            c if (c as u32) < 0x20 => {
                let _ = write!(o, "\\u{:04x}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_names() {
        assert_eq!(short_name("kernel::Vec3::dot"), "Vec3::dot");
        assert_eq!(short_name("trax_main"), "trax_main");
        assert_eq!(short_name("a::b::h0123456789abcdef"), "a::b");
        assert_eq!(
            short_name("<k::V as core::ops::Add>::add"),
            "<k::V as core::ops::Add>::add"
        );
        // C++: namespaces and parameter lists stay.
        for n in [
            "outer::inner::S::go(int const*, unsigned int)",
            "outer::(anonymous namespace)::pick(int const*, unsigned int)",
            "trax::Vec3::dot(trax::Vec3) const",
            "shade::Array<unsigned int, 4u>::operator[](unsigned int) &&",
        ] {
            assert_eq!(short_name(n), n);
        }
    }

    #[test]
    fn json_escapes() {
        assert_eq!(json_str("a\"b\\\n"), "\"a\\\"b\\\\\\n\"");
    }
}
