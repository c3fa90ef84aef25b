"""What a published part measured: the source files it ran, each keyed by a hash of its code.

    python benchmarks/measured.py RECORD -- ARGV...

runs ARGV (`-m MODULE ARGS...` or `SCRIPT ARGS...`, as `python` would) in this process and, at its
exit, writes to RECORD (JSON) the project's files it had imported, each with `code_hash`. That is
the key of a published result, as asv keys a benchmark's result by its source: the hash of the
file's syntax tree without its docstrings and without the `help`, `description` and `epilog`
texts of the command line, so that a comment, a docstring or a help text changed leaves the
published results current, and any change to what runs makes them stale
(tests/test_published.py). A compiled extension imported (a .so) is keyed by its C sources and
headers, as pyproject.toml's `ext-modules` declares them, each hashed whole: a change to the C
code makes the results stale. Package data files (suites, papers' values, the reference set) are
hashed whole (`data_hashes`): every part depends on them.
"""

import ast
import atexit
import hashlib
import importlib.util
import json
import runpy
import sys
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve()       # read now: a script run as __main__ replaces this module's globals
ROOT = HERE.parents[1]
#: the folders of the project's code: a module imported from anywhere else, a virtual environment in
#: the checkout included (the README's install makes one there, .venv), is not the project's
SOURCES = ("ocp", "benchmarks")
#: keyword arguments whose text cannot change what a command computes
TEXT_KEYWORDS = {"help", "description", "epilog"}
#: package data every part reads, hashed whole (what publish.py writes itself is excluded)
DATA = ("ocp/**/*.toml", "ocp/**/*.json", "ocp/**/*.jsonl", "reference/**/*.jsonl", "reference/**/*.json")
WRITTEN = ("ocp/synthesis/data/bifurcation.jsonl",)     # the bifurcation part writes it; the sweeps are inputs


class _Texts(ast.NodeTransformer):
    """Docstrings and help texts removed."""

    def _body(self, node):
        body = node.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str):
            node.body = body[1:] or [ast.Pass()]
        return self.generic_visit(node)

    visit_Module = visit_ClassDef = visit_FunctionDef = visit_AsyncFunctionDef = _body

    def visit_Call(self, node):
        node.keywords = [k for k in node.keywords if k.arg not in TEXT_KEYWORDS]
        return self.generic_visit(node)


def code_hash(path):
    """sha256 of the file's syntax tree, docstrings and help texts removed (16 hex digits); of its
    bytes for a file not in Python (a C source or header)."""
    return source_hash(Path(path).read_bytes(), Path(path).suffix)


def source_hash(source, suffix):
    """`code_hash` of a file's bytes `source`, its suffix `suffix` (".py": the syntax tree's)."""
    if suffix != ".py":
        return hashlib.sha256(source).hexdigest()[:16]
    tree = _Texts().visit(ast.parse(source))
    return hashlib.sha256(ast.dump(tree, include_attributes=False).encode()).hexdigest()[:16]


def data_hashes():
    """{relative path: sha256 of its bytes} of the package data every part reads."""
    files = sorted({p for pattern in DATA for p in ROOT.glob(pattern) if p.is_file()})
    return {str(p.relative_to(ROOT)): hashlib.sha256(p.read_bytes()).hexdigest()[:16] for p in files
            if not str(p.relative_to(ROOT)).startswith(WRITTEN)}


def extension_sources():
    """{module name: [its C sources and headers]} of the compiled extensions in pyproject.toml."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    return {e["name"]: e["sources"] + e.get("depends", []) for e in config["tool"]["setuptools"].get("ext-modules", [])}


def _project(path):
    """path relative to ROOT if it lies in the project's source folders (SOURCES), else None."""
    path = Path(path).resolve()
    return str(path.relative_to(ROOT)) if any(path.is_relative_to(ROOT / folder) for folder in SOURCES) else None


def imported_sources():
    """The project's .py files (in SOURCES) imported by this process so far, and the C sources of its
    compiled extensions imported (relative paths)."""
    found, extensions = set(), extension_sources()
    for name, module in list(sys.modules.items()):
        path = getattr(module, "__file__", None)
        relative = path and _project(path)
        if not relative:
            continue
        if relative.endswith(".py") and Path(path).resolve() != HERE:
            found.add(relative)
        elif name in extensions:
            found.update(extensions[name])
    return sorted(found)


def _record(path, script):
    files = set(imported_sources()) | ({script} if script else set())
    Path(path).write_text(json.dumps({f: code_hash(ROOT / f) for f in sorted(files)}, indent=1))


def main(argv):
    if len(argv) < 3 or argv[1] != "--":
        sys.exit("usage: python benchmarks/measured.py RECORD -- (-m MODULE | SCRIPT) ARGS...")
    record, target = argv[0], argv[2:]
    if target[0] == "-m":
        sys.argv = [target[1], *target[2:]]
        main_file = Path(importlib.util.find_spec(target[1]).origin).resolve()     # run as __main__, not kept
        atexit.register(_record, record, _project(main_file))
        runpy.run_module(target[1], run_name="__main__", alter_sys=True)
    else:
        script = Path(target[0]).resolve()
        sys.argv = [str(script), *target[1:]]
        sys.path.insert(0, str(script.parent))
        atexit.register(_record, record, _project(script))
        runpy.run_path(str(script), run_name="__main__")


if __name__ == "__main__":
    main(sys.argv[1:])
