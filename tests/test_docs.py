"""The documentation's references: every paper's `[paper]` table (ocp/papers/data/*.toml, printed by
`ocp verify`) cites it exactly as the bibliography of README.md does, and the README points to no
file outside the repository."""

import re
from pathlib import Path

from ocp.papers import references

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def bibliography():
    """The README's bibliography as plain text: emphasis removed, line breaks joined."""
    section = README.split("## Bibliography", 1)[1].split("\n## ", 1)[0]
    return re.sub(r"\s+", " ", section.replace("*", ""))


def test_every_paper_is_cited_as_in_the_bibliography():
    text = bibliography()
    papers = references.papers()
    assert papers == ["batista2006", "finch2015", "weinstein_tam"]
    for paper in papers:
        citation, where = references.citation(paper)
        assert citation in text, (paper, citation)
        assert where in text, (paper, where)


def test_the_bibliography_has_the_works_the_suite_relies_on():
    text = bibliography()
    for work in ("J. Appl. Math. Mech. 73 (2009) 403-410", "J. Comput. Syst. Sci. Int. 47 (2008) 163-178",
                 "J. Optim. Theory Appl. 163 (2014) 230-252", "SIAM J. Control Optim. 52 (2014) 82-96",
                 "Nonlinear Dyn. 47 (2007) 65-73", "Math. Program. 91 (2002) 201-213",
                 "SIAM J. Control Optim. 41 (2002) 991-1014", "Applications to Regular and Bang-Bang Control",
                 "Experimental Mathematics 14 (2005) 99-117", "Comput. 11 (2019) 1-36", "Math. Program. 106 (2006) 25-57"):
        assert work in text, work


def _anchors(path):
    """The anchors of a Markdown file's headings as GitHub makes them: lower case, only letters,
    digits, spaces, hyphens and underscores kept, spaces made hyphens, a repeated one suffixed -1,
    -2, ...; lines inside fenced code blocks are not headings."""
    anchors, fenced = set(), False
    for line in path.read_text(encoding="utf-8").splitlines():
        fenced ^= line.startswith("```")
        heading = None if fenced else re.match(r"#+ (.+)$", line)
        if heading:
            anchor = re.sub(r"[^\w\- ]", "", heading.group(1).strip().lower()).replace(" ", "-")
            repeat = next(n for n in range(len(anchors) + 1) if (f"{anchor}-{n}" if n else anchor) not in anchors)
            anchors.add(f"{anchor}-{repeat}" if repeat else anchor)
    return anchors


def test_no_link_leaves_the_repository():
    for doc in ("README.md", "benchmarks/README.md", "ARCHITECTURE.md"):
        text = (ROOT / doc).read_text(encoding="utf-8")
        assert "../" not in text and "/work/" not in text and "shared/papers" not in text, doc
        for target in re.findall(r"\]\(([^)]+)\)", text):
            if not target.startswith(("http://", "https://", "#")):
                file, _, anchor = target.partition("#")
                assert (ROOT / doc).parent.joinpath(file).exists(), (doc, target)
                if anchor and file.endswith(".md"):
                    assert anchor in _anchors((ROOT / doc).parent / file), (doc, target)
