"""The CLI: record, explain, and its errors (run in-process through main())."""

import os
import re

import numpy as np
import pytest
import trimesh

from conecull.app.cli import main
from conecull.datasets.generated import folding_sheet
from shared_data import import_or_skip


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
    out = capsys.readouterr().out
    assert "cone_too_wide" in out
    # folded onto itself: the root's normals oppose, and three triangles witness it (normal_spread)
    line = next(x for x in out.splitlines() if x.startswith("normals: "))
    assert "span a hemisphere or more: those of triangles" in line and "checked exactly" in line


def test_explain_cones_counts_the_failed_cones_by_spread(capsys):
    """`explain --cones`: the failed cones of the query, by whether their normals span a
    hemisphere (normal_spread), the largest nodes named; none at the flat first frame."""
    import conecull
    from conecull.datasets.inputs import load_sequence
    from conecull.normal_spread import Normals, node_spreads

    assert main(["explain", "fold", "--frame", "0", "--cones"]) == 0
    assert "no normal cone failed" in capsys.readouterr().out
    F, P = load_sequence("fold")
    for k in (25, 29):
        assert main(["explain", "fold", "--frame", str(k), "--cones"]) == 0
        out = capsys.readouterr().out.splitlines()
        col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]))
        col.dcd(P[0])
        tr = col.dcd(P[k], trace=True).trace
        bad = tr.cone["node"][~tr.cone["bounded"]]
        spreads = node_spreads(Normals(F, *tr.positions), col.bvh_arrays(), bad)
        within = sum(s.kind == "within" for s in spreads.values())
        assert out[1].startswith(f"{len(bad)} node") and f"; {within} have their normals within" in out[1], out[1]
        assert out[2].startswith("node 0 (depth 0")  # the largest first
    with pytest.raises(SystemExit):  # one question at a time
        main(["explain", "fold", "--frame", "0", "--cones", "--node", "0"])


def test_check_then_explain_a_collision(capsys):
    """The triage path: `check` names the first colliding pair and prints the `explain` command
    that says why it was tested; that command names the smallest node holding both and its
    verdict. With --ccd, a contact's triangle (--face) the same way."""
    assert main(["check", "fold", "--frames", "27:29", "--ccd"]) == 1
    out = capsys.readouterr().out
    pair = next(line for line in out.splitlines() if line.startswith("frame 28: self-intersecting"))
    command = pair.split("why they were tested: ")[1].split()
    assert command[:4] == ["conecull", "explain", "fold", "--frame"]
    assert main(command[1:]) == 0
    i, j = command[-2:]
    text = capsys.readouterr().out
    assert text.startswith(f"frame 28, method nc:\ntriangles {i} and {j} intersect: the smallest node holding both")
    step = next(line for line in out.splitlines() if line.startswith("step 27 -> 28: contact"))
    command = step.split("why: ")[1].split()
    assert command[3:7] == ["--frame", "27", "--ccd", "--face"]
    assert main(command[1:]) == 0
    text = capsys.readouterr().out
    assert text.startswith("step 27 -> 28 (exact), method nc:\ntriangle ") and "touches" in text
    assert main(["explain", "fold", "--frame", "3", "--pair", "0", "1", "--method", "aabb"]) == 0
    assert "do not intersect" in capsys.readouterr().out


@pytest.mark.parametrize("ccd", [False, True])
def test_record_prints_the_explain_command_of_its_first_collision(tmp_path, capsys, ccd):
    out = str(tmp_path / "r.rrd")
    assert main(["record", "fold", "--frames", "26:30", "--out", out] + (["--ccd"] if ccd else [])) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert line.startswith(f"first collision recorded at {'step 27' if ccd else 'frame 28'}; why it was not culled away: ")
    assert main(line.split("away: ")[1].split()[1:]) == 0
    text = capsys.readouterr().out
    assert ("touches" if ccd else "intersect: the smallest node holding both") in text
    assert main(["record", "fold", "--frames", "0:3", "--out", out]) == 0
    assert "first collision" not in capsys.readouterr().out  # none recorded


