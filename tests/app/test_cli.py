"""The CLI: record, explain, and its errors (run in-process through main())."""

import numpy as np
import pytest
import trimesh

from conecull.app.cli import main
from conecull.datasets.generated import folding_sheet


def test_record_default_scene_and_frames(tmp_path, capsys):
    out = tmp_path / "run.rrd"
    assert main(["record", "--out", str(out), "--frames", "2:5"]) == 0
    assert out.stat().st_size > 0
    assert "3 frames" in capsys.readouterr().out


def test_explain_reports_reason(capsys):
    # Frame 0 of 'fold' is flat: the root is culled. At the last frame the root's cone is full.
    assert main(["explain", "fold", "--frame", "0", "--node", "0"]) == 0
    assert "verdict: culled, passed" in capsys.readouterr().out
    assert main(["explain", "fold", "--frame", "29", "--node", "0"]) == 0
    assert "cone_too_wide" in capsys.readouterr().out


def test_explain_known_failing_contour(capsys):
    """A node whose contour test fails on a known reason: find one in the trace, then explain it."""
    import conecull
    from conecull.datasets.inputs import load_sequence

    F, frames = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F))
    col.dcd(frames[0])
    res = col.dcd(frames[20], trace=True)
    fail = np.flatnonzero((res.trace.contour["reason"] > 0) & (res.trace.contour["reason"] < 16))
    assert len(fail)
    node = int(res.trace.contour["node"][fail[0]])
    from conecull.trace import reason_name

    name = reason_name(res.trace.contour["reason"][fail[0]])
    assert main(["explain", "crumple", "--frame", "20", "--node", str(node)]) == 0
    text = capsys.readouterr().out
    assert f"verdict: not culled, {name}" in text and f"node {node}" in text


def test_folder_and_npz_inputs(tmp_path, capsys):
    F, frames = folding_sheet(200, 4)
    d = tmp_path / "frames"
    d.mkdir()
    for k, V in enumerate(frames):
        trimesh.Trimesh(V, F, process=False).export(d / f"f{k:03d}.ply")
    assert main(["record", str(d), "--out", str(tmp_path / "a.rrd")]) == 0
    trimesh.Trimesh(frames[0], F, process=False).export(tmp_path / "m.obj")
    np.savez(tmp_path / "p.npz", positions=frames)
    assert main(["record", str(tmp_path / "m.obj"), "--positions", str(tmp_path / "p.npz"), "--out", str(tmp_path / "b.rrd")]) == 0
    # faces that differ between frames
    trimesh.Trimesh(frames[1], F[::-1], process=False).export(d / "f999.ply")
    assert main(["record", str(d), "--out", str(tmp_path / "c.rrd")]) == 2
    assert "different faces" in capsys.readouterr().err


@pytest.mark.parametrize("argv,msg", [
    (["record", "no/such/path"], "neither a scene"),
    (["record", "fold", "--frames", "40:50"], "selects no frame"),
    (["record", "fold", "--frames", "x"], "expected A:B or K"),
    (["explain", "fold", "--frame", "99", "--node", "0"], "--frame: 99 is out of range"),
    (["explain", "fold", "--frame", "0", "--node", "99999"], "--node: 99999 is out of range"),
    (["record", "no/such/path", "--resolution", "8"], "neither a scene"),
    (["record", "fold", "--resolution", "1"], "resolution: expected an integer >= 3"),
    (["scenes", "--generate", "nope"], "NAME: unknown scene 'nope'"),
    (["record", "fold", "--positions", "p.npz"], "positions: only with a single mesh file, not with the scene 'fold'"),
    (["record", "fold", "--depth", "-5"], "--depth: expected a BVH depth in [0, 64], got -5"),
    (["record", "fold", "--out", "no/such/folder/r.rrd"], "--out: folder"),
    (["record", "fold", "--out", "."], "--out: '.' is a directory"),
    (["demo", "--out", "no/such/folder/d.rrd"], "--out: folder"),
    (["bench", "dcd", "--frames", "0"], "--frames: expected an integer >= 2, got 0"),
    (["bench", "dcd", "--triangles", "-5"], "--triangles: expected an integer >= 8, got -5"),
    (["bench", "contour", "--repeats", "0"], "--repeats: expected an integer >= 1, got 0"),
    (["bench", "threads", "--threads", "0"], "--threads: expected an integer >= 1, got 0"),
    (["bench", "all", "--sizes", "abc"], "--sizes: expected comma-separated triangle counts, got 'abc'"),
    (["bench", "all", "--sizes", "4"], "--sizes: expected triangle counts >= 8"),
])
def test_cli_errors(argv, msg, capsys):
    assert main(argv) == 2
    assert msg in capsys.readouterr().err


def test_scene_resolution_and_generate(tmp_path, capsys):
    out = tmp_path / "f.rrd"
    assert main(["record", "funnel", "--resolution", "8", "--frames", "0:2", "--out", str(out)]) == 0
    assert "98 triangles" in capsys.readouterr().out  # 2 (8 - 1)^2: the resolution reached the scene
    assert main(["scenes", "--generate", "roll", "bend"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == ["roll", "bend"] and all(line.endswith(" s") for line in lines)


def test_resolution_is_only_for_scenes(tmp_path, capsys):
    F, frames = folding_sheet(50, 2)
    d = tmp_path / "frames"
    d.mkdir()
    for k, V in enumerate(frames):
        trimesh.Trimesh(V, F, process=False).export(d / f"f{k:03d}.ply")
    assert main(["record", str(d), "--resolution", "8", "--out", str(tmp_path / "x.rrd")]) == 2
    assert "resolution: only for a built-in scene" in capsys.readouterr().err


def test_unreadable_mesh(tmp_path, capsys):
    bad = tmp_path / "bad.obj"
    bad.write_text("this is not a mesh\n")
    assert main(["record", str(bad)]) == 2
    assert "bad.obj" in capsys.readouterr().err


def test_record_a_real_step_from_shared_data(tmp_path, capsys):
    """A scalable-ccd scene's frames/ folder is a two-frame sequence: record its CCD step."""
    from shared_data import DATA, require

    frames = require(DATA / "scalable-ccd" / "cloth-funnel" / "frames")
    assert main(["record", str(frames), "--ccd", "--out", str(tmp_path / "funnel.rrd")]) == 0
    assert "1 CCD steps (exact), 18484 triangles" in capsys.readouterr().out


def test_bench_from_json_names_a_bad_file(tmp_path, capsys):
    bad = tmp_path / "paper.json"
    bad.write_text("not json")
    assert main(["bench", "all", "--from-json", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert f"--from-json: '{bad}' is not a JSON file" in capsys.readouterr().err
