#!/usr/bin/env python3
"""Derives the coefficients of include/uascma/common/fast_angles.h (needs python3-mpmath).

atan(u) = u + u^3 P(u^2) on |u| <= tan(pi/8): P is fitted by least squares on 4 (degree + 1) Chebyshev nodes of
w = u^2 in [0, tan(pi/8)^2], in 50-digit arithmetic, for degrees 6, 7, ... until the relative error of the fit
(coefficients rounded to double, evaluated exactly) over 2,001 points is below 2e-17; prints each degree's error
and then the coefficients, constant term first (the header evaluates them by Horner from the last).
"""
import mpmath as mp

mp.mp.dps = 50
edge = mp.tan(mp.pi / 8)
w_max = edge**2


def target(w):
    if w == 0:
        return mp.mpf(-1) / 3
    u = mp.sqrt(w)
    return (mp.atan(u) - u) / u**3


for degree in range(6, 14):
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
        error = max(error, abs(u + u**3 * p - mp.atan(u)) / mp.atan(u))
    print(f"degree {degree}: relative error {mp.nstr(error, 3)}")
    if error < 2e-17:
        print("coefficients:", ", ".join(repr(x) for x in coefficients))
        break