def test_explain_known_failing_contour(capsys):
    """A node whose contour test fails on a known reason: find one in the trace, then explain it."""
    import conecull
    from conecull.datasets.inputs import load_sequence

    F, frames = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F))
    col.dcd(frames[0])
    res = col.dcd(frames[29], trace=True)  # crumpled: a contour that is not simple in projection
    fail = np.flatnonzero((res.trace.contour["reason"] > 0) & (res.trace.contour["reason"] < 16))
    assert len(fail)
    node = int(res.trace.contour["node"][fail[0]])
    from conecull.trace import reason_name

    name = reason_name(res.trace.contour["reason"][fail[0]])
    assert main(["explain", "crumple", "--frame", "29", "--node", str(node)]) == 0
    text = capsys.readouterr().out
    assert f"verdict: not culled, {name}" in text and f"node {node}" in text


def write_frames(d, F, frames, name):
    """A folder of PLY frames, frame k in the file name(k)."""
    d.mkdir()
    for k, V in enumerate(frames):
        trimesh.Trimesh(V, F, process=False).export(d / name(k))
    return d


def test_folder_and_npz_inputs(tmp_path, capsys):
    F, frames = folding_sheet(200, 4)
    d = write_frames(tmp_path / "frames", F, frames, lambda k: f"f{k:03d}.ply")
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
    (["explain", "fold", "--frame", "0", "--face", "2048"], "--face: 2048 is out of range: the mesh has triangles 0..2047"),
    (["explain", "fold", "--frame", "0", "--pair", "0", "-3"], "--pair: -3 is out of range"),
    (["explain", "fold", "--frame", "29", "--face", "0", "--ccd"],
     "--frame: 29 is out of range: the input has frames 0..29, so steps start at frames 0..28"),
    (["explain", "fold", "--frame", "3", "--face", "0", "--ccd", "--method", "sct"], "--method: 'sct' is a discrete"),
    (["record", "fold", "--depth", "30"], "--depth: 30 is deeper than this mesh's BVH"),
    (["record", "no/such/path", "--resolution", "8"], "neither a scene"),
    (["record", "fold", "--resolution", "1"], "resolution: expected an integer >= 3"),
    (["scenes", "--generate", "nope"], "NAME: unknown scene 'nope'"),
    (["record", "fold", "--positions", "p.npz"], "positions: only with a single mesh file, not with the scene 'fold'"),
    (["record", "fold", "--depth", "-5"], "--depth: expected a BVH depth in [0, 64], got -5"),
    (["record", "fold", "--out", "no/such/folder/r.rrd"], "--out: folder"),
    (["record", "fold", "--out", "."], "--out: '.' is a directory"),
    (["demo", "--out", "no/such/folder/d.rrd"], "--out: folder"),
    (["bench", "dcd", "--frames", "0"], "--frames: expected an integer in [2, 10000], got 0"),
    (["bench", "dcd", "--triangles", "-5"], "--triangles: expected an integer >= 8, got -5"),
    (["bench", "contour", "--repeats", "0"], "--repeats: expected an integer in [1, 1000], got 0"),
    (["bench", "threads", "--threads", "0"], "--threads: expected an integer in [1, 1024], got 0"),
    (["bench", "all", "--sizes", "abc"], "--sizes: expected comma-separated triangle counts, got 'abc'"),
    (["bench", "all", "--sizes", "4"], "--sizes: expected triangle counts >= 8"),
    (["bench", "all", "--sizes", "16000,10000000000"], "--sizes: sheets of 10000016000 triangles in all would need about"),
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
    d = write_frames(tmp_path / "frames", F, frames, lambda k: f"f{k:03d}.ply")
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
    assert "1 CCD step (exact), 18484 triangles" in capsys.readouterr().out


