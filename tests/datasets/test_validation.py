"""Bad input to the datasets gets a ValueError naming the argument, never a crash, a hang or a
silently wrong answer: frame order of folders, non-finite scenes, sizes, generator arguments,
position files."""

import dataclasses

import numpy as np
import pytest
import trimesh

import conecull
from conecull import datasets
from conecull.datasets import generated, skirt, squishy
from conecull.datasets.inputs import load_sequence, parse_frames


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CONECULL_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


TRI = np.array([[0, 1, 2]])


def test_unpadded_frame_files_load_in_numeric_order(tmp_path):
    d = tmp_path / "frames"
    d.mkdir()
    frames = [np.array([[0, 0, k], [1, 0, k], [0, 1, k]], float) for k in range(12)]
    for k, V in enumerate(frames):  # frame0 .. frame11: text order would be 0, 1, 10, 11, 2, ...
        trimesh.Trimesh(V, TRI, process=False).export(d / f"frame{k}.ply")
    _, P = load_sequence(str(d))
    assert P[:, 0, 2].tolist() == list(range(12))


def test_frame_order_is_numeric_and_deterministic():
    from conecull.datasets.inputs import frame_order

    assert frame_order(["f10.ply", "f2.ply", "f1.ply"]) == ["f1.ply", "f2.ply", "f10.ply"]
    names = ["b10.obj", "a.ply", "f01.ply", "f1.ply", "B2.obj"]
    assert frame_order(names) == frame_order(names[::-1]) == ["a.ply", "B2.obj", "b10.obj", "f01.ply", "f1.ply"]


@pytest.mark.parametrize("resolution", [9, 15])
def test_squishy_is_finite_at_every_resolution(resolution):
    """A tentacle centred on the top face (n = 9, 15) had an undefined swirl direction: NaN."""
    F, P = datasets.load("squishy", resolution=resolution, frames=2)
    assert np.isfinite(P).all() and P.shape == (2, squishy.squishy_counts(resolution)[1], 3)
    assert len(F) == datasets.SCENES["squishy"].triangles(resolution)


def test_load_refuses_and_never_caches_non_finite_positions(cache, monkeypatch):
    scene = datasets.SCENES["bend"]

    def nan_scene(res, frames, dt):
        F, P = scene.generate(res, frames, dt)
        P[1, 3, 2] = np.nan
        return F, P

    monkeypatch.setitem(datasets.SCENES, "bend", type(scene)(**{**scene.__dict__, "generate": nan_scene}))
    with pytest.raises(ValueError, match=r"scene 'bend' at resolution 5: generated a non-finite position \(frame 1, "
                                         r"vertex 3"):
        datasets.load("bend", resolution=5, frames=2)
    assert not list(cache.glob("bend-*"))


@pytest.mark.parametrize("kwargs,match", [
    ({"name": "fold", "resolution": 3000, "frames": 10**4}, "frames: 10000 frames of scene 'fold' at "
                                                             "resolution 3000 would need about"),
    # beyond MAX_FRAMES: a typo that would simulate for hours, whatever the memory
    ({"name": "funnel", "resolution": 3, "frames": 10**6}, r"frames: expected an integer in \[1, 10000\], got 1000000"),
    ({"name": "fold", "resolution": 10**7, "frames": 1}, "resolution: one frame of scene 'fold'"),
    ({"name": "squishy", "resolution": 10**7, "frames": 1}, "resolution: one frame of scene 'squishy'"),
    ({"name": "falling", "resolution": 10**7, "frames": 1}, "resolution: 10000000 does not suit scene 'falling'"),
    # frames left at the scene's default (as the CLI does): the resolution is what to change
    ({"name": "squishy", "resolution": 3000}, "resolution: 20 frames of scene 'squishy' at resolution 3000"),
])
def test_load_refuses_sizes_beyond_memory_up_front(kwargs, match):
    with pytest.raises(ValueError, match=match):
        datasets.load(**kwargs)


