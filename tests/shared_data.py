"""Access to ../shared/data (real CCD data with exact ground truth), by path, never copied.

Tests that need it skip with a clear reason when it is absent (a user's own clone); in CI it is
present, and there they must run (CI=true turns the skip into an error).
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

SHARED = Path(os.environ.get("CONECULL_SHARED", Path(__file__).resolve().parents[1].parent / "shared"))
DATA = SHARED / "data"


def require(path: Path) -> Path:
    if not path.exists():
        msg = f"shared data not found at {path} (clone the project next to ../shared, or set CONECULL_SHARED)"
        if os.environ.get("CI"):
            raise RuntimeError(msg)
        pytest.skip(msg)
    return path


def exact_double(num: int, den: int) -> float:
    """num/den as a double, asserting that it is exactly representable (the data promises it)."""
    x = float(Fraction(num, den))
    if Fraction(x) != Fraction(num, den):
        raise ValueError(f"{num}/{den} is not exactly a double")
    return x


def ccd_query_files():
    root = require(DATA / "ccd-queries")
    return sorted(root.glob("*/*/*.csv"))


def load_ccd_queries(path: Path):
    """(kind 'vf'|'ee', points (q, 8, 3) float64, truth (q,) bool) from one CSV (8 rows a query)."""
    rows = np.loadtxt(path, delimiter=",", dtype=object, ndmin=2)
    rows = np.array([[int(x) for x in r] for r in rows], dtype=object)
    pts = np.array([[exact_double(r[0], r[1]), exact_double(r[2], r[3]), exact_double(r[4], r[5])] for r in rows])
    truth = np.array([int(r[6]) for r in rows[::8]], dtype=bool)
    kind = "vf" if path.parent.name == "vertex-face" else "ee"
    return kind, pts.reshape(-1, 8, 3), truth
