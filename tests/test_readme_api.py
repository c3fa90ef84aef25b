"""The README's API is true: every `sol.NAME...` of its section "Solving" (the code and the prose),
every `s.NAME` of the samples, and every `ocp.NAME`, read from the README itself, exists on a real
solution (a search with a direct transcription beside it)."""

import re
from functools import reduce
from pathlib import Path

import pytest

import ocp

README = Path(__file__).resolve().parents[1] / "README.md"


def section(title):
    text = README.read_text(encoding="utf-8")
    start = text.index(f"\n## {title}\n")
    return text[start:text.index("\n## ", start + 1)]


@pytest.fixture(scope="module")
def sol():
    return ocp.solve(ocp.swing_up(0.75), ocp.MultipleShooting(N=40))


def chains(text, name):
    """The attribute chains `name.a.b` written in `text` (a call's parenthesis ends one)."""
    return sorted(set(re.findall(rf"(?<![\w.]){name}((?:\.[A-Za-z_]\w*)+)", text)))


def test_every_solution_attribute_the_readme_names_exists(sol):
    found = chains(section("Solving"), "sol")
    assert {".status.message", ".best", ".sample", ".total_time_s", ".direct.T"} <= set(found), found
    missing = []
    for chain in found:
        try:
            reduce(getattr, chain.strip(".").split("."), sol)
        except AttributeError:
            missing.append("sol" + chain)
    assert not missing, missing


def test_every_sample_field_the_readme_names_exists(sol):
    found = chains(section("Solving"), "s")
    samples = sol.sample(every=0.5)
    assert len(found) >= 8 and not [c for c in found if not hasattr(samples, c.strip("."))], found


def test_every_package_name_the_readme_uses_exists():
    found = chains(section("Solving"), "ocp")
    assert ".solve" in found and ".MultipleShooting" in found
    assert not [c for c in found if not hasattr(ocp, c.strip(".").split(".")[0])], found