@pytest.mark.parametrize("call,match", [
    (lambda: generated.folding_sheet(100, 3, final_angle="x"), "final_angle: expected a finite number, got 'x'"),
    (lambda: generated.folding_sheet(final_angle=np.nan), "final_angle: expected a finite number, got nan"),
    (lambda: generated.folding_sheet(10**13), "n_triangles: a sheet of 10000000000000 triangles would need about"),
    (lambda: generated.folding_sheet(100, 10**12), "n_frames: 1000000000000 frames of"),
    (lambda: generated.bending_sheet(100, 3, amplitude=np.inf), "amplitude: expected a finite number, got inf"),
    (lambda: generated.crumpling_sphere(seed="a"), "seed: expected an integer >= 0, got 'a'"),
    (lambda: generated.crumpling_sphere(strength=None), "strength: expected a finite number, got None"),
    (lambda: generated.uv_sphere(radius=-1), "radius: expected a finite number >= 0, got -1"),
    (lambda: generated.uv_sphere(10**5, 10**5), "n_lat, n_lon: a 100000 x 100000 sphere would need about"),
    (lambda: generated.grid_sheet(3, 3, width="1"), "width: expected a finite number >= 0, got '1'"),
    (lambda: generated.fold(np.zeros((4, 2)), 1.0), r"V: expected an array of shape \(n, 3\), got \(4, 2\)"),
    (lambda: generated.fold([[0, 0, np.nan]], 1.0), "V: non-finite coordinate nan at row 0, column 2"),
    (lambda: generated.fold(np.zeros((4, 3)), 1.0, radius=0), "radius: expected a finite number > 0, got 0"),
    (lambda: skirt.skirt_sequence(10, 0), "frames: expected an integer >= 1, got 0"),
    (lambda: skirt.skirt_sequence(2.5, 3), "resolution: expected an integer >= 1, got 2.5"),
    (lambda: skirt.tube_grid(2, 5), "n_around: expected an integer >= 3, got 2"),
    (lambda: squishy.squishy_sequence(8.0, 2), "n: expected an integer >= 8, got 8.0"),
    (lambda: squishy.squishy_sequence(8, 0), "frames: expected an integer >= 1, got 0"),
    (lambda: squishy.squishy_ball(8, tentacle_length=0), "tentacle_length: expected a finite number > 0, got 0"),
    (lambda: squishy.squash(np.zeros((3, 3)), 1.0, 1.0), "squeeze: expected a finite number >= 0 and < 1, got 1.0"),
])
def test_generators_name_bad_arguments(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_fold_takes_array_likes():
    W = generated.fold([[0.0, 0, 0], [1.0, 0, 0]], np.pi, x0=0.5, radius=0.1)
    assert W.shape == (2, 3) and W[1, 0] < 0.5  # the far point came back over the fold line


@pytest.fixture
def mesh_file(tmp_path):
    path = tmp_path / "m.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return str(path)


@pytest.mark.parametrize("P,match", [
    (np.zeros((0, 3, 3)), r"positions: no frames in '.*p\.npz' \(shape \(0, 3, 3\)\)"),
    (np.zeros((4, 3, 2)), r"positions: expected an array of shape \(T, n, 3\) in '.*p\.npz', got \(4, 3, 2\)"),
    (np.zeros((4, 5, 3)), r"positions: frames have 5 vertices in '.*p\.npz' but the mesh has 3"),
    (np.where(np.arange(36).reshape(4, 3, 3) == 31, np.nan, 0.0),
     r"positions: frame 3 has a non-finite coordinate nan at row 1, column 1 in '.*p\.npz'"),
])
def test_bad_position_files_are_named(tmp_path, mesh_file, P, match):
    np.savez(tmp_path / "p.npz", positions=P)
    with pytest.raises(ValueError, match=match):
        load_sequence(mesh_file, positions=str(tmp_path / "p.npz"))


def test_positions_out_of_the_queries_range_are_named(tmp_path, mesh_file):
    P = np.zeros((2, 3, 3))
    P[1, 2, 0] = 1e300  # finite, but beyond what the exact predicates take
    np.savez(tmp_path / "p.npz", positions=P)
    with pytest.raises(ValueError, match=r"positions: coordinate 1e\+300 in frame 1 at row 2, column 0 in '.*p\.npz' is "
                                         r"outside the supported range"):
        load_sequence(mesh_file, positions=str(tmp_path / "p.npz"))


def test_positions_as_npy(tmp_path, mesh_file):
    P = np.arange(18, dtype=float).reshape(2, 3, 3)
    np.save(tmp_path / "p.npy", P)
    F, got = load_sequence(mesh_file, positions=str(tmp_path / "p.npy"))
    assert np.array_equal(got, P) and F.tolist() == [[0, 1, 2]]


def test_an_npz_without_arrays(tmp_path, mesh_file):
    np.savez(tmp_path / "p.npz")
    with pytest.raises(ValueError, match="positions: '.*p.npz' holds no array"):
        load_sequence(mesh_file, positions=str(tmp_path / "p.npz"))


@pytest.mark.parametrize("text,match", [
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\n", r"bad\.obj: line 4 \('f 1 1 2'\): a face repeats a vertex: \[1, 1, 2\] \(counted from 1\)"),
    ("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", r"bad\.obj: vertices: non-finite coordinate nan at row 0, column 2"),
    ("v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n",
     r"bad\.obj: vertices: coordinate 1e\+300 at row 1, column 0 is outside the supported range"),
    # OBJ counts from 1: trimesh read 0 as -1, the last vertex ("repeats a vertex: [0, 0, 1]")
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 0 2 3\n",
     r"bad\.obj: line 6: a face refers to vertex 0, but OBJ counts vertices from 1 \('f 0 2 3'\)"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 2/1 0/1 3/1\n", r"bad\.obj: line 4: a face refers to vertex 0"),
])
def test_bad_mesh_files_are_named(tmp_path, text, match):
    (tmp_path / "bad.obj").write_text(text)
    with pytest.raises(ValueError, match=match):
        load_sequence(str(tmp_path / "bad.obj"))
    d = tmp_path / "frames"  # the same in a folder of frames
    d.mkdir()
    (d / "bad.obj").write_text(text)
    with pytest.raises(ValueError, match=match):
        load_sequence(str(d))


def test_obj_zero_check_leaves_valid_faces_alone(tmp_path):
    """A 0 that is not a face's vertex index (a texture index, a negative index, a comment)."""
    p = tmp_path / "ok.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nf 1/1 2/1 3/1\nf -4 -3 -1\n# f 0 1 2\n")
    F, P = load_sequence(str(p))
    assert F.tolist() == [[0, 1, 2], [0, 1, 3]]


