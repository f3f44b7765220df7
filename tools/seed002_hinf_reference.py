#!/usr/bin/env python3
"""Numerical reference for seed 002 (Kogan-type duality paper): generalized H2 / H-inf-lambda filters.

Notation (one horizon, t0 = 0, tf = N):
  plant      x[t+1] = A[t] x[t] + B[t] v[t],  y[t] = C[t] x[t] + D[t] v[t],  z[t] = Cz[t] x[t],  t = 0..N-1
  weights    |x0 - xf0|^2_R + sum_{t=0}^{N-1} v[t]' G[t]^{-1} v[t] <= 1        (|a|^2_R = a' R^{-1} a)
  filter     xf[t+1] = A xf[t] + Th[t] (y[t] - C xf[t]),  xf[0] = xf0 (paper: 0),  zf = Cz xf
  error      e[t+1] = (A - Th C) e[t] + (B - Th D) v[t],  e[0] = x0 - xf0,  ez[t] = Cz e[t]
  operator   xi  = col(e[0], v[0], ..., v[N-1])                       (dim n + N nv)
             eta = col(ez[0], ..., ez[N-1], S^{1/2} e[N])              (dim N nz + n)
             eta = Psi xi,  K = blockdiag(R, G[0], ..., G[N-1])
  gen. H-inf norm (squared) = lambda_max(Psi K Psi')
      = sup (sum_{t=0}^{N-1}|ez[t]|^2 + e[N]' S e[N]) / (|e0|^2_R + sum_{t=0}^{N-1}|v[t]|^2_G)
  split (5.5): B G B' = GB, D G D' = GD > 0, B G D' = 0.

Run with numpy only; part (d) needs cvxpy (Clarabel) and is skipped if cvxpy is missing.
With experiment names as arguments (`seed002_hinf_reference.py hinf_tradeoff hinf_regression`) it
prints part (e) instead: lambda_min of those shipped experiments by bisection and by the design SDP.
"""
import numpy as np

np.set_printoptions(precision=6, suppress=False, linewidth=140)
rng = np.random.default_rng(2)

n, ny, nz, N = 3, 1, 2, 15
nv = n + ny                      # v = (process part, measurement part)


def spd(k, scale=1.0):
    Q = rng.standard_normal((k, k))
    return scale * (Q @ Q.T / k + 0.5 * np.eye(k))


def msqrt(P):
    w, V = np.linalg.eigh((P + P.T) / 2)
    return V @ np.diag(np.sqrt(np.clip(w, 0, None))) @ V.T


# ---------------- plant (time-varying) ----------------
A0 = rng.standard_normal((n, n))
A0 = 1.05 * A0 / max(abs(np.linalg.eigvals(A0)))          # slightly unstable nominal
A = [A0 + 0.05 * rng.standard_normal((n, n)) for _ in range(N)]
C = [rng.standard_normal((ny, n)) for _ in range(N)]
Cz = [np.eye(nz, n) + 0.1 * rng.standard_normal((nz, n)) for _ in range(N + 1)]
B1 = [rng.standard_normal((n, n)) * 0.5 for _ in range(N)]
D1 = [np.array([[1.0 + 0.2 * rng.standard_normal()]]) for _ in range(N)]
G1 = [spd(n, 0.5) for _ in range(N)]
G2 = [spd(ny, 0.3) for _ in range(N)]
B = [np.hstack([B1[t], np.zeros((n, ny))]) for t in range(N)]
D = [np.hstack([np.zeros((ny, n)), D1[t]]) for t in range(N)]
G = [np.block([[G1[t], np.zeros((n, ny))], [np.zeros((ny, n)), G2[t]]]) for t in range(N)]
GB = [B[t] @ G[t] @ B[t].T for t in range(N)]
GD = [D[t] @ G[t] @ D[t].T for t in range(N)]
assert all(np.allclose(B[t] @ G[t] @ D[t].T, 0) for t in range(N))
R = spd(n, 1.0)
S = spd(n, 2.0)
Sh = msqrt(S)
K = np.zeros((n + N * nv, n + N * nv))
K[:n, :n] = R
for t in range(N):
    K[n + t * nv:n + (t + 1) * nv, n + t * nv:n + (t + 1) * nv] = G[t]


