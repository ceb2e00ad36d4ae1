"""Scene registry: names, determinism, the disk cache (and its override), bad arguments, every
scene at a small resolution, and file loaders that keep coincident vertices apart."""

import numpy as np
import pytest
import trimesh

import conecull
from conecull import datasets
from conecull.datasets import generated
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
    F2, P2 = scene.generate(8, 4, scene.dt)
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


def test_listing_states_the_paper_scene_each_stands_for():
    lines = datasets.describe()
    for paper in ("Funnel", "Twisting", "FlowingCloth", "Falling", "Flamenco", "SquishyBall"):
        assert sum(paper in line for line in lines) == 1
    for s in datasets.SCENES.values():  # the listing's triangle count is the generated one
        if s.triangles(8) < 5000:
            F, _ = s.generate(8, 1, s.dt)
            assert len(F) == s.triangles(8), s.name


def test_paper_sized_defaults():
    """Default resolutions give the paper's sizes (Sec. 5.2), within 10%."""
    target = {"funnel": 64_000, "twisting": 64_000, "flowing": 50_000, "falling": 170_000, "flamenco": 49_000,
              "squishy": 1_000_000}
    for name, n in target.items():
        s = datasets.SCENES[name]
        assert abs(s.triangles(s.default_resolution) - n) <= 0.1 * n, name


def test_squishy_ball_is_one_closed_consistently_oriented_surface():
    from conecull.datasets import squishy

    F, V, tentacle, _ = squishy.squishy_ball(24)
    he = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    assert len(np.unique(he, axis=0)) == len(he)  # no directed edge twice: consistent orientation
    assert set(map(tuple, he.tolist())) == set(map(tuple, he[:, ::-1].tolist()))  # closed
    m = conecull.Mesh(F, n_vertices=len(V))
    assert m.n_components == 1 and len(m.nonmanifold_vertices) == 0 and tentacle.max() + 1 == 96
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    assert np.einsum("ij,ij->", V[F[:, 0]], n) > 0  # outward: positive volume
    assert len(conecull.SelfCollider(m).dcd(V).pairs) == 0  # the rest pose does not touch itself


def test_flamenco_folds_press_together_later():
    F, P = datasets.load("flamenco", resolution=24, frames=30)
    col = conecull.SelfCollider(conecull.Mesh(F))
    counts = [len(col.dcd(V).pairs) for V in P]
    assert counts[0] == 0 and max(counts[15:]) > 0


@pytest.mark.parametrize("kwargs,match", [
    ({"name": "nope"}, "name: unknown scene 'nope'"),
    ({"name": "fold", "resolution": 1}, "resolution: expected an integer >= 3"),
    ({"name": "fold", "frames": 0}, "frames: expected an integer in \\[1, 10000\\]"),
    ({"name": "fold", "frames": 2.5}, "frames: expected an integer in \\[1, 10000\\]"),
    ({"name": ["fold"]}, r"name: unknown scene \['fold'\]"),
    ({"name": "squishy", "resolution": 3, "frames": 2}, "resolution: 3 does not suit scene 'squishy'"),
])
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        datasets.load(**kwargs)


@pytest.mark.parametrize("call,match", [
    (lambda: generated.uv_sphere(1, 3), "n_lat: expected an integer >= 2, got 1"),
    (lambda: generated.uv_sphere(3, 0), "n_lon: expected an integer >= 3, got 0"),
    (lambda: generated.folding_sheet(0, 3), "n_triangles: expected an integer >= 2, got 0"),
    (lambda: generated.folding_sheet(-100, 3), "n_triangles: expected an integer >= 2, got -100"),
    (lambda: generated.folding_sheet(10, 0), "n_frames: expected an integer >= 1, got 0"),
    (lambda: generated.crumpling_sphere(2, 3, 0), "n_frames: expected an integer >= 1, got 0"),
    (lambda: generated.grid_sheet(2.5, 3), "nx: expected an integer >= 2, got 2.5"),
])
def test_generators_name_bad_sizes(call, match):
    """No silent clamping and no NumPy message: each bad size is named."""
    with pytest.raises(ValueError, match=match):
        call()


def test_smallest_uv_sphere_is_a_valid_closed_mesh():
    F, V = generated.uv_sphere(2, 3)
    assert F.min() >= 0 and F.max() < len(V) and F.shape == (6, 3)
    conecull.Mesh(F, n_vertices=len(V))


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


def test_complex_positions_are_refused(tmp_path):
    """np.asarray(..., float64) would drop the imaginary part with only a warning."""
    mesh = tmp_path / "t.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    np.savez(tmp_path / "c.npz", positions=np.full((2, 3, 3), 1j))
    with pytest.raises(ValueError, match="positions: expected real coordinates"):
        load_sequence(str(mesh), positions=str(tmp_path / "c.npz"))


