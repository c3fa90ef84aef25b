"""Issue 24: no command is silent for longer than a few seconds. The heartbeat of a long stage
(`ocp.core.heartbeat`) writes a line from QUIET_S on, every EVERY_S, and nothing for a short one."""

import io
import time

from ocp.core import heartbeat as beats


def test_a_long_stage_beats_and_a_short_one_is_silent(monkeypatch):
    monkeypatch.setattr(beats, "QUIET_S", 0.2)
    monkeypatch.setattr(beats, "EVERY_S", 0.2)
    long, short = io.StringIO(), io.StringIO()
    with beats.heartbeat(long, lambda: "the field"):
        time.sleep(0.7)
    with beats.heartbeat(short, lambda: "quick"):
        pass
    lines = long.getvalue().splitlines()
    assert 2 <= len(lines) <= 4 and all(line.startswith("the field: ") and line.endswith(" s") for line in lines)
    assert short.getvalue() == ""


def test_figures_beat_while_a_long_figure_runs(monkeypatch, tmp_path):
    """`ocp figures`: a figure that takes longer than QUIET_S is not silent while it runs."""
    import ocp.figures as figures

    monkeypatch.setattr(beats, "QUIET_S", 0.2)
    monkeypatch.setattr(beats, "EVERY_S", 0.2)
    slow = figures.FIGURES["finch-fig1"]
    monkeypatch.setitem(figures.FIGURES, "finch-fig1", type(slow)(**{**slow.__dict__,
                                                                     "data": lambda: time.sleep(0.6) or slow.data()}))
    stream = io.StringIO()
    figures.write(tmp_path, ["finch-fig1"], ("png",), progress=stream)
    lines = stream.getvalue().splitlines()
    assert any(line.startswith("[1/1] finch-fig1: running: ") for line in lines) and lines[-1].startswith("[1/1] finch-fig1: ")
