#!/usr/bin/env python3
"""Writes the MATLAB fixtures of tests/it/array_files.rs (the Rust crates filterbench uses read
.mat files but do not write them): experiments/kalman_baseline.toml's plant matrices and nominal
covariances, as scipy.io.savemat writes them in MATLAB's v5 format, once uncompressed (`-v6`) and
once compressed (`-v7`, MATLAB's default), plus a complex array that must be refused.

    pip install numpy scipy && python3 tools/write_mat_fixtures.py
"""
import pathlib
import tomllib

import numpy as np
import scipy.io

ROOT = pathlib.Path(__file__).resolve().parent.parent
exp = tomllib.loads((ROOT / "experiments" / "kalman_baseline.toml").read_text())
arrays = {k: np.array(exp["plant"][k], dtype=np.float64) for k in ("A", "B", "C", "D")}
arrays.update({k: np.array(v, dtype=np.float64) for k, v in exp["nominal"].items()})
arrays["Zc"] = np.array([[1.0 + 2.0j, 0.0], [0.0, 1.0]])
out = ROOT / "tests" / "data" / "files"
out.mkdir(parents=True, exist_ok=True)
scipy.io.savemat(out / "kalman_baseline_v6.mat", arrays, format="5", do_compression=False)
scipy.io.savemat(out / "kalman_baseline_v7.mat", arrays, format="5", do_compression=True)
print("wrote", out / "kalman_baseline_v6.mat", "and", out / "kalman_baseline_v7.mat")