@pytest.mark.parametrize("spec,match", [
    ("0:1000", "--frames: '0:1000' goes past the last frame: the input has 30 frames"),
    ("29:31", "--frames: '29:31' goes past the last frame"),
    ("-5:", r"--frames: '-5:': frames are counted from 0"),
    ("3:-1", r"--frames: '3:-1': frames are counted from 0"),
    ("-1", r"--frames: '-1': frames are counted from 0"),
    ("5:5", "--frames: '5:5' selects no frame"),
    ("30", "--frames: '30' selects no frame"),
])
def test_frame_specs_are_never_clamped(spec, match):
    with pytest.raises(ValueError, match=match):
        parse_frames(spec, 30)


def test_frame_specs():
    assert parse_frames("2:5", 30) == range(2, 5) and parse_frames("27:", 30) == range(27, 30)
    assert parse_frames(":3", 30) == range(0, 3) and parse_frames("29", 30) == range(29, 30)
    assert parse_frames(None, 30) == range(30)


def test_scene_listing_columns_line_up():
    lines = datasets.describe()
    for word in (" triangles", " frames", " resolution"):
        assert len({line.index(word) for line in lines}) == 1, word
    # the description (last column) starts at the same place on every line
    starts = {line.index(s.description) for line, s in zip(lines, datasets.SCENES.values())}
    assert len(starts) == 1


def test_bad_frame_folders_are_named(tmp_path):
    d = tmp_path / "frames"
    d.mkdir()
    (d / "notes.txt").write_text("no meshes here")
    with pytest.raises(ValueError, match=r"INPUT: folder '.*frames' has no \.obj or \.ply frames"):
        load_sequence(str(d))
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    trimesh.Trimesh(V, TRI, process=False).export(d / "f0.ply")
    trimesh.Trimesh(np.vstack([V, [[5, 5, 5]]]), TRI, process=False).export(d / "f1.ply")  # one vertex more
    with pytest.raises(ValueError, match=r"INPUT: frame 'f1\.ply' has 4 vertices, 'f0\.ply' has 3"):
        load_sequence(str(d))