# ---------------- (a) stacked error operator ----------------
def build_Psi(Th, Czl=None, Al=None, Bl=None, Cl=None, Dl=None, Shl=None):
    """Psi: col(e0, v[0..N-1]) -> col(Cz e[0], ..., Cz e[N-1], S^{1/2} e[N])."""
    Czl = Cz if Czl is None else Czl
    Al, Bl, Cl, Dl = (A if Al is None else Al), (B if Bl is None else Bl), (C if Cl is None else Cl), (D if Dl is None else Dl)
    Shl = Sh if Shl is None else Shl
    nx, nvv, nzz = Al[0].shape[0], Bl[0].shape[1], Czl[0].shape[0]
    nxi = nx + N * nvv
    E = np.zeros((nx, nxi)); E[:, :nx] = np.eye(nx)      # e[t] = E xi
    rows = []
    for t in range(N):
        rows.append(Czl[t] @ E)
        Ac, Bc = Al[t] - Th[t] @ Cl[t], Bl[t] - Th[t] @ Dl[t]
        E = Ac @ E
        E[:, nx + t * nvv: nx + (t + 1) * nvv] += Bc
    rows.append(Shl @ E)
    return np.vstack(rows)


def lmax(M):
    return float(np.linalg.eigvalsh((M + M.T) / 2)[-1])


def ghinf_norm(Th, **kw):
    Kl = kw.pop("K", K)
    Psi = build_Psi(Th, **kw)
    return lmax(Psi @ Kl @ Psi.T)


# ---------------- Kalman predictor = generalized H2 filter (5.6)-(5.7) ----------------
def kalman_predictor(Al=None, Cl=None, GBl=None, GDl=None, Rl=None):
    Al, Cl, GBl, GDl, Rl = (A if Al is None else Al), (C if Cl is None else Cl), (GB if GBl is None else GBl), (GD if GDl is None else GDl), (R if Rl is None else Rl)
    P = [Rl]; Th = []
    for t in range(N):
        Pt = P[-1]
        Th.append(Al[t] @ Pt @ Cl[t].T @ np.linalg.inv(Cl[t] @ Pt @ Cl[t].T + GDl[t]))
        Minv = np.linalg.inv(np.linalg.inv(Pt) + Cl[t].T @ np.linalg.inv(GDl[t]) @ Cl[t])
        P.append(Al[t] @ Minv @ Al[t].T + GBl[t])
    return Th, P


def error_cov(Th, Rl=None):
    """P[t] = covariance of e[t] when e0 ~ (0,R), v[t] ~ (0,G[t]) independent."""
    P = [R if Rl is None else Rl]
    for t in range(N):
        Ac, Bc = A[t] - Th[t] @ C[t], B[t] - Th[t] @ D[t]
        P.append(Ac @ P[-1] @ Ac.T + Bc @ G[t] @ Bc.T)
    return P


# ---------------- (b) H-inf-lambda recursion (5.9)-(5.10) ----------------
def hinf_lambda(lam, Al=None, Cl=None, Czl=None, GBl=None, GDl=None, Rl=None, Shl=None):
    """Returns (feasible, Th, P, reason). Conditions: lam I - Cz P[t] Cz' > 0 for t = 0..N-1
    (=> M[t] > 0), and lam I - S^{1/2} P[N] S^{1/2} > 0."""
    Al, Cl, Czl = (A if Al is None else Al), (C if Cl is None else Cl), (Cz if Czl is None else Czl)
    GBl, GDl, Rl, Shl = (GB if GBl is None else GBl), (GD if GDl is None else GDl), (R if Rl is None else Rl), (Sh if Shl is None else Shl)
    P = [Rl]; Th = []
    for t in range(len(Al)):
        Pt = P[-1]
        if np.linalg.eigvalsh(lam * np.eye(Czl[t].shape[0]) - Czl[t] @ Pt @ Czl[t].T)[0] <= 0:
            return False, Th, P, f"Cz P Cz' >= lam at t={t}"
        M = np.linalg.inv(Pt) + Cl[t].T @ np.linalg.inv(GDl[t]) @ Cl[t] - Czl[t].T @ Czl[t] / lam
        if np.linalg.eigvalsh((M + M.T) / 2)[0] <= 0:        # cannot happen if the line above passed
            return False, Th, P, f"M not > 0 at t={t}"
        Mi = np.linalg.inv(M)
        Th.append(Al[t] @ Mi @ Cl[t].T @ np.linalg.inv(GDl[t]))
        Pn = Al[t] @ Mi @ Al[t].T + GBl[t]
        P.append((Pn + Pn.T) / 2)
    if np.linalg.eigvalsh(lam * np.eye(Shl.shape[0]) - Shl @ P[-1] @ Shl)[0] <= 0:
        return False, Th, P, "terminal S^1/2 P[N] S^1/2 >= lam"
    return True, Th, P, "ok"


