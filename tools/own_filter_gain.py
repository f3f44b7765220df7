#!/usr/bin/env python3
"""Writes experiments/own_filter.npz: the filter of experiments/own_filter.toml that a user brings.

It is what an engineer would do in numpy/scipy: take the plant of hinf_tradeoff.toml, solve the
discrete algebraic Riccati equation once for the nominal covariances, and keep the steady-state
one-step predictor gain K = A P Cᵀ (C P Cᵀ + D G Dᵀ)⁻¹ (a constant gain, where the time-varying Kalman
predictor of the `kalman` family adapts over the first steps). filterbench reads it with
`gain = { file = "own_filter.npz", key = "K" }` and `form = "predictor"`. P, the steady-state error
covariance the filter believes, is stored beside it as `P` for `claimed`.

    python3 tools/own_filter_gain.py        (numpy and scipy from PyPI)
"""
from pathlib import Path

import numpy as np
from scipy.linalg import solve_discrete_are

A = np.array([[1.0, 0.1, 0.0], [0.0, 0.95, 0.1], [0.0, 0.0, 0.9]])
B = np.array([[0.05, 0.0, 0.0, 0.0], [0.0, 0.1, 0.0, 0.0], [0.0, 0.0, 0.2, 0.0]])
C = np.array([[1.0, 0.0, 0.0]])
D = np.array([[0.0, 0.0, 0.0, 0.5]])
G = np.eye(4)  # the nominal process (3 × 3 identity) and measurement (1) covariances, stacked

Q, R = B @ G @ B.T, D @ G @ D.T
# The filtering DARE of (Aᵀ, Cᵀ) gives the predictor's steady-state prior covariance P.
P = solve_discrete_are(A.T, C.T, Q, R)
K = A @ P @ C.T @ np.linalg.inv(C @ P @ C.T + R)
out = Path(__file__).resolve().parent.parent / "experiments" / "own_filter.npz"
np.savez(out, K=K, P=P)
print(f"{out}: K = {K.ravel()}, tr P = {np.trace(P):.6f}")
