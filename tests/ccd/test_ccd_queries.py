"""Single CCD queries of ../shared/data/ccd-queries (exact ground truth, many hand-crafted
degenerate ones): exact arithmetic has no false negative and no false positive, conservative
never misses a contact, float's errors are counted."""

import numpy as np
import pytest

from conecull._core import ccd as C
from shared_data import ccd_query_files, load_ccd_queries

FILES = ccd_query_files() if True else []


def run(kind, pts, arithmetic):
    fn = C.vertex_face_ccd_rows if kind == "vf" else C.edge_edge_ccd_rows
    cols = [np.ascontiguousarray(pts[:, i]) for i in range(8)]
    return fn(*cols, arithmetic)


@pytest.mark.parametrize("path", FILES, ids=[f"{p.parent.parent.name}/{p.parent.name}/{p.name}" for p in FILES])
def test_conservative_never_misses(path):
    kind, pts, truth = load_ccd_queries(path)
    got = run(kind, pts, "conservative")
    fn = np.flatnonzero(truth & ~got)
    assert len(fn) == 0, f"{path}: false negatives at queries {fn[:10].tolist()}"
    fp = int((~truth & got).sum())
    print(f"{path.parent.parent.name}/{path.parent.name}/{path.name}: {len(truth)} queries, "
          f"{int(truth.sum())} true, conservative FP {fp}")


def test_float_errors_are_counted():
    """Float may miss or invent contacts; this only records how often (see the benchmark)."""
    total = fn = fp = 0
    for path in FILES:
        kind, pts, truth = load_ccd_queries(path)
        got = run(kind, pts, "float")
        total += len(truth)
        fn += int((truth & ~got).sum())
        fp += int((~truth & got).sum())
    print(f"float: {total} queries, FN {fn}, FP {fp}")
    assert total > 0


@pytest.mark.parametrize("path", FILES, ids=[f"{p.parent.parent.name}/{p.parent.name}/{p.name}" for p in FILES])
def test_exact_equals_ground_truth(path):
    kind, pts, truth = load_ccd_queries(path)
    got = run(kind, pts, "exact")
    assert np.array_equal(got, truth), (f"{path}: FN at {np.flatnonzero(truth & ~got)[:10].tolist()}, "
                                        f"FP at {np.flatnonzero(~truth & got)[:10].tolist()}")


def test_bad_arithmetic():
    kind, pts, _ = load_ccd_queries(FILES[0])
    with pytest.raises(ValueError, match="arithmetic: expected 'float', 'conservative' or 'exact'"):
        run(kind, pts[:1], "fast")