def test_a_new_version_replaces_its_stale_cache_file(cache, monkeypatch):
    """Generators or core changed: the scene's file for the same resolution and frame count is
    replaced, not kept beside the new one for ever; other sizes, files without the stored 'meta'
    (written before it was) and files that are not cache files stay."""
    from conecull.datasets import registry

    datasets.load("roll", resolution=10, frames=3)
    datasets.load("roll", resolution=11, frames=3)
    datasets.load("roll", resolution=10, frames=4)
    datasets.load("crumple", resolution=4, frames=3)
    before = {f.name for f in cache.glob("*.npz")}
    assert len(before) == 4
    legacy = cache / "roll-0123456789abcdef.npz"
    np.savez(legacy, faces=np.zeros((1, 3), np.int64), positions=np.zeros((3, 3, 3)))
    (cache / "roll-notes.npz").write_bytes(b"not ours")
    monkeypatch.setattr(registry, "_code_digest", lambda: "generators edited")
    F, P = datasets.load("roll", resolution=10, frames=3)
    after = {f.name for f in cache.glob("*.npz")}
    new = after - before - {legacy.name, "roll-notes.npz"}
    assert len(new) == 1 and len(after) == 7 - 1  # the 10 x 3 file of the old version is gone
    gone = before - after
    assert len(gone) == 1 and gone.pop().startswith("roll-")
    datasets.load("roll", resolution=11, frames=3)  # the other sizes were kept, stale too: replaced when loaded
    final = {f.name for f in cache.glob("*.npz")}
    assert len(final) == 6 and len(final - after) == 1 and len(after - final) == 1
    F2, P2 = datasets.load("roll", resolution=10, frames=3)  # the new file is read back
    assert np.array_equal(P, P2) and legacy.exists() and (cache / "roll-notes.npz").exists()


def test_cache_key_follows_the_core_for_simulated_scenes(monkeypatch):
    """A simulated scene's self-contact runs the core's exact CCD every substep: another core
    (any rebuild: its binary is hashed) gets another cache entry; a kinematic scene does not."""
    from conecull.datasets import registry

    simulated, kinematic = registry.SCENES["falling"], registry.SCENES["fold"]
    assert simulated.effects and not kinematic.effects
    before = registry._key(simulated, 10, 5), registry._key(kinematic, 10, 5)
    monkeypatch.setattr(registry, "_core_digest", lambda: "another core")
    after = registry._key(simulated, 10, 5), registry._key(kinematic, 10, 5)
    assert after[0] != before[0] and after[1] == before[1]


def test_listing_gives_each_scenes_resolution_and_its_least(tmp_path, monkeypatch):
    """`conecull scenes` names the default resolution and the least `load` takes (--resolution's
    range was learnt only from an error): the least loads, one less is refused naming it."""
    import pytest

    from conecull.datasets.registry import min_resolution

    monkeypatch.setenv("CONECULL_CACHE", str(tmp_path))
    lines = dict(zip(datasets.SCENES, datasets.describe()))
    for name, s in datasets.SCENES.items():
        assert f"resolution {s.default_resolution} (>= {min_resolution(s)})" in lines[name], name
    assert min_resolution(datasets.SCENES["squishy"]) == 8
    F, P = datasets.load("squishy", resolution=8, frames=2)
    assert len(F) == datasets.SCENES["squishy"].triangles(8)
    with pytest.raises(ValueError, match=r"resolution: 7 does not suit scene 'squishy'"):
        datasets.load("squishy", resolution=7, frames=2)


def test_cache_key_covers_what_generates_and_not_the_loaders(tmp_path):
    """The code digest reads the modules the scenes' generation imports (found statically): every
    module of the package that generating a kinematic and a simulated scene actually loads is
    among them, and the loaders of real data, which cannot change a generated sequence, are not."""
    import subprocess
    import sys

    from conecull.datasets import registry

    sources = {str(f) for f in registry.generation_sources()}
    script = ("import sys\nfrom conecull.datasets import registry\n"
              "registry.load('fold', resolution=6, frames=2)\nregistry.load('falling', resolution=6, frames=2)\n"
              "print('\\n'.join(m.__file__ for n, m in sys.modules.items() if n.startswith('conecull.datasets')))")
    env = {**__import__("os").environ, "CONECULL_CACHE": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, check=True).stdout
    loaded = set(out.split())
    assert loaded and loaded <= sources, loaded - sources
    assert any(f.endswith("simulator.py") for f in loaded)
    names = {f.rsplit("/", 1)[-1] for f in sources}
    assert not names & {"mesh_files.py", "inputs.py", "shared.py"}
    assert {"registry.py", "cloth.py", "simulator.py", "contact.py"} <= names
