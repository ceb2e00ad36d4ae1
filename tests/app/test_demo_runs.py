"""The main job, as `./dev.sh demo` runs it: `conecull demo` runs headless, writes its recording,
and the recording holds, frame by frame, the collisions an untraced query of the same scene finds."""

import numpy as np

import conecull
from conecull.app.cli import main
from conecull.datasets.inputs import DEFAULT_SCENE, load_sequence
from rrd_helpers import rows_by_frame


def test_demo_writes_a_recording_of_every_frame(tmp_path, capsys):
    out = tmp_path / "demo.rrd"
    assert main(["demo", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert out.stat().st_size > 0 and str(out) in printed
    F, frames = load_sequence(DEFAULT_SCENE)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method="nc")
    want = [len(col.dcd(V).pairs) for V in frames]
    assert any(want) and not all(want)  # the sheet folds until it passes through itself
    got = rows_by_frame(str(out), "/stats/collisions", "Scalars:scalars")
    assert sorted(got) == list(range(len(frames)))
    assert [int(np.asarray(v)[0]) for _, v in sorted(got.items())] == want
    table = [line.split() for line in printed.splitlines() if line.split() and line.split()[0].isdigit()]
    assert [int(r[0]) for r in table] == list(range(len(frames)))
    assert [int(r[5]) for r in table] == want  # the "colliding" column
    # the triage command it prints names the first colliding frame and a pair of it, and runs
    line = next(x for x in printed.splitlines() if x.startswith("why a collision was not culled away: "))
    words = line.split(": ", 1)[1].split()
    first = want.index(next(w for w in want if w))
    assert words[1:5] == ["explain", DEFAULT_SCENE, "--frame", str(first)] and words[5] == "--pair"
    i, j = int(words[6]), int(words[7])
    assert (i, j) in {tuple(p) for p in col.dcd(frames[first]).pairs.tolist()}
    assert main(words[1:]) == 0 and f"triangles {i} and {j} intersect" in capsys.readouterr().out
