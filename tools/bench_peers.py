#!/usr/bin/env python3
"""Python peers of `filterbench bench` (issue 18): the same Monte Carlo as
experiments/bench_example2.toml -- seed 000 Example 2's 3-state plant, N steps, one Kalman filter at
the nominal covariances, Gaussian noise -- with numpy (vectorized over trials, gains precomputed)
and numba (compiled scalar loops with numpy's PCG64 Generator, trials split over one thread per
core). Prints trial-steps/s and the mean summed error J of each, so the mean can be checked against
filterbench's exact figure and the speed set beside `filterbench bench experiments/bench_example2.toml` run in the same session.
The numba peer runs twice: keeping J alone (the fastest peer, the one issue 28's ratio is taken
against), and keeping what filterbench's engine keeps on this experiment -- per step the mean and
variance of |e|^2, of the NEES e'P^-1 e/nx and of the NIS v'S^-1 v/ny -- which is the same work (its
NEES and NIS means over the steps are printed: both should be 1).

    python3 -m venv venv --system-site-packages && venv/bin/pip install numpy numba
    venv/bin/python tools/bench_peers.py [experiments/bench_example2.toml] [--trials 1000000]

Not part of `cargo test`. The plant semantics are filterbench's (docs/math.md §0): x[k+1] = A x[k] +
B w[k], y[k] = C x[k] + D w[k] measured from k = first_measurement, z = x, w ~ N(0, blkdiag(process,
measurement)), x0 ~ N(0, x0), J = sum over k = 0..N of |x[k] - xhat[k|k]|^2.
"""
import argparse
import time
import tomllib

import numpy as np


def load(path):
    with open(path, "rb") as f:
        t = tomllib.load(f)
    p, nom = t["plant"], t["nominal"]
    a, b, c, d = (np.array(p[k], float) for k in "ABCD")
    q = np.zeros((b.shape[1], b.shape[1]))
    q[:3, :3] = np.array(nom["process"], float)
    q[3:, 3:] = np.array(nom["measurement"], float)
    return dict(a=a, b=b, c=c, d=d, q=q, p0=np.array(nom["x0"], float), n=p["horizon"], first=p.get("first_measurement", 0))


def kalman_gains(m):
    """Filtered Kalman gains: xhat[k] = Af[k] xhat[k-1] + K[k] y[k] (Af[0] unused, xhat[0] = E x0 = 0
    before the first measurement), and the NEES and NIS weights filterbench reads: per step
    P[k|k]^-1 / nx and, from the first measurement on, S[k]^-1 / ny (zero before it)."""
    a, b, c, d, q = m["a"], m["b"], m["c"], m["d"], m["q"]
    nx, steps = a.shape[0], m["n"] + 1
    af = np.zeros((steps, nx, nx))
    k_gain = np.zeros((steps, nx, c.shape[0]))
    nees_w = np.zeros((steps, nx, nx))
    nis_w = np.zeros((steps, c.shape[0], c.shape[0]))
    p = m["p0"].copy()
    for k in range(steps):
        if k > 0:
            p = a @ p @ a.T + b @ q @ b.T
            af[k] = a
        if k >= m["first"]:
            s = c @ p @ c.T + d @ q @ d.T
            kk = p @ c.T @ np.linalg.inv(s)
            k_gain[k] = kk
            af[k] = (np.eye(nx) - kk @ c) @ af[k]
            p = (np.eye(nx) - kk @ c) @ p
            nis_w[k] = np.linalg.inv(s) / c.shape[0]
        nees_w[k] = np.linalg.inv(p) / nx
    return af, k_gain, nees_w, nis_w


def run_numpy(m, af, kg, trials, chunk=100_000, seed=1):
    rng = np.random.default_rng(seed)
    lw = np.linalg.cholesky(m["q"])
    l0 = np.linalg.cholesky(m["p0"])
    a, b, c, d = m["a"], m["b"], m["c"], m["d"]
    total, count = 0.0, 0
    for start in range(0, trials, chunk):
        t = min(chunk, trials - start)
        x = rng.standard_normal((t, 3)) @ l0.T
        xh = np.zeros_like(x)
        j = np.zeros(t)
        for k in range(m["n"] + 1):
            w = rng.standard_normal((t, lw.shape[0])) @ lw.T
            if k >= m["first"]:
                y = x @ c.T + w @ d.T
                xh = (xh @ af[k].T if k > 0 else xh) + y @ kg[k].T
            elif k > 0:
                xh = xh @ af[k].T
            e = x - xh
            j += np.einsum("ij,ij->i", e, e)
            x = x @ a.T + w @ b.T
        total += j.sum()
        count += t
    return total / count


