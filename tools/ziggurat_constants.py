#!/usr/bin/env python3
"""The constants of the engine's ziggurat (src/sim/noise/ziggurat.rs, docs/architecture.md
"Drawing"): r, the start of the tail, and v, the area of each layer, for an n-layer ziggurat of the
unnormalized density f(x) = exp(-x^2/2) (Marsaglia and Tsang, J. Stat. Softw. 5(8), 2000).

The layers' edges run from x_1 = r by x_{i+1} = f^-1(v/x_i + f(x_i)) with v = r f(r) + int_r^inf f;
r is the root of the top layer's closure v/x_{n-1} + f(x_{n-1}) = f(0) = 1, found by bisection in 60-digit
arithmetic (mpmath). For n = 256 it gives the paper's r = 3.6541528853610088. Also printed: the
fast path's rejection rate (the share of tries |u X_i| >= X_{i+1}), and how much the closure moves
when v moves by one unit in the last place of a double (the factor by which the rounding of the
table's recursion reaches the top layer's area; tests/it/lane_draws.rs bounds it).

    python3 -m venv venv && venv/bin/pip install mpmath
    venv/bin/python tools/ziggurat_constants.py [--layers 1024]
"""
import argparse

from mpmath import erfc, exp, log, mp, mpf, nstr, sqrt

mp.dps = 60


def f(x):
    return exp(-x * x / 2)


def volume(r):
    return r * f(r) + sqrt(mp.pi / 2) * erfc(r / sqrt(2))


def edges(r, v, n):
    """x_0 .. x_n, or None when the recursion leaves (0, 1) before the top (r too small)."""
    x = [v / f(r), r]
    for _ in range(2, n):
        y = v / x[-1] + f(x[-1])
        if y >= 1:
            return None
        x.append(sqrt(-2 * log(y)))
    return x + [mpf(0)]


def closure(r, v, n):
    """The top layer's area over v, minus 1 (None: the layers ran out before the top)."""
    x = edges(r, v, n)
    return None if x is None else x[n - 1] * (1 - f(x[n - 1])) / v - 1


def overshoot(r, n):
    """v/x_{n-1} + f(x_{n-1}) - 1: the height the top layer needs beyond f(0) = 1 (positive, or the
    layers running out first, when r is too small)."""
    v = volume(r)
    x = edges(r, v, n)
    return None if x is None else v / x[n - 1] + f(x[n - 1]) - 1


def solve(n):
    lo, hi = mpf(2), mpf(6)
    for _ in range(220):
        mid = (lo + hi) / 2
        z = overshoot(mid, n)
        if z is None or z > 0:
            lo = mid
        else:
            hi = mid
    return lo


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--layers", type=int, default=1024)
    n = ap.parse_args().layers
    r = solve(n)
    v = volume(r)
    x = edges(r, v, n)
    reject = sum(1 - x[i + 1] / x[i] for i in range(n)) / n
    ulp = mpf(2) ** -53
    print(f"layers {n}")
    print(f"r = {nstr(r, 20)}")
    print(f"v = {nstr(v, 20)}")
    print(f"fast-path rejection rate {nstr(reject, 5)} (top layer alone {nstr(mpf(1) / n, 5)})")
    print(f"closure with r, v exact {nstr(closure(r, v, n), 3)}, with r, v rounded to doubles "
          f"{nstr(closure(mpf(float(r)), mpf(float(v)), n), 3)}")
    print(f"closure per relative unit of v: {nstr(closure(r, v * (1 + ulp), n) / ulp, 5)}")


if __name__ == "__main__":
    main()
