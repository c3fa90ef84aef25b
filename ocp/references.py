"""Published values, read from `reference/*.toml` (one file a paper).

Each file has a `[paper]` table (id, citation, file in ../shared/papers) and `[[value]]` entries:

    key      name the reproducing module uses for it
    printed  the text as printed (verbatim)
    digits   the printed number as a plain decimal ("1.8540746773")
    reading  "truncated" (Finch's "..."), "rounded", or "approximate" (a printed "about")
    source   section, equation, table or figure
    meaning  what the number is, with its units and convention
"""

import os
import tomllib
from dataclasses import dataclass
from pathlib import Path

REFERENCE_DIR = Path(os.environ.get("OCP_REFERENCE_DIR", Path(__file__).resolve().parents[1] / "reference"))
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


def papers():
    """Ids of the papers that have a reference file."""
    return sorted(p.stem for p in REFERENCE_DIR.glob("*.toml"))


def load(paper):
    """The published values of `paper`, keyed by `key`, in file order."""
    with open(REFERENCE_DIR / f"{paper}.toml", "rb") as f:
        data = tomllib.load(f)
    values = {}
    for entry in data["value"]:
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
