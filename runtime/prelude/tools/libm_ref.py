#!/usr/bin/env python3
"""Exact (mpmath) references for the f64 functions of `runtime/prelude/libm.rs`.

    python3 libm_ref.py gen [OUT]    writes the test data (default
                                     runtime/tests/data/libm_f64.txt) read by
                                     runtime/tests/libm_host.rs
    python3 libm_ref.py check DUMP   exact ULP errors of a dump written by
                                     `TRAX_LIBM_DUMP=DUMP cargo bench -p trax-runtime
                                     --bench libm_ulp` (lines `name x [y] got`, hex)

The data file has one line per point: `name x [y] hi lo`, x, y and hi as f64 bit
patterns in hex, hi = the exact value rounded to nearest, lo = (exact - hi) as a decimal
(hi = inf when the exact value overflows). Inputs: boundary cases, known hard cases and
pseudo-random points (fixed seed), so the output is the same on every run.
"""

import math
import os
import random
import struct
import sys

import mpmath as mp


def d2h(x):
    return "%016x" % struct.unpack("<Q", struct.pack("<d", x))[0]


def h2d(h):
    return struct.unpack("<d", struct.pack("<Q", int(h, 16)))[0]


FUN = {
    "sin": (1, lambda a: mp.sin(a[0])),
    "cos": (1, lambda a: mp.cos(a[0])),
    "sincos.sin": (1, lambda a: mp.sin(a[0])),
    "sincos.cos": (1, lambda a: mp.cos(a[0])),
    "tan": (1, lambda a: mp.tan(a[0])),
    "asin": (1, lambda a: mp.asin(a[0])),
    "acos": (1, lambda a: mp.acos(a[0])),
    "atan": (1, lambda a: mp.atan(a[0])),
    "exp": (1, lambda a: mp.exp(a[0])),
    "exp2": (1, lambda a: mp.power(2, a[0])),
    "log": (1, lambda a: mp.log(a[0])),
    "log2": (1, lambda a: mp.log(a[0], 2)),
    "log10": (1, lambda a: mp.log10(a[0])),
    "cbrt": (1, lambda a: mp.cbrt(a[0]) if a[0] >= 0 else -mp.cbrt(-a[0])),
    "atan2": (2, lambda a: mp.atan2(a[0], a[1])),
    "pow": (2, lambda a: mp.power(a[0], a[1])),
    "powi": (2, lambda a: mp.power(a[0], int(a[1]))),
    "hypot": (2, lambda a: mp.hypot(a[0], a[1])),
}


def exact(name, args):
    """The exact value (mpf) or None (NaN, complex, infinite inputs)."""
    if any(a != a or abs(a) == float("inf") for a in args):
        return None
    big = max([abs(a) for a in args] + [1.0])
    mp.mp.prec = 200 + max(0, int(mp.log(big, 2)))
    if name in ("pow", "powi"):
        mp.mp.prec += 64
    try:
        v = FUN[name][1]([mp.mpf(a) for a in args])
    except (ValueError, ZeroDivisionError):
        return None
    if isinstance(v, mp.mpc) or not mp.isfinite(v):
        return None
    return v


def round_double(v):
    """v rounded to the nearest double (ties to even), subnormals and overflow included."""
    if v == 0:
        return 0.0
    s = -1.0 if v < 0 else 1.0
    a = abs(v)
    e = int(mp.floor(mp.log(a, 2)))
    # Guard against log rounding.
    while mp.mpf(2) ** e > a:
        e -= 1
    while mp.mpf(2) ** (e + 1) <= a:
        e += 1
    q = max(e, -1022) - 52
    m = a / mp.mpf(2) ** q
    n = int(mp.floor(m))
    frac = m - n
    if frac > 0.5 or (frac == 0.5 and n % 2 == 1):
        n += 1
    if n == 2**53 and e >= 1023 or e > 1023:
        return s * float("inf")
    return s * math.ldexp(n, q)


def ulp(v):
    a = abs(v)
    e = int(mp.floor(mp.log(a, 2)))
    return mp.mpf(2) ** (max(e, -1022) - 52)


EDGES = [0.0, 5e-324, 2.2250738585072014e-308, 1e-300, 1e-20, 1e-8, 0.1, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0,
         10.0, 100.0, 1e10, 1e22, 1e100, 1e300, 1.7976931348623157e308,
         0.7853981633974483, 1.5707963267948966, 3.141592653589793, 1073741823.0, 1073741825.5,
         6381956970095103.0 * 2.0 ** 797, 5.319372648326541e+255, 1.1e-07, 0.9999999999999999,
         1.0000000000000002, 709.782712893384, -708.3964185322641, -745.1332191019411, -745.13,
         -744.4400719213812, 1023.9999999999999, -1022.0, -1073.5, -1074.0, -1074.9]