def bisect_lambda(feasible, lo=0.0, hi=1.0, tol=1e-10):
    while not feasible(hi):
        lo, hi = hi, 2 * hi
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
    return hi


def analysis_riccati_feasible(Th, lam):
    """Y[t+1] = Ac (Y^-1 - Cz'Cz/lam)^-1 Ac' + Bc G Bc', Y[0]=R, with Cz Y Cz' < lam, S^1/2 Y[N] S^1/2 < lam.
    Feasible iff gen. H-inf norm of the fixed-Th error system < lam (third independent computation)."""
    Y = R
    for t in range(N):
        if np.linalg.eigvalsh(lam * np.eye(nz) - Cz[t] @ Y @ Cz[t].T)[0] <= 0:
            return False
        Q = np.linalg.inv(np.linalg.inv(Y) - Cz[t].T @ Cz[t] / lam)
        Ac, Bc = A[t] - Th[t] @ C[t], B[t] - Th[t] @ D[t]
        Y = Ac @ Q @ Ac.T + Bc @ G[t] @ Bc.T
        Y = (Y + Y.T) / 2
    return np.linalg.eigvalsh(lam * np.eye(n) - Sh @ Y @ Sh)[0] > 0


def design_sdp(Al, Bl, Cl, Dl, Czl, Gl, Rl, Shl):
    """Design form of (4.7) with Th = X[t+1]^-1 Z: minimize lambda. Returns (lambda, status, Th)."""
    import cvxpy as cp
    Nl, nx, nyl, nvl, nzl = len(Al), Al[0].shape[0], Cl[0].shape[0], Bl[0].shape[1], Czl[0].shape[0]
    lam = cp.Variable()
    X = [cp.Constant(np.linalg.inv(Rl))] + [cp.Variable((nx, nx), symmetric=True) for _ in range(Nl)]
    Z = [cp.Variable((nx, nyl)) for _ in range(Nl)]
    cons = []
    for t in range(Nl):
        XA = X[t + 1] @ Al[t] - Z[t] @ Cl[t]
        XB = X[t + 1] @ Bl[t] - Z[t] @ Dl[t]
        L = cp.bmat([[-X[t], np.zeros((nx, nvl)), Czl[t].T, XA.T],
                     [np.zeros((nvl, nx)), -np.linalg.inv(Gl[t]), np.zeros((nvl, nzl)), XB.T],
                     [Czl[t], np.zeros((nzl, nvl)), -lam * np.eye(nzl), np.zeros((nzl, nx))],
                     [XA, XB, np.zeros((nx, nzl)), -X[t + 1]]])
        cons.append((L + L.T) / 2 << 0)
    T = cp.bmat([[X[Nl], Shl], [Shl, lam * np.eye(nx)]])
    cons.append((T + T.T) / 2 >> 0)
    pr = cp.Problem(cp.Minimize(lam), cons)
    pr.solve(solver=cp.CLARABEL)
    Th = [np.linalg.solve(X[t + 1].value, Z[t].value) for t in range(Nl)]
    return lam.value, pr.status, Th


