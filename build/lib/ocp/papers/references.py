"""Published values, read from the package data `ocp/papers/data/*.toml` (one file a paper).

Each file has a `[paper]` table (id, citation, where to find it) and `[[value]]` entries:

    key      name the reproducing module uses for it
    printed  the text as printed (verbatim)
    digits   the printed number as a plain decimal ("1.8540746773")
    reading  "truncated" (Finch's "..."), "rounded", or "approximate" (a printed "about")
    source   section, equation, table or figure
    meaning  what the number is, with its units and convention
"""

import tomllib
from dataclasses import dataclass
from importlib import resources

READINGS = ("truncated", "rounded", "approximate")


@dataclass(frozen=True)
class Published:
    paper: str
    key: str
    printed: str
    digits: str
    reading: str
    source: str
    meaning: str

    @property
    def value(self):
        return float(self.digits)

    @property
    def significant_digits(self):
        """How many significant digits are printed ("0.0875" -> 3, "12.5" -> 3)."""
        return len(self.digits.lstrip("-").replace(".", "").lstrip("0"))


def _data():
    return resources.files("ocp.papers") / "data"


def papers():
    """Ids of the papers that have a reference file."""
    return sorted(p.name[:-5] for p in _data().iterdir() if p.name.endswith(".toml"))


def _read(paper):
    return tomllib.loads((_data() / f"{paper}.toml").read_text(encoding="utf-8"))


def citation(paper):
    """(citation, where to find it) of `paper`."""
    head = _read(paper)["paper"]
    return head["citation"], head["where"]


def load(paper):
    """The published values of `paper`, keyed by `key`, in file order."""
    values = {}
    for entry in _read(paper)["value"]:
        item = Published(paper=paper, **entry)
        if item.reading not in READINGS:
            raise ValueError(f"{paper}.toml: {item.key}: reading {item.reading!r} not in {READINGS}")
        if item.key in values:
            raise ValueError(f"{paper}.toml: key {item.key!r} appears twice")
        values[item.key] = item
    return values


def value(paper, key):
    """The printed number `key` of `paper`, as a float."""
    return load(paper)[key].value