DOMAIN = {
    "sin": (-100, 100), "cos": (-100, 100), "sincos.sin": (-100, 100), "sincos.cos": (-100, 100),
    "tan": (-100, 100), "asin": (-1, 1), "acos": (-1, 1), "atan": (-20, 20), "exp": (-746, 710),
    "exp2": (-1076, 1024), "log": (0, 100), "log2": (0, 100), "log10": (0, 100), "cbrt": (-100, 100),
    "atan2": (-10, 10), "pow": (-4, 4), "powi": (-4, 4), "hypot": (-1e3, 1e3),
}


def rnd_double(r, lo, hi):
    k = r.randrange(3)
    if k == 0:
        return r.uniform(lo, hi)
    if k == 1:
        return (2.0 ** r.uniform(-1074, 1023.99)) * r.choice([-1.0, 1.0])
    while True:
        x = h2d("%016x" % r.getrandbits(64))
        if x == x and abs(x) != float("inf"):
            return x


def points(name, r, n):
    arity = FUN[name][0]
    lo, hi = DOMAIN[name]
    out = []
    if arity == 1:
        for x in EDGES:
            out.append((x,))
            out.append((-x,))
        for _ in range(n):
            out.append((rnd_double(r, lo, hi),))
        return out
    sel = [0.0, 1e-300, 0.5, 1.0, 2.0, 3.0, 1e10, 1e300, 1.7976931348623157e308, 5e-324]
    for x in sel:
        for y in sel:
            out.append((x, y))
            out.append((-x, -y))
    for _ in range(n):
        if name in ("pow", "powi") and r.random() < 0.75:
            x = r.uniform(-4, 4) if r.random() < 0.5 else 2.0 ** r.uniform(-60, 60)
            l2 = abs(float(mp.log(abs(x), 2))) if x != 0 else 1.0
            y = r.uniform(-1070, 1020) / max(l2, 1e-6)
            if name == "powi" or r.random() < 0.25:
                y = float(round(max(min(y, 2.0 ** 31 - 1), -2.0 ** 31)))
            out.append((x, y))
        else:
            x = rnd_double(r, lo, hi)
            y = rnd_double(r, lo, hi)
            if name == "powi":
                y = float(r.randrange(-2000, 2000))
            out.append((x, y))
    return out


def gen(path, n=100):
    r = random.Random(20260501)
    lines = []
    for name in FUN:
        for args in points(name, r, n):
            if name == "atan2" and 0.0 in args:
                continue  # signed zeros: the special-value tests
            v = exact(name, args)
            if v is None:
                continue
            hi = round_double(v)
            lo = 0.0 if abs(hi) == float("inf") or v == 0 else float(v - mp.mpf(hi))
            if hi == 0.0 and v != 0:
                # Exact value below half the smallest subnormal: rounds to a signed zero.
                hi = -0.0 if v < 0 else 0.0
                lo = float(v)
            if v == 0:
                continue
            lines.append(" ".join([name] + [d2h(a) for a in args] + [d2h(hi), "%.6e" % lo]))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("# generated by runtime/prelude/tools/libm_ref.py gen; name x [y] hi lo\n")
        f.write("\n".join(lines) + "\n")
    print(f"{len(lines)} points written to {path}")


def check(path):
    stats = {}
    for line in open(path):
        parts = line.split()
        if not parts or parts[0].startswith("#"):
            continue
        name = parts[0]
        args = [h2d(h) for h in parts[1:-1]]
        got = h2d(parts[-1])
        v = exact(name, args)
        if v is None or v == 0 or got != got or abs(got) == float("inf"):
            continue
        err = float(abs(mp.mpf(got) - v) / ulp(v))
        s = stats.setdefault(name, [0, 0.0, 0.0, ""])
        s[0] += 1
        s[2] += err
        if err > s[1]:
            s[1] = err
            s[3] = line.strip()
    print(f"{'function':12} {'points':>8} {'max ULP':>9} {'mean ULP':>9}  worst input")
    for name, (n, mx, sm, worst) in stats.items():
        print(f"{name:12} {n:8} {mx:9.4f} {sm / n:9.4f}  {worst}")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    if len(sys.argv) >= 2 and sys.argv[1] == "gen":
        out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "../../tests/data/libm_f64.txt")
        gen(os.path.normpath(out))
    elif len(sys.argv) == 3 and sys.argv[1] == "check":
        check(sys.argv[2])
    else:
        print(__doc__)
        sys.exit(2)


if __name__ == "__main__":
    main()