def test_valid_forms_are_accepted(tmp_path):
    """What NumPy and the standard library accept stays accepted: a 0-d array as a number, None or
    a SeedSequence as a seed, pathlib paths, exact wider dtypes."""
    F, V = generated.grid_sheet(5, 5)
    assert np.array_equal(generated.fold(V, np.array(1.0)), generated.fold(V, 1.0))
    a = generated.crumpling_sphere(8, 12, 2, seed=np.random.SeedSequence(1))[1]
    b = generated.crumpling_sphere(8, 12, 2, seed=np.random.SeedSequence(1))[1]
    assert np.array_equal(a, b) and np.isfinite(generated.crumpling_sphere(8, 12, 2, seed=None)[1]).all()
    path = tmp_path / "m.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    np.savez(tmp_path / "p.npz", positions=np.zeros((2, 3, 3), np.longdouble))  # exact: accepted
    Fl, P = load_sequence(path, positions=tmp_path / "p.npz")
    assert P.shape == (2, 3, 3) and P.dtype == np.float64


def test_inexact_positions_are_refused(tmp_path):
    path = tmp_path / "m.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    P = np.zeros((2, 3, 3), np.longdouble) + np.longdouble(2.0) ** -60 + 1
    np.savez(tmp_path / "p.npz", positions=P)
    with pytest.raises(ValueError, match=r"positions: some float128 coordinates are not exactly float64"):
        load_sequence(str(path), positions=str(tmp_path / "p.npz"))


def test_a_face_beyond_a_files_vertices_is_named(tmp_path):
    """The file has 3 vertices and a face refers to a sixth: the file and its vertex count are
    named (not Mesh's n_vertices, which no one passed)."""
    (tmp_path / "bad.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n")
    with pytest.raises(ValueError, match=r"bad\.ply: face 0 \(counted from 0\): a face refers to vertex 5 \(counted "
                                         r"from 0\), but the file has 3 vertices"):
        load_sequence(str(tmp_path / "bad.ply"))


