#!/usr/bin/env python3
"""Python peers of `filterbench bench` (issue 18): the same Monte Carlo as
experiments/bench_example2.toml -- seed 000 Example 2's 3-state plant, N steps, one Kalman filter at
the nominal covariances, Gaussian noise -- with numpy (vectorized over trials, gains precomputed)
and numba (compiled scalar loops with numpy's PCG64 Generator, trials split over one thread per
core). Prints trial-steps/s and the mean summed error J of each, so the mean can be checked against
filterbench's exact figure and the speed set beside `filterbench bench experiments/bench_example2.toml` run in the same session.

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
    before the first measurement)."""
    a, b, c, d, q = m["a"], m["b"], m["c"], m["d"], m["q"]
    nx, steps = a.shape[0], m["n"] + 1
    af = np.zeros((steps, nx, nx))
    k_gain = np.zeros((steps, nx, c.shape[0]))
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
    return af, k_gain


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
    def trial(g, a, b, c, d, lw, l0, af, kg, first, steps, x, u, w, y, xh, tmp):
        for r in range(x.shape[0]):
            tmp[r] = g.standard_normal()
        matvec(l0, tmp, x, False)
        xh[:] = 0.0
        j = 0.0
        for k in range(steps):
            for r in range(u.shape[0]):
                u[r] = g.standard_normal()
            matvec(lw, u, w, False)
            if k > 0:
                matvec_k(af, k, xh, tmp, False)
                for r in range(x.shape[0]):
                    xh[r] = tmp[r]
            if k >= first:
                matvec(c, x, y, False)
                matvec(d, w, y, True)
                matvec_k(kg, k, y, xh, True)
            for r in range(x.shape[0]):
                e = x[r] - xh[r]
                j += e * e
            matvec(a, x, tmp, False)
            matvec(b, w, tmp, True)
            for r in range(x.shape[0]):
                x[r] = tmp[r]
        return j

    @numba.njit(nogil=True, fastmath=False)
    def run_range(g, a, b, c, d, lw, l0, af, kg, first, steps, trials):
        nx, nw, ny = a.shape[0], b.shape[1], c.shape[0]
        x, u, w, y = np.zeros(nx), np.zeros(nw), np.zeros(nw), np.zeros(ny)
        xh, tmp = np.zeros(nx), np.zeros(nx)
        total = 0.0
        for _ in range(trials):
            total += trial(g, a, b, c, d, lw, l0, af, kg, first, steps, x, u, w, y, xh, tmp)
        return total

    def run(a, b, c, d, lw, l0, af, kg, first, steps, trials, seed):
        """Trials split over one thread per core, each with its own numpy Generator (PCG64 and
        numpy's ziggurat normals, 3.7 ns each inside numba; np.random's legacy Mersenne Twister and
        polar method cost 29 ns), the compiled loop releasing the GIL."""
        from concurrent.futures import ThreadPoolExecutor

        threads = numba.config.NUMBA_NUM_THREADS
        gens = [np.random.Generator(np.random.PCG64(s)) for s in np.random.SeedSequence(seed).spawn(threads)]
        counts = [trials // threads + (i < trials % threads) for i in range(threads)]
        with ThreadPoolExecutor(threads) as ex:
            sums = ex.map(lambda gc: run_range(gc[0], a, b, c, d, lw, l0, af, kg, first, steps, gc[1]), zip(gens, counts))
            return sum(sums) / trials

    return run


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("experiment", nargs="?", default="experiments/bench_example2.toml")
    ap.add_argument("--trials", type=int, default=1_000_000)
    ap.add_argument("--numpy-trials", type=int, default=200_000, help="numpy is slower: fewer trials")
    args = ap.parse_args()
    m = load(args.experiment)
    af, kg = kalman_gains(m)
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
        run = make_numba()
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


if __name__ == "__main__":
    main()
