#!/usr/bin/env python3
"""Derives the polynomial coefficients of include/uascma/common/lane_math.h (needs python3-mpmath).

Two kernels need a fit (exp, expm1 and cos use Taylor coefficients 1/k!, computed in the header):
- atan(u) = u + u^3 P(u^2) on |u| <= 1/2 (the reduction of atan and atan2),
- asin(r) = r + r^3 P(r^2) on 0 <= r <= 1/2 (asin's own range, and its reduction of 1/2 < |s| <= 1 to
  r = sqrt((1 - |s|) / 2)).
P is fitted by least squares on 4 (degree + 1) Chebyshev nodes of w = u^2 in [0, w_max], in 50-digit arithmetic, for
degrees 6, 7, ... until the relative error of the kernel (coefficients rounded to double, evaluated exactly) over
2,001 points is below 2e-17 (a tenth of an ulp); prints each degree's error, then the coefficients, constant term
first. The same method as scripts/fit-fast-atan.py of commit d4d6918 (since removed), there on |u| <= tan(pi/8).
"""
import mpmath as mp

mp.mp.dps = 50


def fit(name, function, edge):
    w_max = edge**2

    def target(w):
        if w == 0:
            return mp.diff(lambda t: function(t), 0, 3) / 6
        u = mp.sqrt(w)
        return (function(u) - u) / u**3

    for degree in range(6, 20):
        n = 4 * (degree + 1)
        nodes = [w_max / 2 * (1 - mp.cos(mp.pi * (k + 0.5) / n)) for k in range(n)]
        A = mp.matrix([[w**j for j in range(degree + 1)] for w in nodes])
        b = mp.matrix([target(w) for w in nodes])
        c = mp.lu_solve(A.T * A, A.T * b)
        coefficients = [float(c[j]) for j in range(degree + 1)]
        error = 0
        for k in range(1, 2001):
            u = edge * k / 2000
            p = mp.mpf(0)
            for coefficient in reversed(coefficients):
                p = p * u * u + coefficient
            error = max(error, abs(u + u**3 * p - function(u)) / function(u))
        print(f"{name} degree {degree}: relative error {mp.nstr(error, 3)}")
        if error < 2e-17:
            print(f"{name} coefficients:", ", ".join(repr(x) for x in coefficients))
            return


fit("atan", mp.atan, mp.mpf(1) / 2)
fit("asin", mp.asin, mp.mpf(1) / 2)


# Constants split into a leading part with trailing zero bits (so that small multiples of it are exact) and the
# rest rounded to a double; printed as C++ hexadecimal literals.
def split(name, value, bits):
    exponent = mp.floor(mp.log(value, 2))
    scale = mp.mpf(2) ** (bits - 1 - exponent)
    high = mp.floor(value * scale) / scale  # the leading `bits` bits of value
    low = value - high
    print(f"{name}: high {float(high).hex()} ({bits} bits), low {float(low).hex()}")
    return high, low


split("pi/4", mp.pi / 4, 51)  # atan2: m pi/4 exact for m <= 4
high1, rest = split("pi/2", mp.pi / 2, 33)  # cos: Cody-Waite, n pi/2 parts exact for n < 2^20
high2, rest2 = split("pi/2 rest", rest, 33)
print(f"pi/2 third part {float(rest2).hex()}")
print(f"pi/4 {float(mp.pi / 4).hex()}, pi/2 low {float(mp.pi / 2 - float(mp.pi / 2)).hex()}, 2/pi {float(2 / mp.pi).hex()}")
