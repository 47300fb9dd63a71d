//! Finds the lexical error behind a failed tokenization: unclosed, mismatched or
//! unexpected delimiters and unterminated literals or comments, with every span rustc
//! names, so the diagnostic says what is wrong instead of "cannot parse string into token
//! stream".

/// A lexical problem, with byte offsets into the source.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LexProblem {
    /// End of file with delimiters still open (outermost first).
    Unclosed {
        /// Unclosed opening delimiters.
        open: Vec<usize>,
    },
    /// A closing delimiter that does not match the innermost open one.
    Mismatched {
        /// The closing delimiter.
        close: usize,
        /// The innermost open delimiter.
        unclosed: usize,
        /// An outer open delimiter the closing one would match.
        candidate: Option<usize>,
    },
    /// A closing delimiter with nothing open.
    Unexpected {
        /// The closing delimiter.
        close: usize,
        /// The last top-level pair of braces closed before it.
        last_pair: Option<(usize, usize)>,
    },
    /// A literal or block comment that runs to the end of the file.
    Unterminated {
        /// Where it starts.
        start: usize,
        /// What it is, in rustc's words (e.g. `double quote string`).
        what: &'static str,
    },
}

fn closer(open: u8) -> u8 {
    match open {
        b'(' => b')',
        b'[' => b']',
        _ => b'}',
    }
}

fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

/// Scans `src` for the first delimiter or literal problem; `None` when it finds none.
pub fn check(src: &str) -> Option<LexProblem> {
    scan(src).err()
}

