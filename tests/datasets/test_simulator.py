"""The simulator computes exactly the effects a scene declares, deterministically, and the
simulated scenes stay finite and plausible at small resolutions."""

import numpy as np
import pytest

from conecull.datasets import generated
from conecull.datasets.sim import Bend, Gravity, PinnedVertices, PlaneCollider, Simulator, SphereCollider, Stretch, Wind


def sheet(n=6):
    F, V = generated.grid_sheet(n, n)
    return F, V + [0.0, 0.0, 0.5]


def test_only_declared_effects_run(monkeypatch):
    def never(*_):
        raise AssertionError("an undeclared effect was computed")

    for cls, stage in ((Stretch, "constrain"), (Bend, "constrain"), (Wind, "force"), (PlaneCollider, "collide"),
                       (SphereCollider, "collide")):
        monkeypatch.setattr(cls, stage, never)
    F, V = sheet()
    sim = Simulator(F, V, [Gravity()])
    X = sim.run(5)
    assert set(sim.calls) == {("Gravity", "force")}
    assert X[-1][:, 2].max() < 0.5  # it fell


def test_declared_effects_all_run_and_are_deterministic():
    F, V = sheet()
    effects = lambda: [Gravity(), Wind(), Stretch(), Bend(), PinnedVertices([0, 5]),  # noqa: E731
                       SphereCollider((0.5, 0.5, 0.2), 0.2, (0, 0, 3.0)), PlaneCollider(0.0)]
    a = Simulator(F, V, effects())
    Xa = a.run(6)
    Xb = Simulator(F, V, effects()).run(6)
    assert np.array_equal(Xa, Xb)
    ran = {name for name, _ in a.calls}
    assert ran == {"Gravity", "Wind", "Stretch", "Bend", "PinnedVertices", "SphereCollider", "PlaneCollider"}
    assert np.array_equal(Xa[-1][[0, 5]], V[[0, 5]])  # pinned vertices stay put
    assert np.isfinite(Xa).all() and Xa[-1][:, 2].min() >= -1e-9  # the floor holds


SIMULATED = ["funnel", "twisting", "flowing", "falling"]


@pytest.mark.parametrize("name", SIMULATED)
def test_simulated_scenes_small(name):
    from conecull import datasets

    F, P = datasets.load(name, resolution=10, frames=6)
    assert np.isfinite(P).all()
    edge = np.linalg.norm(P[:, F[:, 1]] - P[:, F[:, 0]], axis=2)
    assert edge.max() < 3.0 * edge[0].max()  # stretch constraints keep the cloth from exploding


def test_self_contact_keeps_a_squeezed_cloth_free_of_intersections():
    """A sheet whose pinned edges move together buckles through itself without self-contact;
    with it (conecull's own CCD) no frame has a DCD intersection."""
    import conecull
    from conecull.datasets.sim import SelfContact

    n = 12
    F, V = generated.grid_sheet(n, n)
    V = V - [0.5, 0.5, 0] + [0, 0, 0.6]
    edges = [i * n for i in range(n)] + [i * n + n - 1 for i in range(n)]

    def squeeze(t, rest):
        out = rest.copy()
        out[:, 0] = rest[:, 0] * (1 - 0.85 * min(t / 0.8, 1.0))
        return out

    col = conecull.SelfCollider(conecull.Mesh(F))

    def run(extra):
        sim = Simulator(F, V, [Gravity(), Stretch(), Bend(1e-2), PinnedVertices(edges, squeeze)] + extra)
        return [len(col.dcd(x).pairs) for x in sim.run(60)]

    assert max(run([])) > 0  # the scenario really self-intersects without self-contact
    assert max(run([SelfContact()])) == 0