def test_bench_from_json_names_a_bad_file(tmp_path, capsys):
    bad = tmp_path / "paper.json"
    bad.write_text("not json")
    assert main(["bench", "all", "--from-json", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert f"--from-json: '{bad}' is not a JSON file" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
    (tmp_path / "f").write_text("")  # where --out cannot be created: named before the file is read
    assert main(["bench", "all", "--from-json", str(bad), "--out", str(tmp_path / "f" / "o")]) == 2
    assert f"--out: cannot create folder '{tmp_path / 'f' / 'o'}'" in capsys.readouterr().err


@pytest.mark.parametrize("argv,msg", [
    (["view", "fold", "--port", "70000"], r"--port: expected a TCP port in [0, 65535]"),
    (["view", "fold", "--port", "-1"], r"--port: expected a TCP port in [0, 65535]"),
    (["view", "fold", "--host", "192.0.2.1"], "--host: cannot listen on '192.0.2.1'"),
    (["record", "fold", "--frames", "0:1000"], "--frames: '0:1000' goes past the last frame: the input has 30 frames"),
    (["record", "fold", "--frames=-3:"], "--frames: '-3:': frames are counted from 0"),
    (["record", "fold", "--ccd", "--method", "sct"], "--method: 'sct' is a discrete (DCD) method"),
    (["record", "fold", "--resolution", "1"], "--resolution: expected an integer >= 3"),
    (["record", "fold", "--out", "/proc/conecull-test.rrd"], "--out: cannot write '/proc/conecull-test.rrd'"),
    (["record", "fold", "--compare", "nc,nc"], "--compare: 'nc' given twice"),
    (["record", "fold", "--compare", "nc,"], "--compare: expected one of aabb, nc, aabb+front, nc+front, sct, cbc, got ''"),
    (["record", "fold", "--ccd", "--compare", "cbc,sct"], "--compare: 'sct' is a discrete (DCD) method"),
])
def test_cli_errors_name_the_option(argv, msg, capsys):
    """Exit code 2 and the option named, before any work (no hang, no traceback)."""
    if "/proc" in " ".join(argv) and not os.path.isdir("/proc"):
        pytest.skip("no /proc")
    assert main(argv) == 2
    assert msg in capsys.readouterr().err


def test_cli_names_the_positions_file_and_frame(tmp_path, capsys):
    F, frames = folding_sheet(50, 5)
    trimesh.Trimesh(frames[0], F, process=False).export(tmp_path / "m.obj")
    out = str(tmp_path / "r.rrd")
    np.savez(tmp_path / "empty.npz", positions=frames[:0])
    assert main(["record", str(tmp_path / "m.obj"), "--positions", str(tmp_path / "empty.npz"), "--out", out]) == 2
    assert "--positions: no frames in" in capsys.readouterr().err
    bad = frames.copy()
    bad[3, 5, 1] = np.nan
    np.savez(tmp_path / "nan.npz", positions=bad)
    assert main(["record", str(tmp_path / "m.obj"), "--positions", str(tmp_path / "nan.npz"), "--out", out]) == 2
    assert (f"--positions: frame 3 has a non-finite coordinate nan at row 5, column 1 in '{tmp_path / 'nan.npz'}'"
            in capsys.readouterr().err)
    (tmp_path / "rep.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\n")
    assert main(["record", str(tmp_path / "rep.obj"), "--out", out]) == 2
    assert "rep.obj: line 4 ('f 1 1 2'): a face repeats a vertex: [1, 1, 2]" in capsys.readouterr().err


def test_record_unpadded_folder_in_numeric_order(tmp_path, capsys):
    """frame0 .. frame11 are recorded in that order (not frame0, frame1, frame10, ...)."""
    from rrd_helpers import rows_by_frame

    F, frames = folding_sheet(50, 12)
    d = write_frames(tmp_path / "frames", F, frames, lambda k: f"frame{k}.ply")
    out = str(tmp_path / "r.rrd")
    assert main(["record", str(d), "--out", out]) == 0
    mesh = rows_by_frame(out, "/scene/mesh", "Mesh3D:vertex_positions")
    for k in (2, 10):
        assert np.allclose(np.array(mesh[k]).reshape(-1, 3), frames[k][F].reshape(-1, 3))


def test_help_states_defaults(capsys):
    for command, wanted in (("record", ["(default: the scene fold)", "culling method (default nc"]),
                            ("view", ["(default: the scene fold)", "(default 8080", "(default nc)"]),
                            ("demo", ["culling method (default nc)"]),
                            ("explain", ["the frame to query", "a BVH node id", "culling method (default nc)", "(default exact)"]),
                            ("bench", ["(default 64000)"])):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        text = " ".join(capsys.readouterr().out.split())  # argparse wraps lines
        for w in wanted:
            assert w in text, (command, w)


def test_demo_prints_commands_that_work_anywhere(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["demo", "--out", "d.rrd"]) == 0
    line = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("open it with:")][0]
    exe, path = line.split()[3:5]
    assert os.path.isabs(exe) and os.path.basename(exe) == "rerun" and path == str(tmp_path / "d.rrd")


def test_check_reports_first_hits_that_are_real(capsys):
    """`conecull check`: per frame the first intersecting pair, per step the first contact; each is
    one of the full queries' collisions, and the exit status says whether any was found."""
    import re

    import conecull
    from conecull.datasets import load

    assert main(["check", "fold", "--frames", "25:30", "--ccd"]) == 1
    out = capsys.readouterr().out
    F, P = load("fold")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]))
    col.dcd(P[25])
    for k in range(25, 30):
        full = {tuple(p) for p in col.dcd(P[k]).pairs.tolist()}
        line = next(ln for ln in out.splitlines() if ln.startswith(f"frame {k}:"))
        m = re.search(r"triangles (\d+) and (\d+) intersect", line)
        assert (m is not None) == bool(full), line
        assert m is None or (int(m[1]), int(m[2])) in full, line
        if k + 1 < 30:
            step = col.ccd(P[k], P[k + 1])
            line = next(ln for ln in out.splitlines() if ln.startswith(f"step {k} -> {k + 1}:"))
            vf = re.search(r"vertex (\d+) touches triangle (\d+)", line)
            ee = re.search(r"edges (\d+) and (\d+)", line)
            assert (vf or ee) is not None or "collision-free" in line, line
            assert (vf is not None or ee is not None) == bool(len(step.vf) + len(step.ee)), line
            assert vf is None or (int(vf[1]), int(vf[2])) in {tuple(p) for p in step.vf.tolist()}, line
            assert ee is None or (int(ee[1]), int(ee[2])) in {tuple(p) for p in step.ee.tolist()}, line
    assert "collide" in out.splitlines()[-1]
    assert main(["check", "bend", "--frames", "0:6", "--ccd"]) == 0  # never self-intersects
    assert "no collision in the frames and steps checked" in capsys.readouterr().out


