#!/usr/bin/python3
"""Prints the constants of portable_math.cpp from exact decimal arithmetic.

Each constant is split into doubles whose sum carries far more than 53 bits:
  * pi/2 in three 33-bit parts plus a tail, so k * part is exact for
    |k| < 2^20 (Cody-Waite reduction of sin/cos);
  * ln 2 in a 32-bit part plus a tail, so k * hi is exact for |k| < 2^21
    (reduction of exp/log);
  * atan(j/8), j = 1..8, and pi, pi/2 as the nearest double plus the nearest
    double to the rest.
Run: /usr/bin/python3 core/src/math/derive_constants.py
"""
from decimal import Decimal, getcontext
from fractions import Fraction

getcontext().prec = 120
PI = Decimal("3.14159265358979323846264338327950288419716939937510582097494459"
             "230781640628620899862803482534211706798214808651328230664709384")


def nearest_double(d):
    return float(Fraction(d))


def truncated(d, bits):
    """d rounded to `bits` significant bits (the rest zero), as a double."""
    f = Fraction(d)
    if f == 0:
        return 0.0
    e = 0
    a = abs(f)
    while a >= 1:
        a /= 2
        e += 1
    while a < Fraction(1, 2):
        a *= 2
        e -= 1
    scaled = round(a * 2**bits)
    return float(Fraction(scaled, 2**bits) * Fraction(2)**e) * (1 if f > 0 else -1)


def split(d, bits, parts):
    out, rest = [], Decimal(d)
    for _ in range(parts):
        p = truncated(rest, bits)
        out.append(p)
        rest -= Decimal(p)
    out.append(nearest_double(rest))
    return out


def hi_lo(d):
    hi = nearest_double(d)
    return hi, nearest_double(d - Decimal(hi))


def atan(x):
    # Halve the argument until the series converges fast: atan x = 2 atan(x / (1 + sqrt(1 + x^2))).
    doublings = 0
    while x > Decimal("0.05"):
        x = x / (1 + (1 + x * x).sqrt())
        doublings += 1
    total, term, n = Decimal(0), x, 1
    while abs(term) > Decimal(10) ** -110:
        total += term / n
        term *= -x * x
        n += 2
    return total * 2**doublings


def show(name, v):
    print(f"{name} = {v!r}  ({float.hex(v)})")


for i, p in enumerate(split(PI / 2, 33, 3)):
    show(f"pi/2 part {i}", p)
for i, p in enumerate(split(Decimal(2).ln(), 32, 1)):
    show(f"ln2 part {i}", p)
show("2/pi", nearest_double(2 / PI))
show("1/ln2", nearest_double(1 / Decimal(2).ln()))
for name, v in (("pi", PI), ("pi/2", PI / 2)):
    hi, lo = hi_lo(v)
    show(f"{name} hi", hi)
    show(f"{name} lo", lo)
for j in range(1, 9):
    hi, lo = hi_lo(atan(Decimal(j) / 8))
    print(f"atan({j}/8): {{{hi!r}, {lo!r}}}")
for name, v in (("pi/4", PI / 4), ("3pi/4", 3 * PI / 4), ("sqrt(1/2)", (Decimal(1) / 2).sqrt()),
                ("ln(DBL_MAX)", Decimal(float.fromhex("0x1.fffffffffffffp+1023")).ln()),
                ("ln(2^-1075)", Decimal(2).ln() * -1075)):
    show(name, nearest_double(v))


def bernoulli(n_max):
    """B_0..B_n_max as exact fractions (Akiyama-Tanigawa)."""
    out = []
    a = [Fraction(0)] * (n_max + 1)
    for m in range(n_max + 1):
        a[m] = Fraction(1, m + 1)
        for j in range(m, 0, -1):
            a[j - 1] = j * (a[j - 1] - a[j])
        out.append(a[0])
    return out


# tanh x = x + x^3 T(x^2): coefficient of x^(2n-1) is 2^2n (2^2n - 1) B_2n / (2n)!, n >= 2.
B = bernoulli(46)
fact = 1
facts = [1]
for i in range(1, 47):
    fact *= i
    facts.append(fact)
coeffs = [Fraction(2**(2 * n) * (2**(2 * n) - 1)) * B[2 * n] / facts[2 * n] for n in range(2, 24)]
print("tanh tail:", ", ".join(repr(float(c)) for c in coeffs))