def _corrupt_deflate(p, F, P):
    np.savez_compressed(p, faces=F, positions=P)
    b = bytearray(p.read_bytes())
    b[len(b) // 2 : len(b) // 2 + 64] = bytes(64)  # inside the compressed positions
    p.write_bytes(bytes(b))


def _huge_header(p, F, P):
    """positions.npy's header claims a shape beyond int64 (numpy raised OverflowError: found by
    review, a traceback from the CLI, whose exit code 1 reads as "collides")."""
    import io
    import zipfile

    with zipfile.ZipFile(p, "w") as z:
        b = io.BytesIO()
        np.lib.format.write_array(b, F)
        z.writestr("faces.npy", b.getvalue())
        b = io.BytesIO()
        np.lib.format.write_array_header_1_0(b, {"descr": "<f8", "fortran_order": False, "shape": (P.shape[0], 10**30, 3)})
        z.writestr("positions.npy", b.getvalue() + bytes(100))


def _replaced(faces=None, positions=None):
    def damage(p, F, P):
        np.savez(p, faces=F if faces is None else faces(F), positions=P if positions is None else positions(P))
    return damage


@pytest.mark.parametrize("damage,why", [
    (lambda p, F, P: p.write_bytes(p.read_bytes()[:100]), ""),
    (lambda p, F, P: p.write_bytes(b""), ""),
    (_corrupt_deflate, ""),
    (_huge_header, ""),
    (lambda p, F, P: np.savez(p, faces=F), "no array 'positions'"),
    (_replaced(positions=lambda P: np.full_like(P, np.nan)), "a non-finite position"),
    (_replaced(positions=lambda P: np.full_like(P, 1e300)), r"coordinate 1e\+300 in frame 0 .* outside the supported range"),
    (_replaced(faces=lambda F: np.where(F == 0, 10**6, F)), r"face ids outside \[0, \d+\)"),
    (_replaced(faces=lambda F: np.column_stack([F[:, 0], F[:, 0], F[:, 2]])), "a triangle repeats a vertex"),
    (_replaced(faces=lambda F: F[:1]), r"1 triangles, the scene has \d+"),
    (_replaced(faces=lambda F: F[:0], positions=lambda P: P[:, :0]), r"0 triangles, the scene has \d+"),
    (_replaced(positions=lambda P: P[:2]), r"positions float64 \(2, \d+, 3\)"),
])
def test_a_damaged_cache_file_is_named(cache, damage, why):
    """A cached scene is checked when read, as it was before it was written: a damaged file is a
    ValueError naming it (and saying to delete it), never a sequence handed out (an empty scene
    was, and `check` then found "no collision")."""
    F, P = datasets.load("fold", resolution=4)
    (path,) = cache.glob("fold-*.npz")
    damage(path, F, P)
    with pytest.raises(ValueError, match=rf"cache: '.*fold-.*\.npz' is damaged or not a scene cache \({why}.*delete it"):
        datasets.load("fold", resolution=4)
    path.unlink()  # as the message says: the next load generates it again
    F2, P2 = datasets.load("fold", resolution=4)
    assert np.array_equal(F2, F) and np.array_equal(P2, P)


def test_a_cache_path_that_is_a_file(tmp_path, monkeypatch):
    """Refused before generating (the scene would be lost at the end otherwise)."""
    (tmp_path / "file").write_text("")
    monkeypatch.setenv("CONECULL_CACHE", str(tmp_path / "file"))
    with pytest.raises(ValueError, match=r"CONECULL_CACHE: '.*file' is not a folder"):
        datasets.load("fold", resolution=4)


def test_a_cache_that_cannot_be_written(tmp_path, monkeypatch):
    """Refused before generating, naming CONECULL_CACHE: a folder under a file, and one under a
    read-only file system (found by probing: both generated the scene, then gave a raw
    NotADirectoryError or PermissionError traceback). Nothing is generated."""
    (tmp_path / "file").write_text("")
    calls = []
    monkeypatch.setitem(datasets.SCENES, "fold", dataclasses.replace(datasets.SCENES["fold"], generate=lambda *a: calls.append(a)))
    for folder, why in ((tmp_path / "file" / "sub", "Not a directory"), ("/proc/conecull-cache", "No such file")):
        monkeypatch.setenv("CONECULL_CACHE", str(folder))
        with pytest.raises(ValueError, match=rf"CONECULL_CACHE: cannot write scenes to '{folder}' \({why}"):
            datasets.load("fold", resolution=4)
    assert not calls
    monkeypatch.delenv("CONECULL_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "file"))
    with pytest.raises(ValueError, match=r"the cache folder \(set CONECULL_CACHE to a writable folder to use "
                                         r"another\): cannot write scenes to '.*file/conecull'"):
        datasets.load("fold", resolution=4)


@pytest.mark.parametrize("make,match", [
    (lambda: generated.crumpling_sphere(3, 3, 3, strength=1.7e308), r"strength: the positions would reach"),
    (lambda: generated.bending_sheet(50, 3, amplitude=1e300), r"amplitude: the positions would reach"),
    (lambda: generated.uv_sphere(3, 3, radius=1e-300), r"radius: the positions would reach 1e-300"),
    (lambda: generated.grid_sheet(3, 3, width=1e300), r"width, height: the positions would reach"),
    (lambda: generated.fold(generated.grid_sheet(4, 4)[1], 3.0, x0=-1e308), r"angle, x0, radius: the positions"),
    (lambda: generated.folding_sheet(50, 3, final_angle=1e-300), r"final_angle: the positions would reach"),
])
def test_generators_never_return_positions_a_query_refuses(make, match):
    """Finite arguments can still overflow (crumpling_sphere(strength=1.7e308) returned inf with
    only NumPy's RuntimeWarning): refused, naming the argument, with no warning on the way."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=match):
            make()


def test_generators_at_the_edge_of_the_query_range_still_query():
    """What the generators accept, the queries accept: a sphere of radius 2^100 (its coordinates
    up to 2^100, the smallest non-zero ones far above 2^-128) answers a query."""
    F, V = generated.uv_sphere(6, 8, radius=2.0**100)
    assert conecull.SelfCollider(conecull.Mesh(F)).dcd(V).pairs.shape == (0, 2)
