"""The layers of ARCHITECTURE.md: a module imports only from its own package and the layers below.
And the package data: a wheel installed into a fresh virtual environment finds its papers, suites and
the reference set (and `ocp score` works there)."""

import ast
import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path


ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "ocp"
#: bottom to top; a module of layer L may import layers < L and its own package
LAYERS = [{"core"}, {"exact", "scenes"}, {"direct", "indirect", "sampling"}, {"result"}, {"solving"}, {"synthesis"},
          {"papers", "reference"}, {"bench"}, {"figures"}, {"commands"}, {"cli"}]


def layer(part):
    return next(i for i, names in enumerate(LAYERS) if part in names)


def imported(path):
    """The top-level ocp packages or modules imported by the module at `path` (absolute and relative)."""
    module = path.relative_to(ROOT).with_suffix("").parts
    tree = ast.parse(path.read_text())
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = list(module[:len(module) - node.level]) + (node.module.split(".") if node.module else [])
                names = [base + [a.name] for a in node.names] if len(base) == 1 else [base]
            elif node.module and node.module.split(".")[0] == "ocp":
                base = node.module.split(".")
                names = [base + [a.name] for a in node.names] if len(base) == 1 else [base]
            else:
                continue
            found |= {n[1] for n in names if len(n) > 1}
        elif isinstance(node, ast.Import):
            found |= {a.name.split(".")[1] for a in node.names if a.name.startswith("ocp.")}
    return found


def test_no_module_imports_a_layer_above_its_own():
    upward = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        if parts == ("__init__",):
            continue                      # the package's lazy names point at every layer by design
        own = parts[0]
        for other in imported(path):
            if other != own and layer(other) >= layer(own):
                upward.append(f"{path.relative_to(ROOT)} imports ocp.{other}")
    assert not upward, upward


def test_every_package_has_a_layer():
    packages = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    modules = {p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__"}
    assert packages | modules <= set().union(*LAYERS)


def test_the_wheel_carries_its_data(tmp_path):
    """Build the wheel, install it (no dependencies) into a fresh virtual environment that sees this
    environment's third-party packages, and run `ocp verify --paper finch2015` and `ocp bench --help`
    there, outside the source tree."""
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(wheels), str(ROOT)],
                   check=True, capture_output=True, timeout=300)
    env_dir = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(env_dir)], check=True, timeout=120)
    python = env_dir / "bin" / "python"
    site = Path(subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               capture_output=True, text=True, check=True).stdout.strip())
    (site / "dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    wheel = next(wheels.glob("ocp-*.whl"))
    subprocess.run([str(python), "-m", "pip", "install", "--no-deps", "-q", str(wheel)], check=True,
                   capture_output=True, timeout=300)
    run = lambda *args: subprocess.run([str(env_dir / "bin" / "ocp"), *args], capture_output=True, text=True,
                                       cwd=tmp_path, timeout=600, env={**os.environ, "PYTHONPATH": ""})
    where = subprocess.run([str(python), "-c", "import ocp.papers; print(ocp.papers.__file__)"], capture_output=True,
                           text=True, cwd=tmp_path).stdout
    assert str(env_dir) in where
    verify = run("verify", "--paper", "finch2015")
    assert verify.returncode == 0 and "t_inf_swing_up_kappa_1" in verify.stdout and "agrees" in verify.stdout
    bench = run("bench", "--help")
    assert bench.returncode == 0 and "quick" in bench.stdout
    suites = subprocess.run([str(python), "-c", "from ocp.bench import suite; print(len(suite.load('quick').pairs()))"],
                            capture_output=True, text=True, cwd=tmp_path)
    assert int(suites.stdout) > 0
    # the reference set, read from the wheel's share/ocp/reference, and `ocp score` against it
    count = subprocess.run([str(python), "-c", "from ocp.reference import data; print(data.folder()); "
                            "print(sum(r['status'] == 'solved' for r in data.load().values()))"],
                           capture_output=True, text=True, cwd=tmp_path)
    folder, solved = count.stdout.split()
    assert str(env_dir) in folder and int(solved) >= 200
    row = next(r for r in map(json.loads, (ROOT / "reference" / "instances.jsonl").open()) if r["status"] == "solved")
    answer = tmp_path / "answer.json"
    answer.write_text(json.dumps({"instance": row["id"], "arc_signs": row["optimum"]["arc_signs"],
                                  "switch_times": row["optimum"]["refined"]["switch_times"],
                                  "T": row["optimum"]["refined"]["T"]}))
    scored = run("score", str(answer), "--json")
    assert scored.returncode == 0 and json.loads(scored.stdout)["class"] == "optimum"
