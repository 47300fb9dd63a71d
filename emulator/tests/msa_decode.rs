//! MSA decoder/disassembler checked against `llvm-mc --disassemble` as the oracle.
//!
//! Random words are generated per instruction format (fixed major/minor opcode bits,
//! random operand bits); every word is disassembled by llvm-mc and by our decoder and
//! the texts (whitespace-normalised) must agree, including which words are invalid.

use std::io::Write;
use std::process::{Command, Stdio};

use trax_emulator::msa::decode;

/// Small deterministic PRNG (xorshift64*), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 32) as u32
    }
}

/// Runs llvm-mc on the words (one per line); returns per word `Some(text)` or `None` if invalid.
fn llvm_mc(words: &[u32]) -> Vec<Option<String>> {
    let mut input = String::new();
    for w in words {
        let b = w.to_le_bytes();
        input.push_str(&format!(
            "0x{:02x} 0x{:02x} 0x{:02x} 0x{:02x}\n",
            b[0], b[1], b[2], b[3]
        ));
    }
    let mut child = Command::new("llvm-mc")
        .args([
            "--disassemble",
            "-triple=mipsel",
            "-mcpu=mips32r6",
            "-mattr=+msa",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("llvm-mc must be installed (LLVM 14 tools)");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let mut invalid = vec![false; words.len()];
    for line in stderr.lines() {
        // "<stdin>:LINE:COL: warning: invalid instruction encoding"
        if line.contains("invalid instruction encoding") {
            let n: usize = line.split(':').nth(1).unwrap().parse().unwrap();
            invalid[n - 1] = true;
        }
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    let mut texts = stdout
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|l| !l.is_empty() && !l.starts_with('.'));
    let res: Vec<Option<String>> = invalid
        .iter()
        .map(|&bad| if bad { None } else { texts.next() })
        .collect();
    assert!(
        texts.next().is_none(),
        "llvm-mc printed more instructions than expected"
    );
    res
}

/// (name, fixed-bit mask, fixed-bit value) for each MSA encoding format.
const FORMATS: &[(&str, u32, u32)] = &[
    ("I8", 0xFC00_003C, 0x7800_0000),
    ("I5", 0xFC00_003E, 0x7800_0006),
    ("BIT", 0xFC00_003E, 0x7800_0008),
    ("3R-0D..0F", 0xFC00_003C, 0x7800_000C),
    ("3R-10..13", 0xFC00_003C, 0x7800_0010),
    ("3R-14..15", 0xFC00_003E, 0x7800_0014),
    ("ELM", 0xFC00_003F, 0x7800_0019),
    ("ELM-special", 0xFC3F_003F, 0x783E_0019),
    ("3RF", 0xFC00_003C, 0x7800_0018),
    ("VEC/2R/2RF", 0xFC00_003F, 0x7800_001E),
    ("2R", 0xFFE0_003F, 0x7B00_001E),
    ("2RF", 0xFFE0_003F, 0x7B20_001E),
    ("MI10", 0xFC00_0038, 0x7800_0020),
    ("MSA-any", 0xFC00_0000, 0x7800_0000),
    ("COP1-branch", 0xFE00_0000, 0x4600_0000),
    ("COP1-branch-v", 0xFF60_0000, 0x4560_0000),
];

/// LLVM 14's MIPS disassembler prints the signed immediates of `maxi_s mini_s ceqi
/// clti_s clei_s` (5 bits) and `ldi` (10 bits) as unsigned numbers although its
/// assembler takes them signed (e.g. `ldi.b $w0, -5`); we print them signed, so
/// the oracle's text is converted before comparing.
fn signed_imm_fixup(text: &str) -> String {
    let mnemonic = text.split(['.', ' ']).next().unwrap_or("");
    let width = match mnemonic {
        "maxi_s" | "mini_s" | "ceqi" | "clti_s" | "clei_s" => 5,
        "ldi" => 10,
        _ => return text.to_string(),
    };
    let (head, last) = text.rsplit_once(' ').unwrap();
    let v: i64 = last.parse().unwrap();
    let v = if v >= 1 << (width - 1) {
        v - (1 << width)
    } else {
        v
    };
    format!("{head} {v}")
}

#[test]
fn decode_matches_llvm_mc() {
    let mut rng = Rng(0x1234_5678_9ABC_DEF1);
    let per_format = 3000;
    let mut words = Vec::new();
    for &(_, mask, value) in FORMATS {
        for _ in 0..per_format {
            words.push((rng.next() & !mask) | value);
        }
    }
    let oracle = llvm_mc(&words);
    let mut mismatches = Vec::new();
    let mut valid = 0;
    for (w, want) in words.iter().zip(&oracle) {
        let got = decode(*w).map(|i| i.to_string());
        if want.is_some() {
            valid += 1;
        }
        // COP1 words that are not MSA branches are valid FPU instructions for llvm-mc.
        let want = match want {
            Some(t) if *w >> 26 == 0x11 && !t.starts_with("bz.") && !t.starts_with("bnz.") => None,
            Some(t) => Some(signed_imm_fixup(t)),
            None => None,
        };
        if got != want {
            mismatches.push(format!("{w:#010x}: ours {got:?}, llvm-mc {want:?}"));
        }
    }
    assert!(
        valid > words.len() / 3,
        "too few valid words generated: {valid}"
    );
    assert!(
        mismatches.is_empty(),
        "{} mismatches of {}:\n{}",
        mismatches.len(),
        words.len(),
        mismatches
            .iter()
            .take(400)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn hand_checked_examples() {
    let cases: &[(u32, &str)] = &[
        (0x7802_080e, "addv.b $w0, $w1, $w2"),
        (0x7825_20d4, "sld.h $w3, $w4[$5]"),
        (0x7b36_a047, "ldi.h $w1, -300"),
        (0x78b3_0899, "copy_s.w $2, $w1[3]"),
        (0x7923_e899, "insert.h $w2[3], $sp"),
        (0x7bff_e863, "ld.d $w1, -8($sp)"),
        (0x4563_0004, "bz.v $w3, 20"),
        (0x7a03_105b, "fexdo.h $w1, $w2, $w3"),
    ];
    for &(w, text) in cases {
        assert_eq!(
            decode(w).map(|i| i.to_string()).as_deref(),
            Some(text),
            "{w:#x}"
        );
    }
    assert!(decode(0x0000_0000).is_none());
    assert!(decode(0x7bff_ffff).is_none());
}

/// C source exercising the MSA code LLVM 14 generates from generic vector code.
const VECTOR_C: &str = r#"
typedef float f4 __attribute__((vector_size(16)));
typedef int i4 __attribute__((vector_size(16)));
typedef double d2 __attribute__((vector_size(16)));
typedef short s8 __attribute__((vector_size(16)));
typedef signed char b16 __attribute__((vector_size(16)));
f4 mandel(f4 cr, f4 ci, int n, i4 *cnt) {
  f4 zr = {0}, zi = {0}; i4 c = {0};
  for (int k = 0; k < n; k++) {
    f4 zr2 = zr*zr, zi2 = zi*zi;
    i4 m = (zr2 + zi2) < 4.0f;
    c -= m;
    zi = 2.0f*zr*zi + ci; zr = zr2 - zi2 + cr;
  }
  *cnt = c; return zr;
}
void many(f4 *a, i4 *b, d2 *d, s8 *s, b16 *q, unsigned *u, int n) {
  for (int i = 0; i < n; i++) {
    a[i] = a[i] / (a[i+1] + 1.5f) - __builtin_sqrtf(a[i][0]);
    b[i] = (b[i] >> 3) ^ (b[i+1] << 2) | (b[i] & 7);
    b[i] = b[i] / (b[i+2] | 1) + b[i] % 3;
    d[i] = d[i] * d[i+1] - 3.0;
    s[i] = s[i] * s[i+1] + (s8){1,2,3,4,5,6,7,8};
    q[i] = __builtin_shufflevector(q[i], q[i+1], 0,17,2,19,4,21,6,23,8,25,10,27,12,29,14,31);
    a[i] = __builtin_convertvector(b[i], f4) + __builtin_convertvector(__builtin_convertvector(a[i], i4), f4);
    d[i] = __builtin_convertvector(__builtin_shufflevector(a[i], a[i], 0, 1), d2);
    b[i] = (i4){b[i][2], b[i][0], b[i][3], n};
    u[i] = (unsigned)b[i][1] + (unsigned)s[i][3] + (unsigned)q[i][5];
  }
  for (int i = 0; i < 4 * n; i++) u[i] = u[i] * 3u + (u[i] >> 2);
}
"#;

/// Code compiled by clang-14 for mips32r6 +msa: every MSA word in `.text` decodes to
/// the same text llvm-objdump prints.
#[test]
fn llvm_generated_code_decodes() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-msa-cc");
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("v.c");
    let obj = dir.join("v.o");
    std::fs::write(&src, VECTOR_C).unwrap();
    let st = Command::new("clang-14")
        .args([
            "--target=mipsel-linux-gnu",
            "-mcpu=mips32r6",
            "-mmsa",
            "-mfp64",
            "-O2",
            "-c",
            "-o",
        ])
        .arg(&obj)
        .arg(&src)
        .status()
        .expect("clang-14 must be installed");
    assert!(st.success());
    let out = Command::new("llvm-objdump")
        .args(["-d", "--mattr=+msa"])
        .arg(&obj)
        .output()
        .expect("llvm-objdump must be installed");
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&out.stdout);
    let mut checked = 0;
    for line in text.lines() {
        // "      14: 19 28 30 79  \tinsert.w\t$w0[0], $5"
        let Some((addr_bytes, rest)) = line.split_once('\t') else {
            continue;
        };
        let Some((_, bytes)) = addr_bytes.split_once(':') else {
            continue;
        };
        let b: Vec<u8> = bytes
            .split_whitespace()
            .filter_map(|h| u8::from_str_radix(h, 16).ok())
            .collect();
        if b.len() != 4 {
            continue;
        }
        let word = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        // objdump may append a symbol annotation such as " <mandel+0x1>".
        let rest = rest.split(" <").next().unwrap_or(rest);
        let want = rest.split_whitespace().collect::<Vec<_>>().join(" ");
        let is_msa = word >> 26 == 0x1E || (word >> 26 == 0x11 && want.contains("$w"));
        if !is_msa {
            continue;
        }
        let want = signed_imm_fixup(&want);
        // Branch targets are printed as absolute addresses by objdump; compare mnemonics only.
        let got = decode(word).map(|i| i.to_string());
        if want.starts_with("bz.") || want.starts_with("bnz.") {
            assert_eq!(
                got.as_deref().map(|g| g.split(',').next().unwrap()),
                want.split(',').next()
            );
        } else {
            assert_eq!(got.as_deref(), Some(want.as_str()), "{word:#010x}");
        }
        checked += 1;
    }
    assert!(
        checked > 50,
        "only {checked} MSA instructions found in clang output"
    );
}

/// Execution-unit classes used by the timing model.
#[test]
fn unit_classes() {
    use trax_runtime::isa::UnitClass;
    let cases: &[(u32, UnitClass)] = &[
        (0x7802_080e, UnitClass::IntAdd),    // addv.b
        (0x7a03_105b, UnitClass::Conv),      // fexdo.h
        (0x7bff_e863, UnitClass::Memory),    // ld.d
        (0x4563_0004, UnitClass::Branch),    // bz.v
        (0x78b3_0899, UnitClass::RegFile),   // copy_s.w
        (0x7825_20d4, UnitClass::Bitwise),   // sld.h
        (0x7800_001b, UnitClass::FpAdd),     // fadd.w
        (0x7880_001b, UnitClass::FpMul),     // fmul.w
        (0x78c0_001b, UnitClass::FpDiv),     // fdiv.w
        (0x7b26_001e, UnitClass::FpInvSqrt), // fsqrt.w
        (0x7880_001a, UnitClass::FpCmp),     // fceq.w
        (0x7b80_001b, UnitClass::FpMinMax),  // fmax.w
        (0x7a00_0012, UnitClass::IntDiv),    // div_s.b
        (0x7800_0012, UnitClass::IntMul),    // mulv.b
    ];
    for &(w, unit) in cases {
        let inst = decode(w).unwrap();
        assert_eq!(inst.unit(), unit, "{inst}");
    }
}

/// Our disassembly re-assembles (with `llvm-mc`) to the original word. This checks the
/// signed immediates we print where LLVM's disassembler prints unsigned ones. (Branches
/// are excluded: LLVM prints their offset relative to the branch, but parses it relative
/// to the delay slot.)
#[test]
fn disassembly_reassembles() {
    let mut rng = Rng(0x5EED);
    let mut words = Vec::new();
    while words.len() < 6000 {
        let w = 0x7800_0000 | (rng.next() & 0x03FF_FFFF);
        if decode(w).is_some() {
            words.push(w);
        }
    }
    let asm: String = words
        .iter()
        .map(|&w| format!("{}\n", decode(w).unwrap()))
        .collect();
    let mut child = Command::new("llvm-mc")
        .args([
            "-triple=mipsel",
            "-mcpu=mips32r6",
            "-mattr=+msa",
            "-show-encoding",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("llvm-mc must be installed (LLVM 14 tools)");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(asm.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("error"),
        "llvm-mc rejected our syntax:\n{}",
        &stderr[..stderr.len().min(3000)]
    );
    let encodings: Vec<u32> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split("encoding: [").nth(1))
        .map(|e| {
            let b: Vec<u8> = e
                .trim_end_matches(']')
                .split(',')
                .map(|h| u8::from_str_radix(h.trim().trim_start_matches("0x"), 16).unwrap())
                .collect();
            u32::from_le_bytes([b[0], b[1], b[2], b[3]])
        })
        .collect();
    assert_eq!(encodings.len(), words.len());
    let bad: Vec<String> = words
        .iter()
        .zip(&encodings)
        .filter(|(w, e)| w != e)
        .map(|(w, e)| format!("{w:#010x} -> `{}` -> {e:#010x}", decode(*w).unwrap()))
        .take(20)
        .collect();
    assert!(bad.is_empty(), "round trip failed:\n{}", bad.join("\n"));
}
