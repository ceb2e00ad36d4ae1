"""The loaders of the real data (datasets/shared.py) on small hand-made files in its formats
(shared/notes/data.md), so these run without ../shared: a well-formed step and query file give
the contacts written into them; a damaged one is a ValueError naming the file (and row), never
a wrong ground truth (found by review: a flagged row with a face id beyond the mesh became a
contact with face -37375, a flag "no" counted as a contact, ids below their range picked other
edges, and a zero denominator raised ZeroDivisionError)."""

import json

import numpy as np
import pytest
import trimesh

from conecull.datasets.shared import load_ccd_queries, load_scalable_step

# Two triangles sharing edge (1, 2); n = 4 vertices, edges (ours, i < j, sorted): 0 (0, 1),
# 1 (0, 2), 2 (1, 2), 3 (1, 3), 4 (2, 3). Box ids: vertices 0..3, edges 4..8 (theirs, sorted
# by (larger, smaller), here the same order), faces 9, 10.
F = np.array([[0, 1, 2], [1, 3, 2]])
V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
VF = ([[3, 9], [0, 10], [2, 9]], [True, False, True])      # (3, face 0) and (2, face 0) flagged
EE = ([[4, 8], [5, 7]], [True, False])                      # edges 0 and 4 flagged


def write_step(root, vf=VF, ee=EE):
    d = root / "scalable-ccd" / "tiny"
    for sub in ("frames", "boxes", "mma_bool"):
        (d / sub).mkdir(parents=True, exist_ok=True)
    for k in (0, 1):
        trimesh.Trimesh(V + 0.1 * k, F, process=False).export(d / "frames" / f"tiny_{k}.ply")
    for kind, (boxes, flags) in (("vf", vf), ("ee", ee)):
        (d / "boxes" / f"0{kind}.json").write_text(json.dumps(boxes))
        (d / "mma_bool" / f"0{kind}_mma_bool.json").write_text(json.dumps(flags))
    return d


def test_a_well_formed_step(tmp_path):
    write_step(tmp_path)
    F2, V0, V1, vf, ee = load_scalable_step(tmp_path, "tiny", "0")
    assert np.array_equal(F2, F) and np.allclose(V1 - V0, 0.1)
    assert vf == {(3, 0), (2, 0)} and ee == {(0, 4)}


@pytest.mark.parametrize("vf,ee,file,match", [
    (([[3, 11]], [True]), EE, "boxes/0vf.json", r"entry 0 is \[3, 11\], expected two box ids: a vertex in \[0, n\) "
                                                r"and a face"),
    (([[4, 9]], [True]), EE, "boxes/0vf.json", r"entry 0 is \[4, 9\]"),     # 4 is an edge's id, not a vertex's
    (([[3, 8]], [False]), EE, "boxes/0vf.json", r"entry 0 is \[3, 8\]"),    # checked even when not flagged
    (([[3, 9.0]], [True]), EE, "boxes/0vf.json", r"entry 0 is \[3, 9\.0\]"),
    (([[3]], [True]), EE, "boxes/0vf.json", r"entry 0 is \[3\]"),
    (VF, ([[3, 8]], [True]), "boxes/0ee.json", r"entry 0 is \[3, 8\], expected two box ids: two edges in \[n, n \+ "
                                               r"n_edges\) with n = 4, n_edges = 5"),
    (VF, ([[4, 9]], [True]), "boxes/0ee.json", r"entry 0 is \[4, 9\]"),
    (([[3, 9]], ["no"]), EE, "mma_bool/0vf_mma_bool.json", r"entry 0 is 'no', expected true or false"),
    (([[3, 9]], [1]), EE, "mma_bool/0vf_mma_bool.json", r"entry 0 is 1, expected true or false"),
    (([[3, 9], [2, 9]], [True]), EE, "tiny", r"step 0 vf: 2 candidate pairs in boxes/ but 1 flags"),
    (({"a": 1}, [True]), EE, "boxes/0vf.json", "expected a JSON list"),
])
def test_damaged_ground_truth_is_named(tmp_path, vf, ee, file, match):
    write_step(tmp_path, vf, ee)
    with pytest.raises(ValueError, match=rf"{file}.*{match}" if "/" in file else match):
        load_scalable_step(tmp_path, "tiny", "0")


def test_unreadable_files_are_named(tmp_path):
    d = write_step(tmp_path)
    (d / "boxes" / "0ee.json").write_text("[[4, 8], ")
    with pytest.raises(ValueError, match=r"boxes/0ee\.json: cannot read it as JSON"):
        load_scalable_step(tmp_path, "tiny", "0")
    d = write_step(tmp_path)
    (d / "frames" / "tiny_1.ply").write_bytes((d / "frames" / "tiny_1.ply").read_bytes()[:120])
    with pytest.raises(ValueError, match=r"tiny_1\.ply: (cannot read this frame|not a triangle mesh)"):
        load_scalable_step(tmp_path, "tiny", "0")
    with pytest.raises(ValueError, match=r"step: no frames 1 and the next one"):
        load_scalable_step(tmp_path, "tiny", "1")


# One vertex-face query, 8 rows: x, y, z as numerator, denominator, then the truth.
ROWS = ["0,1,1,2,0,1,1", "0,1,1,2,1,1,1", "1,1,0,1,0,1,1", "0,1,1,1,0,1,1",
        "0,1,1,2,-1,1,1", "0,1,1,2,1,1,1", "1,1,0,1,0,1,1", "0,1,1,1,0,1,1"]


def write_queries(tmp_path, rows):
    path = tmp_path / "set" / "vertex-face" / "q.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(rows) + "\n")
    return path


def test_a_well_formed_query_file(tmp_path):
    kind, pts, truth = load_ccd_queries(write_queries(tmp_path, ROWS))
    assert kind == "vf" and pts.shape == (1, 8, 3) and truth.tolist() == [True]
    assert pts[0, 0].tolist() == [0.0, 0.5, 0.0] and pts[0, 4].tolist() == [0.0, 0.5, -1.0]


@pytest.mark.parametrize("change,match", [
    (lambda r: r[:7], r"has 7 rows; expected a positive multiple of 8"),
    (lambda r: [], r"has 0 rows"),
    (lambda r: ["0,1,1,0,0,1,1"] + r[1:], r"row 1: 1/0 has a zero denominator"),
    (lambda r: ["0,1,1,3,0,1,1"] + r[1:], r"row 1: 1/3 is not exactly a double"),
    (lambda r: [f"0,1,{10**400},1,0,1,1"] + r[1:], r"row 1: 1000.*/1 is beyond the range of a double"),
    (lambda r: r[:2] + ["x,1,0,1,0,1,1"] + r[3:], r"row 3 holds a value that is not an integer"),
    (lambda r: r[:2] + ["0,1,0,1,0,1"] + r[3:], r"row 3 has 6 columns; expected 7"),
    (lambda r: r[:7] + ["0,1,1,1,0,1,0"], r"row 8: truth 0, expected 0 or 1 and the same on the query's 8 rows"),
    (lambda r: [x[:-1] + "2" for x in r], r"row 1: truth 2"),
])
def test_damaged_query_files_are_named(tmp_path, change, match):
    path = write_queries(tmp_path, change(list(ROWS)))
    with pytest.raises(ValueError, match=r"path: '.*q\.csv' " + match):
        load_ccd_queries(path)
