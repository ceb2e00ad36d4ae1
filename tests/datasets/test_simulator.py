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