fn scan(src: &str) -> Result<(), LexProblem> {
    let s = src.as_bytes();
    let n = s.len();
    let mut stack: Vec<usize> = Vec::new();
    let mut last_pair = None;
    let mut i = 0;
    while i < n {
        let c = s[i];
        match c {
            b'/' if s.get(i + 1) == Some(&b'/') => {
                while i < n && s[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if s.get(i + 1) == Some(&b'*') => {
                let start = i;
                let mut depth = 0;
                loop {
                    if i + 1 >= n {
                        return Err(LexProblem::Unterminated {
                            start,
                            what: "block comment",
                        });
                    }
                    if s[i] == b'/' && s[i + 1] == b'*' {
                        depth += 1;
                        i += 2;
                    } else if s[i] == b'*' && s[i + 1] == b'/' {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
            }
            b'"' => i = quoted(s, i, i + 1, "double quote string")?,
            b'\'' => {
                // A character literal, or a lifetime/label.
                let next = i + 1;
                if s.get(next) == Some(&b'\\') {
                    i = char_lit(s, i, "character literal")?;
                } else {
                    let w = src[next.min(n)..].chars().next().map_or(1, char::len_utf8);
                    if s.get(next + w) == Some(&b'\'') {
                        i = next + w + 1;
                    } else {
                        i = next;
                    }
                }
            }
            b'(' | b'[' | b'{' => {
                stack.push(i);
                i += 1;
            }
            b')' | b']' | b'}' => {
                match stack.last() {
                    None => {
                        return Err(LexProblem::Unexpected {
                            close: i,
                            last_pair,
                        })
                    }
                    Some(&o) if closer(s[o]) == c => {
                        stack.pop();
                        if stack.is_empty() && c == b'}' {
                            last_pair = Some((o, i));
                        }
                    }
                    Some(&o) => {
                        let candidate = stack.iter().rev().copied().find(|&p| closer(s[p]) == c);
                        return Err(LexProblem::Mismatched {
                            close: i,
                            unclosed: o,
                            candidate,
                        });
                    }
                }
                i += 1;
            }
            c if is_ident(c) => {
                let start = i;
                while i < n && is_ident(s[i]) {
                    i += 1;
                }
                let word = &s[start..i];
                let raw_prefix = matches!(word, b"r" | b"br" | b"cr");
                if raw_prefix && matches!(s.get(i), Some(b'"' | b'#')) {
                    let mut hashes = 0;
                    while s.get(i + hashes) == Some(&b'#') {
                        hashes += 1;
                    }
                    if s.get(i + hashes) == Some(&b'"') {
                        // Raw string: ends at `"` followed by as many `#`.
                        let mut j = i + hashes + 1;
                        loop {
                            if j >= n {
                                let what = if word == b"br" {
                                    "raw byte string"
                                } else {
                                    "raw string"
                                };
                                return Err(LexProblem::Unterminated { start, what });
                            }
                            if s[j] == b'"'
                                && j + hashes < n
                                && s[j + 1..=j + hashes].iter().all(|&h| h == b'#')
                            {
                                i = j + 1 + hashes;
                                break;
                            }
                            j += 1;
                        }
                    }
                    // Otherwise a raw identifier (`r#name`): the `#` is skipped next round.
                } else if matches!(word, b"b" | b"c") && s.get(i) == Some(&b'"') {
                    let what = if word == b"b" {
                        "double quote byte string"
                    } else {
                        "double quote string"
                    };
                    i = quoted(s, start, i + 1, what)?;
                } else if word == b"b" && s.get(i) == Some(&b'\'') {
                    i = char_lit(s, i, "byte constant")?;
                }
            }
            _ => i += 1,
        }
    }
    if stack.is_empty() {
        Ok(())
    } else {
        Err(LexProblem::Unclosed { open: stack })
    }
}

/// Skips a quoted string whose body starts at `body`; returns the offset after it.
fn quoted(s: &[u8], start: usize, body: usize, what: &'static str) -> Result<usize, LexProblem> {
    let mut j = body;
    while j < s.len() {
        match s[j] {
            b'\\' => j += 2,
            b'"' => return Ok(j + 1),
            _ => j += 1,
        }
    }
    Err(LexProblem::Unterminated { start, what })
}

/// Skips a character literal with an escape, starting at the quote `q`.
fn char_lit(s: &[u8], q: usize, what: &'static str) -> Result<usize, LexProblem> {
    let mut j = q + 1;
    while j < s.len() {
        match s[j] {
            b'\\' => j += 2,
            b'\'' => return Ok(j + 1),
            b'\n' => break,
            _ => j += 1,
        }
    }
    Err(LexProblem::Unterminated { start: q, what })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delimiters_inside_literals_comments_and_lifetimes_are_ignored() {
        let ok = [
            "fn f<'a>(x: &'a u8) -> char { '{' }",
            "fn f() { let s = \"}{)(\"; let r = r#\"\"}\"#; let b = b\"[\"; }",
            "fn f() { /* { /* nested } */ ( */ let c = '\\''; let d = b'}'; }",
            "fn f() { // }\n let r#type = 1; 'outer: loop { break 'outer; } }",
            "fn f() { let e = '\\u{7d}'; let s = \"\\\"}\"; let u = 'é'; }",
            "fn f() { let s = br##\"\"#}\"##; let c = c\"{\"; }",
        ];
        for src in ok {
            assert_eq!(check(src), None, "{src}");
        }
    }

    #[test]
    fn finds_each_kind_of_problem() {
        assert_eq!(
            check("fn f() {\n  if x { (\n}"),
            Some(LexProblem::Mismatched {
                close: 20,
                unclosed: 18,
                candidate: Some(16),
            })
        );
        assert_eq!(
            check("fn f() { g(1 }"),
            Some(LexProblem::Mismatched {
                close: 13,
                unclosed: 10,
                candidate: Some(7),
            })
        );
        assert_eq!(
            check("fn f() {\n  {\n}"),
            Some(LexProblem::Unclosed { open: vec![7] })
        );
        assert_eq!(
            check("fn f() {}\n}"),
            Some(LexProblem::Unexpected {
                close: 10,
                last_pair: Some((7, 8)),
            })
        );
        assert_eq!(
            check("fn f() { let s = \"ab; }"),
            Some(LexProblem::Unterminated {
                start: 17,
                what: "double quote string",
            })
        );
        assert_eq!(
            check("fn f() { let s = r#\"ab\"; }"),
            Some(LexProblem::Unterminated {
                start: 17,
                what: "raw string",
            })
        );
        assert_eq!(
            check("fn f() {} /* a /* b */"),
            Some(LexProblem::Unterminated {
                start: 10,
                what: "block comment",
            })
        );
    }

    /// Every prelude file tokenizes with `syn`, so the check must find nothing in it.
    #[test]
    fn no_false_alarms_on_the_prelude() {
        for (path, src) in trax_runtime::prelude::FILES {
            assert_eq!(check(src), None, "{path}");
        }
    }
}
