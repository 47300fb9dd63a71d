#!/usr/bin/env python3
"""Derives the polynomial coefficients and tables of `runtime/prelude/libm.rs`.

Usage: python3 runtime/prelude/tools/libm_coeffs.py   (needs mpmath: pip install mpmath)

Prints Rust source: every `const` polynomial coefficient and `static` table of libm.rs,
in the order libm.rs declares them, plus (as comments) the maximum error of each
polynomial *with its coefficients rounded to f64*, measured on a dense grid at 256-bit
precision. Deterministic: the same output on every run.

Polynomials are minimax (Remez exchange) for the weighted error named in each spec:
`rel` = relative error of the whole approximation F(x), `abs` = absolute error.
An approximation is `fixed(x) + sum_k c_k x^k` for the listed exponents k.
"""

import mpmath as mp

mp.mp.prec = 256


def remez(F, fixed, exps, a, b, weight, iters=60, grid=4000):
    """Minimax coefficients for F(x) ~ fixed(x) + sum c_k x^k on [a, b]."""
    n = len(exps)
    a, b = mp.mpf(a), mp.mpf(b)

    def w(x):
        if weight == "rel":
            return 1 / abs(F(x))
        return mp.mpf(1)

    def err(c, x):
        p = fixed(x) + mp.fsum(ci * x**k for ci, k in zip(c, exps))
        return (F(x) - p) * w(x)

    # Initial reference: Chebyshev-like points strictly inside (a, b], b included.
    ref = [a + (b - a) * (1 - mp.cos(mp.pi * (i + 1) / (n + 1))) / 2 for i in range(n + 1)]
    c = None
    E = None
    lo = a if a != 0 else (b - a) * mp.mpf(10) ** -6
    xs = [lo + (b - lo) * (mp.mpf(i) / grid) ** 1 for i in range(grid + 1)]
    for _ in range(iters):
        # Solve sum c_k x_j^k + (-1)^j E / w(x_j) = F(x_j) - fixed(x_j).
        A = mp.matrix(n + 1, n + 1)
        rhs = mp.matrix(n + 1, 1)
        for j, x in enumerate(ref):
            for i, k in enumerate(exps):
                A[j, i] = x**k
            A[j, n] = (-1) ** j / w(x)
            rhs[j] = F(x) - fixed(x)
        sol = mp.lu_solve(A, rhs)
        c = [sol[i] for i in range(n)]
        E = sol[n]
        # Locate the extrema of the error on the grid, refine each by golden search.
        es = [err(c, x) for x in xs]
        ext = []
        for i in range(len(xs)):
            left = es[i - 1] if i > 0 else None
            right = es[i + 1] if i + 1 < len(xs) else None
            v = es[i]
            if (left is None or abs(v) >= abs(left)) and (right is None or abs(v) >= abs(right)):
                if left is not None and right is not None:
                    x = refine(lambda t: abs(err(c, t)), xs[i - 1], xs[i + 1])
                else:
                    x = xs[i]
                ext.append((x, err(c, x)))
        # Keep alternating signs: merge neighbours of equal sign (largest wins).
        alt = []
        for x, e in ext:
            if alt and mp.sign(alt[-1][1]) == mp.sign(e):
                if abs(e) > abs(alt[-1][1]):
                    alt[-1] = (x, e)
            else:
                alt.append((x, e))
        while len(alt) > n + 1:
            # Drop the smaller end.
            if abs(alt[0][1]) < abs(alt[-1][1]):
                alt.pop(0)
            else:
                alt.pop()
        if len(alt) < n + 1:
            break
        newref = [x for x, _ in alt]
        m = max(abs(e) for _, e in alt)
        ref = newref
        if m - abs(E) < abs(E) * mp.mpf(10) ** -12:
            break
    return c


def refine(f, a, b):
    """Golden-section search for the maximum of f on [a, b]."""
    g = (mp.sqrt(5) - 1) / 2
    x1 = b - g * (b - a)
    x2 = a + g * (b - a)
    f1, f2 = f(x1), f(x2)
    for _ in range(60):
        if f1 > f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - g * (b - a)
            f1 = f(x1)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + g * (b - a)
            f2 = f(x2)
    return (a + b) / 2


def max_err(F, fixed, exps, c, a, b, weight, grid=20000):
    a, b = mp.mpf(a), mp.mpf(b)
    lo = a if a != 0 else (b - a) * mp.mpf(10) ** -9
    m = mp.mpf(0)
    for i in range(grid + 1):
        x = lo + (b - lo) * i / grid
        p = fixed(x) + mp.fsum(ci * x**k for ci, k in zip(c, exps))
        e = F(x) - p
        if weight == "rel":
            e /= F(x)
        m = max(m, abs(e))
    return m