def make_numba():
    import numba

    @numba.njit(fastmath=False, inline="always")
    def matvec(m, v, out, add):
        for r in range(m.shape[0]):
            s = out[r] if add else 0.0
            for q in range(m.shape[1]):
                s += m[r, q] * v[q]
            out[r] = s

    @numba.njit(fastmath=False, inline="always")
    def matvec_k(m, k, v, out, add):
        for r in range(m.shape[1]):
            s = out[r] if add else 0.0
            for q in range(m.shape[2]):
                s += m[k, r, q] * v[q]
            out[r] = s

    @numba.njit(fastmath=False, inline="always")
    def affine(m, v, n, u, out):
        """out = m v + n u (the plant's next state, its measurement)."""
        matvec(m, v, out, False)
        matvec(n, u, out, True)

    @numba.njit(fastmath=False, inline="always")
    def normal(g, l, u, out):
        """out = l u, u standard normal (l a covariance's Cholesky factor)."""
        for r in range(u.shape[0]):
            u[r] = g.standard_normal()
        matvec(l, u, out, False)

    @numba.njit(fastmath=False, inline="always")
    def start(g, l0, tmp, x, xh):
        """x[0] ~ N(0, P0) and the estimate before any measurement, E x[0] = 0."""
        normal(g, l0, tmp, x)
        xh[:] = 0.0

    @numba.njit(fastmath=False, inline="always")
    def trial(g, a, b, c, d, lw, l0, af, kg, first, steps, x, u, w, y, xh, tmp):
        start(g, l0, tmp, x, xh)
        j = 0.0
        for k in range(steps):
            normal(g, lw, u, w)
            if k > 0:
                matvec_k(af, k, xh, tmp, False)
                for r in range(x.shape[0]):
                    xh[r] = tmp[r]
            if k >= first:
                affine(c, x, d, w, y)
                matvec_k(kg, k, y, xh, True)
            for r in range(x.shape[0]):
                e = x[r] - xh[r]
                j += e * e
            affine(a, x, b, w, tmp)
            x[:] = tmp
        return j

    @numba.njit(fastmath=False, inline="always")
    def quad(m, k, v):
        s = 0.0
        for r in range(v.shape[0]):
            for q in range(v.shape[0]):
                s += v[r] * m[k, r, q] * v[q]
        return s

    @numba.njit(fastmath=False, inline="always")
    def trial_stats(g, a, b, c, d, lw, l0, kg, nees_w, nis_w, first, steps, x, u, w, y, xh, tmp, nu, acc):
        """One trial of the filter in its predictor-corrector form (the same estimates as `trial`),
        adding each step's |e|^2, NEES and NIS and their squares to acc[k]."""
        start(g, l0, tmp, x, xh)
        j = 0.0
        for k in range(steps):
            normal(g, lw, u, w)
            if k > 0:
                matvec(a, xh, tmp, False)
                xh[:] = tmp
            if k >= first:
                affine(c, x, d, w, y)
                matvec(c, xh, nu, False)
                for r in range(y.shape[0]):
                    nu[r] = y[r] - nu[r]
                matvec_k(kg, k, nu, xh, True)
                v = quad(nis_w, k, nu)
                acc[k, 4] += v
                acc[k, 5] += v * v
            e2 = 0.0
            for r in range(x.shape[0]):
                tmp[r] = x[r] - xh[r]
                e2 += tmp[r] * tmp[r]
            j += e2
            acc[k, 0] += e2
            acc[k, 1] += e2 * e2
            v = quad(nees_w, k, tmp)
            acc[k, 2] += v
            acc[k, 3] += v * v
            affine(a, x, b, w, tmp)
            x[:] = tmp
        return j

    @numba.njit(nogil=True, fastmath=False)
    def run_range_stats(g, a, b, c, d, lw, l0, kg, nees_w, nis_w, first, steps, trials):
        nx, nw, ny = a.shape[0], b.shape[1], c.shape[0]
        x, u, w, y = np.zeros(nx), np.zeros(nw), np.zeros(nw), np.zeros(ny)
        xh, tmp, nu = np.zeros(nx), np.zeros(nx), np.zeros(ny)
        acc = np.zeros((steps, 6))
        total, total2 = 0.0, 0.0
        for _ in range(trials):
            jt = trial_stats(g, a, b, c, d, lw, l0, kg, nees_w, nis_w, first, steps, x, u, w, y, xh, tmp, nu, acc)
            total += jt
            total2 += jt * jt
        return total, total2, acc

    @numba.njit(nogil=True, fastmath=False)
    def run_range(g, a, b, c, d, lw, l0, af, kg, first, steps, trials):
        nx, nw, ny = a.shape[0], b.shape[1], c.shape[0]
        x, u, w, y = np.zeros(nx), np.zeros(nw), np.zeros(nw), np.zeros(ny)
        xh, tmp = np.zeros(nx), np.zeros(nx)
        total = 0.0
        for _ in range(trials):
            total += trial(g, a, b, c, d, lw, l0, af, kg, first, steps, x, u, w, y, xh, tmp)
        return total

    def split(work, trials, seed):
        """`work(generator, count)` on one thread per core, the trials split between them, each with
        its own numpy Generator (PCG64 and numpy's ziggurat normals, 3.7 ns each inside numba;
        np.random's legacy Mersenne Twister and polar method cost 29 ns), the compiled loop
        releasing the GIL. Returns each thread's result."""
        from concurrent.futures import ThreadPoolExecutor

        threads = numba.config.NUMBA_NUM_THREADS
        gens = [np.random.Generator(np.random.PCG64(s)) for s in np.random.SeedSequence(seed).spawn(threads)]
        counts = [trials // threads + (i < trials % threads) for i in range(threads)]
        with ThreadPoolExecutor(threads) as ex:
            return list(ex.map(lambda gc: work(*gc), zip(gens, counts)))

    def run(a, b, c, d, lw, l0, af, kg, first, steps, trials, seed):
        """The mean summed error J over `trials` trials."""
        sums = split(lambda g, n: run_range(g, a, b, c, d, lw, l0, af, kg, first, steps, n), trials, seed)
        return sum(sums) / trials

    def run_stats(a, b, c, d, lw, l0, kg, nees_w, nis_w, first, steps, trials, seed):
        """`run` with filterbench's statistics: per step the mean and variance of |e|^2, NEES and NIS
        (by sums of the values and of their squares, per thread, added at the end), and J's mean and
        variance. Returns J's mean and the per-step sums divided by the trials."""
        work = lambda g, n: run_range_stats(g, a, b, c, d, lw, l0, kg, nees_w, nis_w, first, steps, n)
        parts = split(work, trials, seed)
        return sum(p[0] for p in parts) / trials, sum(p[2] for p in parts) / trials

    return run, run_stats


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("experiment", nargs="?", default="experiments/bench_example2.toml")
    ap.add_argument("--trials", type=int, default=1_000_000)
    ap.add_argument("--numpy-trials", type=int, default=200_000, help="numpy is slower: fewer trials")
    args = ap.parse_args()
    m = load(args.experiment)
    af, kg, nees_w, nis_w = kalman_gains(m)
    steps = m["n"] + 1
    lw = np.linalg.cholesky(m["q"])
    l0 = np.linalg.cholesky(m["p0"])
    print(f"{args.experiment}: N = {m['n']}, {steps} steps per trial")

    t0 = time.perf_counter()
    mean = run_numpy(m, af, kg, args.numpy_trials)
    dt = time.perf_counter() - t0
    print(f"numpy (vectorized over trials, 1e5 per chunk): {args.numpy_trials * steps / dt:.3e} trial-steps/s, "
          f"{args.numpy_trials} trials in {dt:.2f} s, mean J = {mean:.4f}")

    try:
        run, run_stats = make_numba()
    except ImportError:
        print("numba: not installed (pip install numba)")
        return
    import numba

    run(m["a"], m["b"], m["c"], m["d"], lw, l0, af, kg, m["first"], steps, 1000, 7)  # compile
    t0 = time.perf_counter()
    mean = run(m["a"], m["b"], m["c"], m["d"], lw, l0, af, kg, m["first"], steps, args.trials, 7)
    dt = time.perf_counter() - t0
    print(f"numba (compiled loops, trials split over {numba.config.NUMBA_NUM_THREADS} threads): "
          f"{args.trials * steps / dt:.3e} trial-steps/s, {args.trials} trials in {dt:.2f} s, mean J = {mean:.4f}")

    # The same work as filterbench's engine on this experiment, which keeps per step the mean and
    # variance of |e|^2, NEES and NIS besides J (the line above keeps J alone).
    stats_args = (m["a"], m["b"], m["c"], m["d"], lw, l0, kg, nees_w, nis_w, m["first"], steps)
    run_stats(*stats_args, 1000, 7)  # compile
    t0 = time.perf_counter()
    mean, per_step = run_stats(*stats_args, args.trials, 7)
    dt = time.perf_counter() - t0
    nis = per_step[m["first"]:, 4]
    print(f"numba with filterbench's statistics (per-step mean and variance of |e|^2, NEES and NIS): "
          f"{args.trials * steps / dt:.3e} trial-steps/s, {args.trials} trials in {dt:.2f} s, mean J = {mean:.4f}, "
          f"NEES mean over steps {per_step[:, 2].mean():.4f}, NIS {nis.mean():.4f}")


if __name__ == "__main__":
    main()