@pytest.mark.parametrize("name", SIMULATED)
def test_a_scene_runs_exactly_the_effects_it_declares(name):
    """Every declared effect runs; nothing else is even constructed (the simulator refuses a
    set-up whose effects differ from the declaration)."""
    from conecull.datasets import cloth, registry

    scene = registry.SCENES[name]
    F, V, built, options = getattr(cloth, name)(8)
    sim = Simulator(F, V, built, dt=scene.dt, declared=scene.effects, **options)
    sim.run(3)
    assert {e.name for e in built} == set(scene.effects)
    ran = {type(e).__name__ for e in built}
    assert {cls for cls, _ in sim.calls} == ran
    with pytest.raises(ValueError, match="effects: the scene declares"):
        Simulator(F, V, built, declared=scene.effects + ("wind",) if "wind" not in scene.effects else ("gravity",))


def test_colliders_push_out():
    from conecull.datasets.sim import CapsuleCollider, FunnelCollider

    F, V = sheet(4)
    sim = Simulator(F, V, [CapsuleCollider((0.5, 0.5, 0.0), (0.5, 0.5, 1.0), 0.3)])
    sim.p = sim.x.copy()
    sim._run("collide", 0.01)
    d = np.linalg.norm(sim.p[:, :2] - [0.5, 0.5], axis=1)
    assert (d >= 0.3 - 1e-12).all()
    # funnel: a point inside moving out through the wall stays inside
    sim = Simulator(F, V, [FunnelCollider(z_bottom=0.0, z_top=1.0, r_hole=0.1)])
    sim.x[:] = [0.0, 0.0, 0.5]
    sim.p = sim.x + [1.0, 0.0, 0.0]
    sim._run("collide", 0.01)
    R = 0.1 + 0.5 * np.tan(np.radians(35.0))
    assert (np.linalg.norm(sim.p[:, :2], axis=1) <= R + 1e-9).all()


@pytest.mark.parametrize("name,resolution,frames", [("funnel", 10, 30), ("falling", 16, 30), ("twisting", 14, 30)])
def test_self_contact_scenes_stay_intersection_free(name, resolution, frames):
    import conecull
    from conecull import datasets

    F, P = datasets.load(name, resolution=resolution, frames=frames)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]))
    assert all(len(col.dcd(x).pairs) == 0 for x in P)
    assert P[-1][:, 2].max() < P[0][:, 2].max()  # it fell


def test_affine_dependency_is_exact_on_fractions():
    """IsometricBend's weights (signed-area cofactors, by Cramer) against their definition, in
    exact arithmetic: sum K = 0 and sum K p = 0 for four rational points of a plane, K_c + K_d = 2,
    and swapping c and d swaps K_c and K_d."""
    from fractions import Fraction as Q

    from conecull.datasets.sim.effects.constraints import affine_dependency

    def side(p, a, b):
        return (b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])

    rng = np.random.default_rng(7)
    tested = 0
    for _ in range(300):
        coordinate = lambda: Q(int(rng.integers(-50, 50)), int(rng.integers(1, 9)))  # noqa: E731
        pts = [(coordinate(), coordinate()) for _ in range(4)]
        a, b, c, d = pts
        if side(c, a, b) * side(d, a, b) >= 0:
            continue  # c and d not on opposite sides of line ab: not a hinge
        K = affine_dependency(a, b, c, d)
        assert K[2] + K[3] == 2
        assert sum(K) == 0
        assert sum(k * p[0] for k, p in zip(K, pts)) == 0 and sum(k * p[1] for k, p in zip(K, pts)) == 0
        assert affine_dependency(a, b, d, c) == (K[0], K[1], K[3], K[2])
        tested += 1
    assert tested > 100


def _hinge(rng):
    """A random flat hinge in 3D: a, b (the edge), c on one side, d on the other, each (1, 3)."""
    u, w = np.linalg.qr(rng.standard_normal((3, 2)))[0].T
    o = rng.standard_normal(3)
    at = lambda x, y: (o + x * u + y * w)[None, :]  # noqa: E731
    return at(0.0, 0.0), at(1.0, 0.0), at(rng.uniform(-0.5, 1.5), rng.uniform(0.3, 1.0)), \
        at(rng.uniform(-0.5, 1.5), -rng.uniform(0.3, 1.0))


