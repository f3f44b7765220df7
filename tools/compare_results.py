"""Compares two result folders table by table (Parquet, polars): which numeric columns changed and by
how much (largest absolute and relative difference), so a change to the exact analysis or the Monte
Carlo can say which shipped numbers moved.

    python3 tools/compare_results.py BEFORE_DIR AFTER_DIR

Each directory holds one folder per experiment (results/NAME as `experiment NAME --out DIR/NAME`
writes it). Timing columns (`*_seconds`) are reported separately: they differ on every run.

A Monte Carlo mean that moved is also given in standard errors: |after - before| over
sqrt(se_before^2 + se_after^2), the standard error of the difference of two independent estimates,
which is what two runs on different random streams are (the largest, the median, and how many
exceed 3). The same draws give 0 everywhere.
"""

import math
import sys
from pathlib import Path

import polars as pl

TABLES = ["summary", "steps", "paired", "gains", "design_trace"]

# Each table's Monte Carlo means and their standard errors.
MEANS = {
    "summary": [("empirical_mean", "std_error")],
    "steps": [("mse_mean", "mse_std_error"), ("nees_mean", "nees_std_error"), ("nis_mean", "nis_std_error")],
    "paired": [("mean_diff", "std_error")],
}


def in_standard_errors(a: pl.DataFrame, b: pl.DataFrame, table: str) -> list[str]:
    """How far each moved Monte Carlo mean of `table` went, in standard errors of the difference."""
    out = []
    for mean, se in MEANS.get(table, []):
        if not all(c in a.columns and c in b.columns for c in (mean, se)):
            continue
        z = []
        for u, v, su, sv in zip(a[mean].to_list(), b[mean].to_list(), a[se].to_list(), b[se].to_list()):
            if None in (u, v, su, sv) or any(math.isnan(t) for t in (u, v, su, sv)) or u == v:
                continue
            d = math.hypot(su, sv)
            if d > 0:
                z.append(abs(v - u) / d)
        if z:
            z.sort()
            beyond = sum(1 for t in z if t > 3)
            out.append(
                f"{mean} moved {len(z)} values by up to {z[-1]:.2f} SE (median {z[len(z) // 2]:.2f}, {beyond} beyond 3 SE)"
            )
    return out


def compare(before: Path, after: Path) -> int:
    changed = 0
    for exp in sorted(p.name for p in before.iterdir() if p.is_dir()):
        for table in TABLES:
            fa, fb = before / exp / f"{table}.parquet", after / exp / f"{table}.parquet"
            if not fa.exists() and not fb.exists():
                continue
            if not (fa.exists() and fb.exists()):
                print(f"{exp}/{table}: present in only one of the two")
                changed += 1
                continue
            a, b = pl.read_parquet(fa), pl.read_parquet(fb)
            if a.height != b.height:
                print(f"{exp}/{table}: row counts differ ({a.height} vs {b.height})")
                changed += 1
                continue
            diffs = []
            # A column added or removed is a change; the columns both have are compared value by value.
            added = [c for c in b.columns if c not in a.columns]
            removed = [c for c in a.columns if c not in b.columns]
            if added:
                diffs.append("added columns " + ", ".join(added))
            if removed:
                diffs.append("removed columns " + ", ".join(removed))
            for col in [c for c in a.columns if c in b.columns]:
                if col.endswith("_seconds"):
                    continue
                ca, cb = a[col], b[col]
                if ca.dtype.is_numeric():
                    x, y = ca.cast(pl.Float64).to_list(), cb.cast(pl.Float64).to_list()
                    worst_abs, worst_rel, n = 0.0, 0.0, 0
                    for u, v in zip(x, y):
                        if u is None and v is None:
                            continue
                        if (u is None) != (v is None) or (math.isnan(u) != math.isnan(v)):
                            n += 1
                            worst_rel = math.inf
                            continue
                        if math.isnan(u) or u == v:
                            continue
                        n += 1
                        worst_abs = max(worst_abs, abs(u - v))
                        worst_rel = max(worst_rel, abs(u - v) / max(abs(u), abs(v)))
                    if n:
                        diffs.append(f"{col}: {n} values, max abs {worst_abs:.3g}, max rel {worst_rel:.3g}")
                elif not ca.equals(cb, null_equal=True):
                    diffs.append(f"{col}: values differ")
            if diffs:
                changed += 1
                print(f"{exp}/{table}: " + "; ".join(diffs + in_standard_errors(a, b, table)))
            else:
                print(f"{exp}/{table}: identical")
    return changed


if __name__ == "__main__":
    sys.exit(1 if compare(Path(sys.argv[1]), Path(sys.argv[2])) else 0)