def f64(v):
    return float(v)


def lit(v):
    """A Rust f64 literal that parses back to exactly this double."""
    r = repr(float(v))
    if "e" not in r and "." not in r and "inf" not in r:
        r += ".0"
    return r


def emit_poly(name, doc, F, fixed, exps, a, b, weight, tail=0):
    """Emits the coefficients of F(x) ~ fixed(x) + sum c_k x^k.

    With `tail` = t > 0 (intervals around 0, where every basis function vanishes at 0 and
    the Haar condition fails), the Remez exchange runs on the tail function
    G(x) = (F(x) - fixed(x)) / x^t with the basis x^(k - t) and absolute error instead.
    The reported error is always that of F itself, measured over the whole interval."""
    if tail:
        def G(x):
            # G is smooth at 0; keep away from the cancellation in F(x) - fixed(x).
            if abs(x) < mp.mpf(10) ** -20:
                x = mp.mpf(10) ** -20 if x >= 0 else -mp.mpf(10) ** -20
            return (F(x) - fixed(x)) / x**tail
        c = remez(G, lambda x: 0, [k - tail for k in exps], a, b, "abs")
    else:
        c = remez(F, fixed, exps, a, b, weight)
    cr = [mp.mpf(f64(ci)) for ci in c]
    e = max_err(F, fixed, exps, cr, a, b, weight)
    bits = -mp.log(e, 2) if e > 0 else mp.inf
    print(f"// {name}: {doc}; max {weight} error 2^-{float(bits):.1f} on [{float(a):.6g}, {float(b):.6g}]")
    for i, (ci, k) in enumerate(zip(cr, exps)):
        print(f"const {name}_{i}: f64 = {lit(ci)}; // x^{k}")
    print()


def dd(v):
    hi = float(v)
    lo = float(v - mp.mpf(hi))
    return hi, lo


