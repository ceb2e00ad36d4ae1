"""Single CCD queries of ../shared/data/ccd-queries (exact ground truth, many hand-crafted
degenerate ones): exact arithmetic has no false negative and no false positive, conservative
never misses a contact (float's errors are counted by `conecull bench ccd`, not asserted)."""

import numpy as np
import pytest

from conecull._core import ccd as C
from shared_data import DATA, N_CCD_QUERIES, N_CCD_QUERY_FILES, ccd_query_files, load_ccd_queries, params, require

ROOT = DATA / "ccd-queries"
FILES = ccd_query_files()
CASES = params(FILES, [f"{p.parent.parent.name}/{p.parent.name}/{p.name}" for p in FILES], ROOT)


def run(kind, pts, arithmetic):
    fn = C.vertex_face_ccd_rows if kind == "vf" else C.edge_edge_ccd_rows
    cols = [np.ascontiguousarray(pts[:, i]) for i in range(8)]
    return fn(*cols, arithmetic)


def test_the_data_is_all_there():
    """The parametrized tests below cover every file and query the data holds."""
    require(ROOT)
    assert len(FILES) == N_CCD_QUERY_FILES, f"{ROOT}: {len(FILES)} query files, expected {N_CCD_QUERY_FILES}"
    total = sum(len(load_ccd_queries(p)[2]) for p in FILES)
    assert total == N_CCD_QUERIES, f"{ROOT}: {total} queries, expected {N_CCD_QUERIES}"


@pytest.mark.parametrize("path", CASES)
def test_conservative_never_misses(path):
    require(ROOT)
    kind, pts, truth = load_ccd_queries(path)
    got = run(kind, pts, "conservative")
    fn = np.flatnonzero(truth & ~got)
    assert len(fn) == 0, f"{path}: false negatives at queries {fn[:10].tolist()}"
    fp = int((~truth & got).sum())
    print(f"{path.parent.parent.name}/{path.parent.name}/{path.name}: {len(truth)} queries, "
          f"{int(truth.sum())} true, conservative FP {fp}")


@pytest.mark.parametrize("path", CASES)
def test_exact_equals_ground_truth(path):
    require(ROOT)
    kind, pts, truth = load_ccd_queries(path)
    got = run(kind, pts, "exact")
    assert np.array_equal(got, truth), (f"{path}: FN at {np.flatnonzero(truth & ~got)[:10].tolist()}, "
                                        f"FP at {np.flatnonzero(~truth & got)[:10].tolist()}")


def test_bad_arithmetic():
    kind, pts = "vf", np.zeros((1, 8, 3))  # needs no data: only the argument is wrong
    with pytest.raises(ValueError, match="arithmetic: expected 'float', 'conservative' or 'exact'"):
        run(kind, pts[:1], "fast")