def shipped(name):
    """(e) lambda_min of a shipped experiment (time-invariant A, B, D, Cz; C per step if given):
    bisection on (5.10) and the design SDP, the numbers tests/it/hinf_sdp.rs checks the Rust SDP
    against."""
    import pathlib
    import tomllib
    path = pathlib.Path(__file__).resolve().parent.parent / "experiments" / f"{name}.toml"
    e = tomllib.loads(path.read_text())
    pl, nom = e["plant"], e["nominal"]
    Nl = pl["horizon"]
    A1, B1, D1 = (np.array(pl[k], float) for k in ("A", "B", "D"))
    nx = A1.shape[0]
    Cz1 = np.array(pl.get("Cz", np.eye(nx)), float)
    Cs = [np.array(c, float) for c in pl["C_steps"]] if "C_steps" in pl else [np.array(pl["C"], float)] * Nl
    blocks = [np.array(nom[b], float) for b in pl["noise_blocks"]]
    Gl = np.zeros((sum(b.shape[0] for b in blocks),) * 2)
    o = 0
    for b in blocks:
        Gl[o:o + b.shape[0], o:o + b.shape[0]] = b
        o += b.shape[0]
    Rl = np.array(nom["x0"], float)
    Sl = np.array(next(f for f in e["filters"] if f.get("lambda") == "min")["terminal_weight"], float)
    Al, Bl, Dl, Czl = [A1] * Nl, [B1] * Nl, [D1] * Nl, [Cz1] * (Nl + 1)
    GBl, GDl = [B1 @ Gl @ B1.T] * Nl, [D1 @ Gl @ D1.T] * Nl
    lam_b = bisect_lambda(lambda l: hinf_lambda(l, Al, Cs[:Nl], Czl, GBl, GDl, Rl, msqrt(Sl))[0], tol=1e-12)
    lam_s, st, _ = design_sdp(Al, Bl, Cs[:Nl], Dl, Czl, [Gl] * Nl, Rl, msqrt(Sl))
    print(f"(e) {name}: lambda_min bisection={lam_b:.10f}, design SDP (cvxpy/Clarabel)={lam_s:.10f} ({st}),"
          f" rel.diff {abs(lam_s - lam_b) / lam_b:.1e}")


