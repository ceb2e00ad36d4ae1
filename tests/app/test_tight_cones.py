"""app/tight_cones.py: the replay of Alg. 2 reproduces the core's counters (box tests and
elementary tests) on frames of two scenes, culling more nodes never adds a test, and the nodes
that would pass do cull more."""

import pytest

from conecull.app.tight_cones import main, tight_cone_gain
from conecull.datasets import load


@pytest.mark.parametrize("scene", ["crumple", "fold"])
def test_the_replay_counts_as_the_core(scene):
    F, P = load(scene)
    gains = [tight_cone_gain(F, P[0], V) for V in [*P[::4], P[25]]]  # raises if the replay and the core differ
    for g in gains:
        assert g["tight_bv_tests"] <= g["bv_tests"] and g["tight_elementary_tests"] <= g["elementary_tests"]
        assert g["would_pass"] <= g["within"] <= g["failed_cones"]
    assert any(g["within"] for g in gains)
    assert any(g["tight_bv_tests"] < g["bv_tests"] and g["tight_elementary_tests"] < g["elementary_tests"]
               for g in gains)


def test_the_command_names_an_unknown_step(capsys):
    from shared_data import DATA, require

    require(DATA / "scalable-ccd")
    assert main(["armadillo-rollers", "no-such-step"]) == 2
    assert "STEP: unknown step 'no-such-step'; known: armadillo-rollers" in capsys.readouterr().err