def main():
    pi = mp.pi
    print("// ---- generated by runtime/prelude/tools/libm_coeffs.py ----")
    print()
    # f32 functions (evaluated in f64).
    emit_poly("SINF", "sin(r) = r + sum", mp.sin, lambda x: x, [3, 5, 7, 9], 0, pi / 4 * 1.001, "rel")
    emit_poly("COSF", "cos(r) = 1 + sum", mp.cos, lambda x: 1, [2, 4, 6, 8], 0, pi / 4 * 1.001, "rel")
    t8 = mp.tan(pi / 8)
    emit_poly("ATANF", "atan(t) = t + sum", mp.atan, lambda x: x, [3, 5, 7, 9, 11, 13, 15], 0, t8 * 1.001, "rel")
    emit_poly("EXP2F", "2^r = 1 + sum (|r| <= 1/128)", lambda x: mp.power(2, x), lambda x: 1, [1, 2, 3],
              -mp.mpf(1) / 128, mp.mpf(1) / 128, "rel", tail=1)
    smax = (mp.sqrt(2) - 1) / (mp.sqrt(2) + 1)
    emit_poly("LOGF", "ln((1+s)/(1-s)) = 2s + sum", lambda s: 2 * mp.atanh(s), lambda s: 2 * s,
              [3, 5, 7, 9, 11], 0, smax * 1.0001, "rel")
    # f64 functions.
    emit_poly("SIN", "sin(r) = r + sum", mp.sin, lambda x: x, [3, 5, 7, 9, 11, 13, 15], 0, pi / 4 * 1.001, "rel")
    emit_poly("COS", "cos(r) = 1 - r^2/2 + sum", mp.cos, lambda x: 1 - x * x / 2, [4, 6, 8, 10, 12, 14], 0,
              pi / 4 * 1.001, "rel")
    emit_poly("ATAN", "atan(t) = t + sum (|t| <= 1/32)", mp.atan, lambda x: x, [3, 5, 7, 9], 0,
              mp.mpf(1) / 32 * 1.001, "rel")
    emit_poly("ASIN", "asin(x) = x + sum (|x| <= 1/2)", mp.asin, lambda x: x,
              [3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31], 0, mp.mpf(1) / 2 * 1.0001, "rel")
    h = mp.log(2) / 128
    emit_poly("EXP", "e^r = 1 + r + r^2/2 + sum (|r| <= ln2/128)", mp.exp, lambda x: 1 + x + x * x / 2,
              [3, 4, 5, 6], -h * 1.01, h * 1.01, "rel", tail=3)
    emit_poly("EXP2", "2^r = 1 + sum (|r| <= 1/128)", lambda x: mp.power(2, x), lambda x: 1,
              [1, 2, 3, 4, 5, 6], -mp.mpf(1) / 128 * 1.001, mp.mpf(1) / 128 * 1.001, "rel", tail=1)
    emit_poly("LOGR", "ln((1+s)/(1-s)) = 2s + s*R(s), R = sum",
              lambda s: 2 * mp.atanh(s) / s - 2 if s != 0 else mp.mpf(0),
              lambda s: 0, [2, 4, 6, 8, 10, 12, 14, 16], 0, smax * 1.0001, "abs")
    emit_poly("LOGQ", "ln((1+s)/(1-s)) = 2s + 2s^3/3 + s^5*Q(s), Q = sum",
              lambda s: (2 * mp.atanh(s) - 2 * s - 2 * s**3 / 3) / s**5 if s != 0 else mp.mpf(2) / 5,
              lambda s: 0, [0, 2, 4, 6, 8, 10, 12, 14], 0, smax * 1.0001, "abs")
    # Tables.
    print("// 2^(j/64), j = 0..63, as (hi, lo) pairs: hi = f64(2^(j/64)), lo = f64(2^(j/64) - hi).")
    print("static EXP_TAB: [f64; 128] = [")
    for j in range(64):
        hi, lo = dd(mp.power(2, mp.mpf(j) / 64))
        print(f"    {lit(hi)}, {lit(lo)},")
    print("];")
    print()
    print("// atan(k/16), k = 0..16, as (hi, lo) pairs.")
    print("static ATAN_TAB: [f64; 34] = [")
    for k in range(17):
        hi, lo = dd(mp.atan(mp.mpf(k) / 16))
        print(f"    {lit(hi)}, {lit(lo)},")
    print("];")
    print()
    # 2/pi: 40 words of 32 bits, word k = bits 32k+1 .. 32k+32 after the binary point.
    mp.mp.prec = 1400
    v = 2 / mp.pi
    words = []
    for k in range(40):
        v *= 2**32
        w = int(mp.floor(v))
        words.append(w)
        v -= w
    print("// 2/pi in 32-bit words: word k holds the fraction bits 32k+1 ..= 32k+32.")
    print("static TWO_OVER_PI: [u32; 40] = [")
    for i in range(0, 40, 6):
        print("    " + " ".join(f"0x{w:08X}," for w in words[i:i + 6]))
    print("];")
    mp.mp.prec = 256
    print()
    consts = {
        "PIO2": pi / 2,
        "PI": pi,
        "LN2": mp.log(2),
        "LOG2E": 1 / mp.log(2),
        "LOG10E": 1 / mp.log(10),
        "LOG10_2": mp.log10(2),
        "TWO_THIRDS": mp.mpf(2) / 3,
        "THREE_PIO4": 3 * pi / 4,
    }
    for k, v in consts.items():
        hi, lo = dd(v)
        print(f"const {k}_HI: f64 = {lit(hi)};")
        print(f"const {k}_LO: f64 = {lit(lo)};")
    print(f"const INV_PIO2: f64 = {lit(2 / pi)};")
    # pi/2 in three 53-bit parts, for the fma reduction.
    p1 = float(pi / 2)
    p2 = float(pi / 2 - mp.mpf(p1))
    p3 = float(pi / 2 - mp.mpf(p1) - mp.mpf(p2))
    print(f"const PIO2_1: f64 = {lit(p1)};")
    print(f"const PIO2_2: f64 = {lit(p2)};")
    print(f"const PIO2_3: f64 = {lit(p3)};")
    # Constants whose high part has trailing zeros, so that k * HI is exact for the k used.
    for name, v, bits in [("LN2_42", mp.log(2), 42), ("LOG10_2_42", mp.log10(2), 42),
                          ("LN2_64", mp.log(2) / 64, 36)]:
        e = int(mp.floor(mp.log(v, 2)))
        hi = mp.floor(v * mp.mpf(2) ** (bits - 1 - e)) / mp.mpf(2) ** (bits - 1 - e)
        print(f"const {name}_HI: f64 = {lit(hi)}; // {bits} significant bits")
        print(f"const {name}_LO: f64 = {lit(v - hi)};")
    print(f"const INV_LN2_64: f64 = {lit(64 / mp.log(2))};")
    print(f"const TAN_PIO8: f64 = {lit(mp.tan(pi / 8))};")
    print()
    print("// ---- end of generated code ----")


if __name__ == "__main__":
    main()
