"""Scene registry: names, determinism, the disk cache (and its override), bad arguments, every
scene at a small resolution, and file loaders that keep coincident vertices apart."""

import numpy as np
import pytest
import trimesh

import conecull
from conecull import datasets
from conecull.app.cli import main
from conecull.datasets.inputs import load_sequence


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CONECULL_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_names_and_listing(capsys):
    assert {"fold", "roll", "crumple", "bend"} <= set(datasets.names())
    assert main(["scenes"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == len(datasets.names()) and all("triangles" in line for line in out)


@pytest.mark.parametrize("name", datasets.names())
def test_every_scene_small_and_deterministic(name):
    F, P = datasets.load(name, resolution=8, frames=4)
    assert F.ndim == 2 and F.shape[1] == 3 and P.shape[0] == 4 and P.shape[2] == 3
    assert np.isfinite(P).all() and F.max() < P.shape[1]
    scene = datasets.SCENES[name]
    F2, P2 = scene.generate(8, 4)
    assert np.array_equal(F, F2) and np.array_equal(P, P2)
    conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1])).dcd(P[-1])


def test_second_load_is_a_file_read(cache, monkeypatch):
    F, P = datasets.load("roll", resolution=10, frames=3)
    assert len(list(cache.glob("roll-*.npz"))) == 1
    scene = datasets.SCENES["roll"]

    def boom(*_):
        raise AssertionError("generated again instead of read from the cache")

    monkeypatch.setitem(datasets.SCENES, "roll", type(scene)(**{**scene.__dict__, "generate": boom}))
    F2, P2 = datasets.load("roll", resolution=10, frames=3)
    assert np.array_equal(F, F2) and np.array_equal(P, P2)


def test_teaching_scenes_do_what_they_say():
    F, P = datasets.load("roll", resolution=24, frames=12)
    col = conecull.SelfCollider(conecull.Mesh(F))
    counts = [len(col.dcd(V).pairs) for V in P]
    assert counts[0] == 0 and counts[-1] > 0  # flat at first, touches itself in the end
    F, P = datasets.load("bend", resolution=16, frames=5)
    col = conecull.SelfCollider(conecull.Mesh(F))
    assert all(len(col.dcd(V).pairs) == 0 for V in P)


@pytest.mark.parametrize("kwargs,match", [
    ({"name": "nope"}, "name: unknown scene 'nope'"),
    ({"name": "fold", "resolution": 1}, "resolution: expected an integer >= 3"),
    ({"name": "fold", "frames": 0}, "frames: expected an integer >= 1"),
    ({"name": "fold", "frames": 2.5}, "frames: expected an integer >= 1"),
])
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        datasets.load(**kwargs)


@pytest.mark.parametrize("ext", ["obj", "ply"])
def test_loader_round_trip_keeps_coincident_vertices(tmp_path, ext):
    """Two vertices at the same position (a seam) must stay two vertices."""
    F = np.array([[0, 1, 2], [3, 4, 5]])
    V0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0], [1, 0, 0], [0, -1, 0.0]])  # 3, 4 duplicate 0, 1
    frames = [V0, V0 + [0.0, 0.0, 0.25]]
    d = tmp_path / "frames"
    d.mkdir()
    for k, V in enumerate(frames):
        trimesh.Trimesh(V, F, process=False).export(d / f"f{k}.{ext}")
    F2, P = load_sequence(str(d))
    assert np.array_equal(F2, F) and np.array_equal(P, np.stack(frames))
