"""app/tight_cones.py: the replay of Alg. 2 reproduces the core's counters (box tests and
elementary tests) on every frame of two scenes, and culling more nodes never adds a test."""

import numpy as np
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


def test_the_command_names_unknown_steps(capsys):
    assert main(["no-such-step"]) == 1
    assert "no shared steps" in capsys.readouterr().out