@pytest.mark.parametrize("argv, message", [
    (["check", "bend", "--ccd", "--method", "sct"], "--method: 'sct' is a discrete (DCD) method"),
    (["check", "bend", "--frames", "40"], "--frames: '40' selects no frame"),
    (["check", "bend", "--arithmetic", "float"], "--arithmetic: only with --ccd"),
    (["record", "bend", "--arithmetic", "float"], "--arithmetic: 'float' is a CCD mode"),
])
def test_check_bad_options(argv, message, capsys):
    assert main(argv) == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("argv,msg", [
    (["bench", "dcd", "--scenes", "fold"], "--scenes: the dcd suite does not use it (options of `bench dcd`: --frames, "),
    (["bench", "dcd", "--skip", "steps"], "--skip: the dcd suite does not use it"),
    (["bench", "ccd", "--frames", "4"], "--frames: the ccd suite does not use it"),
    (["bench", "front", "--repeats", "3"], "--repeats: the front suite does not use it"),
    (["bench", "dcd", "--leaf-size", "1"], "--leaf-size: the dcd suite does not use it"),
    (["bench", "front", "--leaf-size", "0"], "--leaf-size: expected an integer in [1, 64], got 0"),
    (["bench", "front", "--leaf-size", "65"], "--leaf-size: expected an integer in [1, 64], got 65"),
    (["bench", "trace", "--threads", "2"], "--threads: the trace suite always measures one thread"),
    (["bench", "contour", "--threads", "2"], "--threads: the contour suite always measures one thread"),
    (["bench", "all", "--from-json", "x.json", "--scenes", "fold"], "--scenes: only the output folder goes with --from-json"),
    (["bench", "threads", "--threads", "5000"], "--threads: expected an integer in [1, 1024], got 5000"),
    (["bench", "dcd", "--threads", "0"], "--threads: expected an integer in [1, 1024], got 0"),
    (["bench", "dcd", "--frames", "100000000"], "--frames: expected an integer in [2, 10000], got 100000000"),
    (["bench", "dcd", "--repeats", "0"], "--repeats: expected an integer in [1, 1000], got 0"),
    (["bench", "dcd", "--triangles", "100000000000000"], "--triangles: a sheet of 100000000000000 triangles would need"),
    (["bench", "dcd", "--out", "/dev/null/x"], "--out: cannot create folder '/dev/null/x'"),
    (["bench", "ccd", "--ipctk-candidates", "5"], "--ipctk-candidates: the ccd suite does not use it"),
    (["bench", "all", "--ipctk-candidates", "-1"], "--ipctk-candidates: expected an integer in [0, 1000000000], got -1"),
])
def test_bench_options_are_checked_before_any_work(argv, msg, capsys):
    """Exit code 2 with the option named, at once: an option the suite would ignore, a count out
    of range, an output folder that cannot be made (the results are written at the end)."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert msg in err and "Traceback" not in err, err


def test_bench_out_that_is_a_file(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    assert main(["bench", "dcd", "--out", str(tmp_path / "f")]) == 2
    assert f"--out: '{tmp_path / 'f'}' exists and is not a folder" in capsys.readouterr().err


@pytest.mark.parametrize("content,msg", [
    (None, "--from-json: cannot read"),  # a folder
    ('{"machine": {}, "scenes": 5}', "is not the paper.json of a `bench all` run (its 'scenes' is not a list of rows)"),
    ('{"machine": {}, "scenes": [{"x": 1}]}', "is not the paper.json of a `bench all` run (a row lacks or mistypes"),
    ('{}', "is not the paper.json of a `bench all` run (it has no 'machine' entry)"),  # was a "not measured" table
    ('{"scenes": []}', "is not the paper.json of a `bench all` run (it has no 'machine' entry)"),
    ('[1, 2]', "is not the paper.json of a `bench all` run"),
    # rows only the plots read (a KeyError, a ZeroDivisionError traceback before)
    ('{"machine": {}, "scaling": [{"triangles": 1000}]}', "a row lacks or mistypes 'dcd_nc_ms'"),
    ('{"machine": {}, "scaling": [{"triangles": 0, "dcd_nc_ms": 1.0, "ccd_nc_ms": 1.0}]}', "a row lacks or mistypes"),
])
def test_bench_from_json_names_a_file_that_is_no_paper_json(tmp_path, content, msg, capsys):
    if content and "scaling" in content:  # only the plots read those rows
        import_or_skip("matplotlib", "the bench's plots (pip install 'conecull[bench]')")
    path = tmp_path / "paper.json"
    if content is None:
        path.mkdir()
    else:
        path.write_text(content)
    assert main(["bench", "all", "--from-json", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert msg in err and "Traceback" not in err, err
    assert not (tmp_path / "o").exists()  # refused: no folder left behind (found by review)
    assert main(["bench", "all", "--from-json", str(tmp_path / "none.json"), "--out", str(tmp_path / "o")]) == 2
    assert f"--from-json: cannot read '{tmp_path / 'none.json'}'" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_bench_refusals_leave_no_folder(tmp_path, capsys):
    """--skip, --scenes and an empty --from-json are refused before --out is created (and an
    empty --from-json never starts the full evaluation)."""
    out = tmp_path / "o"
    for argv, msg in ((["bench", "first-hit", "--skip", "scenes"], "--skip: first-hit can leave out 'steps', got ['scenes']"),
                      (["bench", "all", "--skip", "everything"], "--skip: all can leave out 'scenes', 'steps'"),
                      (["bench", "front", "--scenes", "nope"], "--scenes: unknown scene 'nope'"),
                      (["bench", "all", "--from-json", ""], "--from-json: expected the path of a paper.json, got ''")):
        assert main([*argv, "--out", str(out)]) == 2
        assert msg in capsys.readouterr().err
        assert not out.exists(), argv


def test_record_to_a_full_disk(capsys):
    """rerun reports a failed write as a RuntimeError: the CLI printed a traceback (found by
    probing with --out /dev/full). Now an error naming the file, exit status 2, and the device
    itself left alone (a failed recording's file is removed only if it is a regular file)."""
    if not os.path.exists("/dev/full"):
        pytest.skip("this system has no /dev/full")
    assert main(["record", "fold", "--resolution", "10", "--frames", "0:2", "--out", "/dev/full"]) == 2
    err = capsys.readouterr().err
    assert "conecull record: error: cannot write the recording '/dev/full'" in err and "No space left" in err
    assert os.path.exists("/dev/full")


def test_scenes_generate_checks_every_name_first(capsys, monkeypatch):
    """`scenes --generate fold FOLD` generated fold (minutes for a large scene) before refusing FOLD."""
    import conecull.datasets as datasets

    calls = []
    monkeypatch.setattr(datasets, "load", lambda name, *a, **k: calls.append(name))
    assert main(["scenes", "--generate", "fold", "FOLD"]) == 2
    assert "NAME: unknown scene 'FOLD'" in capsys.readouterr().err and calls == []


def test_library_warnings_are_one_line(tmp_path, capsys):
    """A mesh file's polygons split into triangles: said once, as one line naming the command
    (not a Python warning with its source line)."""
    d = tmp_path / "quads"
    d.mkdir()
    for k in range(2):
        (d / f"f{k}.obj").write_text(f"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 {0.1 * k}\nf 1 2 3 4\n")
    assert main(["check", str(d)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == ["conecull check: warning: INPUT: 1 face of 'f0.obj' with more than 3 corners was split into "
                   "triangles (a fan from each face's first corner, in file order): triangle ids count these "
                   "triangles, not the file's faces"]


def test_check_record_and_explain_agree_on_the_first_pair(tmp_path, capsys):
    """`check` builds its BVH from frame 0, as `record` and `explain` do, whatever --frames says:
    the first pair it names at a frame is the one `record` names (it was 12 x 60 with --frames
    28:29 and 973 x 1084 over all frames)."""
    firsts = []
    for frames in ("28:29", "20:30"):
        assert main(["check", "fold", "--frames", frames]) == 1
        line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("frame 28:"))
        firsts.append(line.split("--pair ")[1])
    assert main(["record", "fold", "--frames", "28:29", "--out", str(tmp_path / "r.rrd")]) == 0
    recorded = capsys.readouterr().out.split("--pair ")[1].split()[:2]
    assert firsts[0] == firsts[1] == " ".join(recorded)


def test_explain_tells_a_front_methods_story_as_the_recording_does(tmp_path, capsys):
    """A front method's verdict depends on every query before (Alg. 4: a front that churned rests
    for several queries): `explain` replays the queries `record --frames A:` made (--since A), so
    its sentence for each collision is the recording's log line, frame by frame (it replayed
    nothing and said "built from the top" where the recording said "resumed, then dropped for
    churning")."""
    from rrd_helpers import log_rows

    path = str(tmp_path / "f.rrd")
    modes = set()
    for scene, frames, ccd in (("roll", "0:30", []), ("fold", "25:30", []), ("fold", "25:29", ["--ccd"])):
        assert main(["record", scene, "--frames", frames, "--method", "nc+front", "--out", path] + ccd) == 0
        capsys.readouterr()
        since = frames.split(":")[0]
        log = log_rows(path)
        checked = 0
        for k, rows in sorted(log.items()):
            warn = [t for level, t in rows if level == "WARN" and not t.startswith("...")]
            if not warn:
                continue
            if ccd:
                m = re.match(r"vertex (\d+) touches triangle (\d+)", warn[0]) or re.match(r"edges", warn[0])
                if m is None or not m.groups():
                    continue
                what = ["--face", m[2]]
            else:
                m = re.match(r"triangles (\d+) and (\d+) intersect", warn[0])
                what = ["--pair", m[1], m[2]]
            argv = ["explain", scene, "--frame", str(k), "--method", "nc+front", "--since", since] + what + ccd
            assert main(argv) == 0
            text = capsys.readouterr().out.splitlines()
            said = text[2] if ccd else text[1]  # CCD: the face's first contact, after "triangle F takes part in"
            assert said == warn[0], (argv, said, warn[0])
            modes |= {w for w in ("resumed", "built from the top", "churning", "rests", "Collide from the top")
                      if w in said}
            checked += 1
        assert checked >= 2, (scene, frames, ccd)
    assert {"resumed", "churning"} <= modes, modes  # a history longer than one query mattered


def test_explain_since_is_checked(capsys):
    assert main(["explain", "fold", "--frame", "5", "--pair", "0", "1", "--since", "2"]) == 2
    assert "--since: only for a front method" in capsys.readouterr().err
    assert main(["explain", "fold", "--frame", "5", "--pair", "0", "1", "--since", "6", "--method", "nc+front"]) == 2
    assert "--since: 6 is out of range" in capsys.readouterr().err


def test_ccd_on_a_one_frame_input_is_refused(tmp_path, capsys):
    """check --ccd printed "no collision in the frames and steps checked" (exit 0) with no step."""
    (tmp_path / "m.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    np.save(tmp_path / "p.npy", np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], float))
    args = [str(tmp_path / "m.obj"), "--positions", str(tmp_path / "p.npy"), "--ccd"]
    assert main(["check"] + args) == 2
    assert "--ccd: the input has one frame" in capsys.readouterr().err
    assert main(["explain"] + args + ["--frame", "0", "--face", "0"]) == 2
    assert "--ccd: the input has one frame" in capsys.readouterr().err
    assert main(["check"] + args[:-1]) == 0
    assert "1 triangle, method nc: no collision" in capsys.readouterr().out


@pytest.mark.parametrize("argv", [["check", "fold", "--frames", "-3:"], ["record", "fold", "--frames", "-1"]])
def test_a_negative_frame_gets_our_message(argv, capsys):
    """argparse took '-3:' for an option ("expected one argument"); our check says what is wrong."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "--frames: " in err and "counted from 0 (not from the end)" in err, err


def test_an_empty_input_is_not_the_default_scene(capsys, tmp_path):
    """`check ''` ran the default scene (an empty INPUT read as none given)."""
    for argv in (["check", ""], ["record", "", "--out", str(tmp_path / "r.rrd")]):
        assert main(argv) == 2
        assert "INPUT: '' is neither a scene" in capsys.readouterr().err


def test_a_fifo_as_out_is_refused(capsys, tmp_path):
    """Opening a FIFO to check that it can be written waits for a reader: `record` hung."""
    os.mkfifo(tmp_path / "out.rrd")
    assert main(["record", "--out", str(tmp_path / "out.rrd"), "--frames", "0:2"]) == 2
    assert "--out: '" in capsys.readouterr().err


@pytest.mark.parametrize("argv,msg", [
    (["check", "fold", "--ccd", "--frames", "2"], "--ccd: --frames 2 selects one frame, and `check` checks the steps"),  # said "no collision"
    (["check", "fold", "--frames", "1_0"], "--frames: expected A:B or K, got '1_0'"),  # read as frame 10
    (["check", "fold", "--frames", " 1 "], "--frames: expected A:B or K, got ' 1 '"),
    (["bench", "all", "--sizes", "-5,10"], "--sizes: expected triangle counts >= 8, got '-5,10'"),  # argparse's words
    (["explain", "fold", "--frame", "3", "--node", "-2"], "--node: -2 is out of range"),
])
def test_more_bad_options_are_named(argv, msg, capsys):
    """From a bad-input probe: each was a wrong answer or argparse's 'expected one argument'."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert msg in err and "Traceback" not in err, err