def test_isometric_bend_is_zero_at_rest_and_grows_linearly_with_the_fold():
    """C = sum K_j x_j is zero on the flat rest hinge (so on any affine image of it: sum K = 0) and
    grows like the fold angle."""
    from conecull.datasets.sim.effects.constraints import hinge_weights

    rng = np.random.default_rng(3)
    for _ in range(50):
        a, b, c, d = _hinge(rng)
        K = hinge_weights(a, b, c, d)[0]
        X = np.concatenate([a, b, c, d])
        assert abs(K.sum()) < 1e-12 and np.abs(K @ X).max() < 1e-12
        axis = (b - a)[0] / np.linalg.norm(b - a)

        def fold(t):  # d turned about the edge by angle t
            v = (d - a)[0]
            v = v * np.cos(t) + np.cross(axis, v) * np.sin(t) + axis * (axis @ v) * (1 - np.cos(t))
            return np.concatenate([a, b, c, (a[0] + v)[None, :]])

        small, smaller = (np.linalg.norm(K @ fold(t)) / t for t in (1e-2, 1e-3))
        assert small > 0.05 and abs(small / smaller - 1) < 0.01  # linear in the angle


def test_isometric_bend_keeps_a_squeezed_sheet_from_crinkling():
    """A sheet whose opposite edges are pushed together must buckle. With Bend (no resistance
    near flat) it crinkles at the scale of single triangles; with IsometricBend it folds smoothly:
    the falling scene's robe, gathered around the body, is the same situation."""
    import conecull
    from conecull.datasets.sim import IsometricBend

    n = 32
    F, V = generated.grid_sheet(n, n)
    edges = np.flatnonzero((V[:, 0] < 1e-9) | (V[:, 0] > V[:, 0].max() - 1e-9))

    def squeeze(t, rest):
        out = rest.copy()
        s = min(t / 0.4, 1.0) * 0.35
        out[:, 0] = np.where(rest[:, 0] < 0.5, rest[:, 0] + s / 2, rest[:, 0] - s / 2)
        return out

    off, ef = conecull.Mesh(F).edge_faces
    inner = np.flatnonzero(np.diff(off) == 2)
    f1, f2 = ef[off[inner]], ef[off[inner] + 1]

    def sharp_hinges(bend, seed):
        sim = Simulator(F, V, [Stretch(), bend, PinnedVertices(edges, squeeze)])  # flat at rest
        sim.x[:, 2] += 1e-4 * np.random.default_rng(seed).standard_normal(len(V))  # then off the plane
        X = sim.run(30)[-1]
        N = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
        N /= np.linalg.norm(N, axis=1)[:, None]
        return float((np.einsum("ij,ij->i", N[f1], N[f2]) < np.cos(np.radians(30.0))).mean())

    for seed in range(4):  # each start (1e-4 noise off the plane): 2.2-2.6% against 9.2-11.5% when written
        isometric, distance = sharp_hinges(IsometricBend(1e-6), seed), sharp_hinges(Bend(1e-6), seed)
        assert isometric < 0.05 < distance and distance > 2.5 * isometric, (seed, isometric, distance)


def test_isometric_bend_refuses_a_bent_rest_pose_and_leaves_degenerate_hinges_free():
    """A curved rest pose would be flattened by IsometricBend: refused, naming a hinge. A hinge
    with a zero-area face has no weights: left out, the others kept."""
    from conecull.datasets.sim import IsometricBend

    F, V = sheet(5)
    bent = V.copy()
    bent[:, 2] += 0.3 * bent[:, 0] ** 2  # a parabolic cylinder
    with pytest.raises(ValueError, match="positions: IsometricBend needs a flat rest pose"):
        Simulator(F, bent, [IsometricBend()])
    flat = Simulator(F, V, [IsometricBend()]).effects[0]
    squashed = V.copy()
    squashed[F[0, 2]] = 0.5 * (squashed[F[0, 0]] + squashed[F[0, 1]])  # face 0 has no area
    kept = Simulator(F, squashed, [IsometricBend()]).effects[0]
    assert 0 < len(kept.q) < len(flat.q) and np.isfinite(kept.K).all()
    X = Simulator(F, squashed, [Gravity(), IsometricBend()]).run(5)
    assert np.isfinite(X).all()
