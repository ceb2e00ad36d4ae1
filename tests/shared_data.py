"""Access to ../shared/data (real CCD data with exact ground truth), by path, never copied: the
loaders of conecull.datasets.shared, plus the tests' rules for when the data is absent.

Tests that need it skip with a clear reason when it is absent (a user's own clone); in CI it is
present, and there they must run: `.ci/run` sets CONECULL_CI=1 (as CI=true does),
which turns the skip into an error. Nothing here raises or skips at import time, so a module that
needs the data never stops the collection of the others.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from conecull.datasets import shared

SHARED = Path(os.environ.get("CONECULL_SHARED", Path(__file__).resolve().parents[1].parent / "shared"))
DATA = SHARED / "data"


# What the data holds (notes/data.md): if a listing finds fewer, the data moved, and the tests
# that iterate over it must fail rather than shrink to nothing.
N_CCD_QUERY_FILES = 24
N_CCD_QUERIES = 2824
N_SCALABLE_STEPS = 4


def _missing(path: Path) -> str:
    return f"shared data not found at {path} (clone the project next to ../shared, or set CONECULL_SHARED)"


def in_ci() -> bool:
    """CI (`.ci/run` sets CONECULL_CI=1): everything optional must be present and run."""
    return bool(os.environ.get("CONECULL_CI") or os.environ.get("CI"))


def require(path: Path) -> Path:
    """Inside a test: the path, or skip (an error where the data is required)."""
    if not path.exists():
        if in_ci():
            raise RuntimeError(_missing(path))
        pytest.skip(_missing(path))
    return path


def import_or_skip(module: str, reason: str):
    """An optional test dependency: skip without it, except where CI requires everything."""
    try:
        return __import__(module, fromlist=["_"])
    except ImportError:
        if in_ci():
            raise RuntimeError(f"{module} is required in CI: {reason}")
        pytest.skip(f"{module} not installed: {reason}")


def params(items, ids, path: Path, arity: int = 1):
    """Parametrize over the data's items. When the data is absent: one case "absent" that skips
    with the reason (instead of an empty parameter set, which would pass silently), or, where the
    data is required, runs; such a test starts with require(path), which then fails."""
    if path.exists():
        return [pytest.param(*(x if arity > 1 else (x,)), id=i) for x, i in zip(items, ids)]
    marks = () if in_ci() else pytest.mark.skip(reason=_missing(path))
    return [pytest.param(*([None] * arity), id="absent", marks=marks)]


def ccd_query_files():
    """The query CSVs, [] when the data is absent (collection-safe)."""
    return shared.ccd_query_files(DATA)


load_ccd_queries = shared.load_ccd_queries


def scalable_ccd_steps():
    """(scene, step) of every scalable-ccd step, [] when the data is absent (collection-safe)."""
    return shared.scalable_ccd_steps(DATA)


def load_scalable_step(scene: str, step: str):
    """conecull.datasets.shared.load_scalable_step on this checkout's data (skips without it)."""
    require(DATA / "scalable-ccd" / scene)
    return shared.load_scalable_step(DATA, scene, step)