def main():
    print(f"plant: n={n}, ny={ny}, nz={nz}, nv={nv}, horizon t=0..{N} (N={N} steps), Psi is {N*nz+n}x{n+N*nv}")

    # ---- Theorem 2.1 sanity ----
    ThK, P2 = kalman_predictor()
    Psi = build_Psi(ThK)
    lm = lmax(Psi @ K @ Psi.T)
    Ki = np.linalg.inv(K)
    ratios = []
    for _ in range(2000):
        Lr = rng.standard_normal((K.shape[0], rng.integers(1, 5)))
        Kx = Lr @ Lr.T
        ratios.append(np.trace(Psi @ Kx @ Psi.T) / np.trace(Ki @ Kx))
    w, V = np.linalg.eigh(Psi @ K @ Psi.T)
    xi_star = K @ Psi.T @ V[:, -1]; xi_star /= np.sqrt(xi_star @ Ki @ xi_star)
    print(f"[Thm 2.1] Kalman predictor: lambda_max(Psi K Psi')={lm:.10g}; max random mean-square ratio={max(ratios):.6g} (<=);"
          f" worst deterministic xi on ellipsoid gives |Psi xi|^2={np.sum((Psi@xi_star)**2):.10g}")

    # ---- generalized H2 guarantee (Theorem 3.1 applied to (5.3)) ----
    Pcov = error_cov(ThK)
    dev = []
    for t in range(N + 1):
        if t < N:
            rowsz = Psi[t * nz:(t + 1) * nz]                         # ez[t] as a function of xi
        else:
            rowsz = Cz[N] @ np.linalg.pinv(Sh) @ Psi[N * nz:]        # ez[N] = Cz e[N]
        dev.append(abs(lmax(rowsz @ K @ rowsz.T) - lmax(Cz[t] @ P2[t] @ Cz[t].T)) / lmax(Cz[t] @ P2[t] @ Cz[t].T))
    print(f"[H2] max_t rel.diff worst |ez[t]|^2 over ellipsoid vs lambda_max(Cz P2 Cz'): {max(dev):.2e};"
          f" |P2 - Cov(e)| = {max(np.abs(P2[t]-Pcov[t]).max() for t in range(N+1)):.2e}")
    mineig = np.inf
    for _ in range(200):
        ThP = [ThK[t] + 0.3 * rng.standard_normal(ThK[t].shape) for t in range(N)]
        Pp = error_cov(ThP)
        mineig = min(mineig, min(np.linalg.eigvalsh(Pp[t] - P2[t])[0] for t in range(N + 1)))
    print(f"[H2] P_Theta[t] - P2[t] >= 0 for 200 perturbed gain sequences: min eigenvalue = {mineig:.3e}"
          f"  (so Kalman also minimises max_t lambda_max: it is generalized-H2 optimal)")
    gH2 = max(lmax(Cz[t] @ P2[t] @ Cz[t].T) for t in range(N + 1))
    print(f"[H2] generalized H2 level max_t lambda_max(Cz P2 Cz') = {gH2:.6g}")

    # ---- (a) norm of Kalman predictor ----
    nK = ghinf_norm(ThK)
    lamK = bisect_lambda(lambda l: analysis_riccati_feasible(ThK, l))
    print(f"(a) gen. H-inf norm of Kalman predictor: lambda_max(PsiKPsi')={nK:.10g}, analysis-Riccati bisection={lamK:.10g}")

    # ---- (b) smallest feasible lambda ----
    lam_min = bisect_lambda(lambda l: hinf_lambda(l)[0])
    print(f"(b) H-inf-lambda recursion: smallest feasible lambda = {lam_min:.10g}")
    for lam in [0.99 * lam_min, 0.5 * lam_min]:
        print(f"    lambda={lam:.6g}: feasible={hinf_lambda(lam)[0]} ({hinf_lambda(lam)[3]})")

    # ---- (c) designed filter norm < lambda; convergence to Kalman ----
    print("(c) lambda, norm of designed filter (lambda_max), norm/lambda, analysis-Riccati norm")
    res_c = {}
    for f in [1 + 1e-6, 1.001, 1.01, 1.1, 1.5, 3.0, 10.0]:
        lam = f * lam_min
        ok, Th, P, _ = hinf_lambda(lam)
        assert ok
        nm = ghinf_norm(Th)
        nr = bisect_lambda(lambda l: analysis_riccati_feasible(Th, l))
        res_c[f] = (lam, Th, nm)
        print(f"    {lam:.8g}  {nm:.8g}  {nm/lam:.6f}  {nr:.8g}   {'OK (<lambda, >=lambda_min)' if lam_min*(1-1e-8) <= nm < lam else 'VIOLATION'}")
    for lam in [1e2, 1e4, 1e6, 1e8]:
        ok, Th, P, _ = hinf_lambda(lam)
        dT = max(np.abs(Th[t] - ThK[t]).max() for t in range(N))
        dP = max(np.abs(P[t] - P2[t]).max() for t in range(N + 1))
        print(f"    lambda={lam:.0e}: feasible={ok}, max|Th_inf-Th_Kalman|={dT:.3e}, max|P_inf-P2|={dP:.3e}")

    # ---- regression (5.11)-(5.15) ----
    p = 3
    Phi = [rng.standard_normal((ny, p)) for _ in range(N)]
    Gr = [np.array([[0.2 + 0.1 * t / N]]) for t in range(N)]
    Rr = spd(p, 1.0)
    Al = [np.eye(p)] * N
    Bl = [np.zeros((p, ny))] * N
    Dl = [np.eye(ny)] * N
    GBl = [np.zeros((p, p))] * N
    Czr = [np.eye(p)] * (N + 1)
    Sr = np.eye(p)
    Kr = np.zeros((p + N * ny, p + N * ny)); Kr[:p, :p] = Rr
    for t in range(N):
        Kr[p + t:p + t + 1, p + t:p + t + 1] = Gr[t]
    # RLS (5.13)
    Pi = [np.linalg.inv(Rr)]; ThR = []
    for t in range(N):
        Pi.append(Pi[-1] + Phi[t].T @ np.linalg.inv(Gr[t]) @ Phi[t])
        ThR.append(np.linalg.inv(Pi[-1]) @ Phi[t].T @ np.linalg.inv(Gr[t]))
    ThKr, P2r = kalman_predictor(Al, Phi, GBl, Gr, Rr)
    print(f"[5.13] RLS gain P2[t+1] Phi' G^-1 vs Kalman (5.6) with A=I,C=Phi,GD=G,GB=0: max diff "
          f"{max(np.abs(ThR[t]-ThKr[t]).max() for t in range(N)):.2e}")
    feas_r = lambda l: hinf_lambda(l, Al, Phi, Czr, GBl, Gr, Rr, Sr)[0]
    lam_r = bisect_lambda(feas_r)
    lam = 1.2 * lam_r
    ok, ThH, PH, _ = hinf_lambda(lam, Al, Phi, Czr, GBl, Gr, Rr, Sr)
    # (5.15) form: P^-1[t+1] = P^-1[t] + Phi'G^-1Phi - I/lam, Th = P[t+1] Phi' G^-1
    Pi = np.linalg.inv(Rr); d515 = 0.0
    for t in range(N):
        Pi = Pi + Phi[t].T @ np.linalg.inv(Gr[t]) @ Phi[t] - np.eye(p) / lam
        d515 = max(d515, np.abs(np.linalg.inv(Pi) @ Phi[t].T @ np.linalg.inv(Gr[t]) - ThH[t]).max())
    kw = dict(Czl=Czr, Al=Al, Bl=Bl, Cl=Phi, Dl=Dl, Shl=Sr, K=Kr)
    nH = ghinf_norm(ThH, **dict(kw)); nRLS = ghinf_norm(ThR, **dict(kw))
    print(f"[5.15] H-inf regression (Cz=I, S=I): lambda_min={lam_r:.8g}; at lambda={lam:.6g}: (5.15) vs (5.9) gain diff {d515:.2e},"
          f" norm={nH:.8g} (<lambda: {nH < lam}); RLS norm={nRLS:.8g}")

    # ---- (d) SDP (4.7) ----
    try:
        import cvxpy as cp
    except ImportError:
        print("(d) cvxpy not installed: SDP skipped")
        return

    def sdp_analysis(Th):
        lam = cp.Variable()
        X = [cp.Constant(np.linalg.inv(R))] + [cp.Variable((n, n), symmetric=True) for _ in range(N)]
        cons = []
        Gi = [np.linalg.inv(G[t]) for t in range(N)]
        for t in range(N):
            Ac, Bc = A[t] - Th[t] @ C[t], B[t] - Th[t] @ D[t]
            L = cp.bmat([[Ac.T @ X[t + 1] @ Ac - X[t], Ac.T @ X[t + 1] @ Bc, Cz[t].T],
                         [Bc.T @ X[t + 1] @ Ac, Bc.T @ X[t + 1] @ Bc - Gi[t], np.zeros((nv, nz))],
                         [Cz[t], np.zeros((nz, nv)), -lam * np.eye(nz)]])
            cons.append((L + L.T) / 2 << 0)
        T = cp.bmat([[X[N], Sh], [Sh, lam * np.eye(n)]])
        cons.append((T + T.T) / 2 >> 0)
        pr = cp.Problem(cp.Minimize(lam), cons)
        pr.solve(solver=cp.CLARABEL)
        return lam.value, pr.status

    lsK, st = sdp_analysis(ThK)
    print(f"(d) SDP (4.7) [Clarabel], Kalman predictor: lambda*={lsK:.8g} ({st}) vs lambda_max={nK:.8g}, rel.diff {abs(lsK-nK)/nK:.1e}")
    for f in [1.01, 1.5]:
        lam, Th, nm = res_c[f]
        ls, st = sdp_analysis(Th)
        print(f"    H-inf-lambda filter (lambda={lam:.6g}): SDP={ls:.8g} ({st}) vs lambda_max={nm:.8g}, rel.diff {abs(ls-nm)/nm:.1e}")
    ld, st, ThD = design_sdp(A, B, C, D, Cz, G, R, Sh)
    print(f"    design SDP (X[t+1]Th=Z): min lambda={ld:.8g} ({st}) vs bisection lambda_min={lam_min:.8g}, rel.diff {abs(ld-lam_min)/lam_min:.1e};"
          f" lambda_max of the SDP filter={ghinf_norm(ThD):.8g}")


if __name__ == "__main__":
    import sys
    if sys.argv[1:]:
        for name in sys.argv[1:]:
            shipped(name)
    else:
        main()
