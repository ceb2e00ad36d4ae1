"""The README's screenshot tool captures a view once it stops changing (the web viewer can still be
ingesting a recording after any fixed wait), with a cap and a warning when it never settles."""

from conecull.viz import screenshots


class _Page:
    def __init__(self, shots):
        self.shots, self.taken = list(shots), 0

    def screenshot(self):
        shot = self.shots[min(self.taken, len(self.shots) - 1)]
        self.taken += 1
        return shot


def test_waits_until_two_shots_in_a_row_agree(tmp_path, monkeypatch):
    monkeypatch.setattr(screenshots.time, "sleep", lambda s: None)
    page = _Page([b"frame 30", b"frame 35", b"frame 40", b"frame 40"])
    path = tmp_path / "a.png"
    screenshots._settled_screenshot(page, str(path), wait=0.0)
    assert path.read_bytes() == b"frame 40" and page.taken == 4


def test_gives_up_after_the_limit_with_a_warning(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(screenshots.time, "sleep", lambda s: None)
    clock = iter(range(0, 10_000, 100))
    monkeypatch.setattr(screenshots.time, "monotonic", lambda: next(clock))
    page = _Page([str(k).encode() for k in range(100)])  # never the same twice
    path = tmp_path / "b.png"
    screenshots._settled_screenshot(page, str(path), wait=1.0, limit=250.0)
    assert "still changing" in capsys.readouterr().out
    assert path.read_bytes() == str(page.taken - 1).encode()
