"""The architecture's rules, checked on the package as it is installed (harness/ as ptpcert,
conformance/ as ptpcert.conformance, laid out in a temporary directory, so the checks see
exactly what a wheel contains):

* the import-linter contracts in pyproject.toml: the layers of the core, the independence of
  the procedures (RK 512 on the 3964R link only), every model pure, the reports apart;
* no import cycle among the modules, imports inside functions included (grimp);
* the core names no procedure: what the core needs of one comes through its description;
* modules along their jobs: none over about 500 lines unless its docstring says why;
* no private name imported from another module.

Each rule has a test that plants a break of it and sees it caught."""

from __future__ import annotations

import ast
import io
import os
import re
import shutil
import subprocess
import sys
import tokenize
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LINT = shutil.which("lint-imports") or str(Path(sys.executable).parent / "lint-imports")
CONTRACTS = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]


def _layout(tmp: Path) -> Path:
    pkg = tmp / "ptpcert"
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    shutil.copytree(ROOT / "harness", pkg, ignore=ignore)
    shutil.copytree(ROOT / "conformance", pkg / "conformance", ignore=ignore)
    shutil.copytree(ROOT / "vectors", pkg / "vectors", ignore=ignore)
    return tmp


def _plant(tree: Path, module: str, line: str) -> None:
    f = tree / "ptpcert" / module
    f.write_text(f.read_text() + f"\n{line}  # probe\n")


def _lint(tree: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return subprocess.run([LINT, str(ROOT / "pyproject.toml"), "--no-cache"], cwd=tree, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def linter():
    if not Path(LINT).exists():
        pytest.fail("lint-imports is not installed: pip install -e '.[test]' installs import-linter")
    return LINT


# ----------------------------------------------------------------------------- the contracts
def test_the_contracts_hold(linter, tmp_path):
    p = _lint(_layout(tmp_path))
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-2000:]
    assert f"{len(CONTRACTS)} kept, 0 broken" in p.stdout


@pytest.mark.parametrize("module,line,contract", [
    # a lower layer imports a higher one
    ("transport/base.py", "from .. import runner", "The layers of ptpcert"),
    ("runner/options.py", "from ptpcert import conformance", "The layers of ptpcert"),
    ("scenario.py", "from ptpcert.procedures import p3964", "The layers of ptpcert"),
    ("registry.py", "from . import profile", "The layers of ptpcert"),
    # one procedure imports another
    ("procedures/ascii/fuzz.py", "from ptpcert.procedures.p3964 import link", "The procedures are independent"),
    ("procedures/p3964/link.py", "from ptpcert.procedures.rk512.model import codec", "The procedures are independent"),
    ("procedures/rk512/status.py", "from ptpcert.procedures.p3964 import chart", "The procedures are independent"),
    # a model is not pure
    ("procedures/ascii/model/codec.py", "import time", "Every model is pure"),
    ("procedures/rk512/model/codec.py", "from ptpcert import scenario", "Every model is pure"),
    ("procedures/p3964/model/codec.py", "from ptpcert.procedures.p3964 import description", "Every model is pure"),
    ("model/line.py", "import hypothesis", "Every model is pure"),
    # the reports reach into the engine
    ("report/html/__init__.py", "from ptpcert import scenario", "The reports import only"),
])
def test_a_break_of_each_contract_is_caught(linter, tmp_path, module, line, contract):
    tree = _layout(tmp_path)
    if not (tree / "ptpcert" / module).exists():   # a module that became a package
        module = module.removesuffix(".py") + "/__init__.py"
    _plant(tree, module, line)
    p = _lint(tree)
    assert p.returncode != 0
    broken = [ln for ln in p.stdout.splitlines() if " BROKEN" in ln]
    assert any(contract in ln for ln in broken), p.stdout[-3000:]


def test_the_purity_contract_forbids_every_package_but_the_model():
    """The purity contract is a list of what the models may not import; it names every
    top-level module of ptpcert but the model, so a package added later cannot slip past it."""
    pure = next(c for c in CONTRACTS if c["name"].startswith("Every model is pure"))
    forbidden = set(pure["forbidden_modules"])
    tops = {p.stem if p.suffix == ".py" else p.name for p in (ROOT / "harness").iterdir()
            if (p.suffix == ".py" or (p / "__init__.py").exists()) and p.name != "__init__.py"}
    tops.add("conformance")
    missing = {f"ptpcert.{t}" for t in tops} - forbidden - {"ptpcert.model", "ptpcert.procedures"}
    assert not missing, f"the purity contract does not forbid {sorted(missing)}"
    layers = next(c for c in CONTRACTS if c["type"] == "layers")
    in_layers = {m.strip() for layer in layers["layers"] for m in layer.split("|")}
    assert in_layers == tops, f"modules outside the layers: {sorted(tops - in_layers)}"


# ----------------------------------------------------------------------------- import cycles
def _cycles(tree: Path) -> list[list[str]]:
    """The strongly connected components (of more than one module) of the import graph of the
    package laid out in ``tree``, imports inside functions included."""
    code = ("import grimp, json\n"
            "g = grimp.build_graph('ptpcert', include_external_packages=False, exclude_type_checking_imports=True)\n"
            "print(json.dumps({m: sorted(g.find_modules_directly_imported_by(m)) for m in g.modules}))\n")
    env = {**os.environ, "PYTHONPATH": str(tree)}
    out = subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, capture_output=True, text=True,
                         timeout=300, check=True)
    import json
    adj = json.loads(out.stdout)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    comps: list[list[str]] = []

    def strong(v: str) -> None:   # Tarjan's algorithm, iterative over the edges of v
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in adj.get(v, ()):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    for v in sorted(adj):
        if v not in index:
            strong(v)
    return comps


def test_no_import_cycle_among_the_modules(tmp_path):
    assert _cycles(_layout(tmp_path)) == []


def test_a_planted_cycle_is_caught(tmp_path):
    tree = _layout(tmp_path)
    _plant(tree, "model/line.py", "def _f():\n    from ptpcert.model import app")   # inside a function
    _plant(tree, "model/app.py", "from ptpcert.model import line")
    assert ["ptpcert.model.app", "ptpcert.model.line"] in _cycles(tree)


# ----------------------------------------------------------------------------- the core names no procedure
#: names of the built-in procedures and of what only one of them has on the line
_PROCEDURE_WORDS = re.compile(r"3964|rk ?512|\bascii\b|reatel|\bSTX\b|\bDLE\b|\bETX\b|\bNAK\b|\bXON|\bXOFF|"
                              r"\bprime\b|\bTRES\b|NAKTIM", re.I)
#: the STATUS codes of the CP 341 (Tables 8-1, 8-2) name the events of every procedure
_CATALOGUES = {"model/codes.py"}


def _docstring_lines(tree: ast.AST) -> set[int]:
    out: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            first = node.body[0] if node.body else None
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                out.update(range(first.lineno, first.end_lineno + 1))
    return out


def procedure_names_in_code(root: Path) -> list[str]:
    """Where the core's code (not its docstrings or comments) names a procedure: names and
    strings under ``root`` outside ``procedures/``."""
    found = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root).as_posix()
        if rel.startswith("procedures/") or rel in _CATALOGUES:
            continue
        src = path.read_text("utf-8")
        docs = _docstring_lines(ast.parse(src))
        for tok in tokenize.generate_tokens(io.StringIO(src).readline):
            if tok.type not in (tokenize.NAME, tokenize.STRING) or tok.start[0] in docs:
                continue
            if tok.type == tokenize.STRING and re.fullmatch(r"[rbfu]*(['\"])ascii\1", tok.string, re.I):
                continue   # the text codec
            if tok.string in ("ensure_ascii", "isascii") or not _PROCEDURE_WORDS.search(tok.string):
                continue
            found.append(f"{rel}:{tok.start[0]}: {tok.string[:80]}")
    return found


def test_the_core_names_no_procedure():
    assert procedure_names_in_code(ROOT / "harness") == []


def test_a_procedure_named_in_the_core_is_caught(tmp_path):
    tree = _layout(tmp_path)
    _plant(tree, "model/line.py", 'DEFAULT = "3964R"')
    _plant(tree, "runner/options.py", "STX = 2")
    found = procedure_names_in_code(tree / "ptpcert")
    assert any(f.startswith("model/line.py") for f in found) and any("STX" in f for f in found), found


# ----------------------------------------------------------------------------- modules along their jobs
MAX_LINES = 500
#: at most this many modules may be longer, each saying why in its docstring
MAX_LONG = 4
_WHY = re.compile(r"one piece", re.I)


def long_modules(root: Path) -> list[tuple[str, int, bool]]:
    """(module, lines, its docstring says why it is one piece) of every module over MAX_LINES."""
    out = []
    for path in sorted(root.rglob("*.py")):
        n = len(path.read_text("utf-8").splitlines())
        if n > MAX_LINES:
            doc = ast.get_docstring(ast.parse(path.read_text("utf-8"))) or ""
            out.append((path.relative_to(root).as_posix(), n, bool(_WHY.search(doc))))
    return out


def test_modules_along_their_jobs():
    long = long_modules(ROOT / "harness") + long_modules(ROOT / "conformance")
    assert all(why for _, _, why in long), [m for m in long if not m[2]]
    assert len(long) <= MAX_LONG, long


def test_a_long_module_without_a_reason_is_caught(tmp_path):
    tree = _layout(tmp_path)
    _plant(tree, "model/line.py", "\n".join(f"X{i} = {i}" for i in range(MAX_LINES)))
    assert ("model/line.py", pytest.approx(MAX_LINES, abs=200), False) in [
        (m, n, why) for m, n, why in long_modules(tree / "ptpcert")]


# ----------------------------------------------------------------------------- private names stay home
def private_imports(root: Path, package: str = "ptpcert") -> list[str]:
    """Imports of a private name (``_x``) from another module of the package."""
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text("utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith(package)):
                for alias in node.names:
                    if alias.name.startswith("_") and not alias.name.startswith("__"):
                        found.append(f"{path.relative_to(root).as_posix()}:{node.lineno}: {alias.name}")
    return found


def test_no_private_name_is_imported_from_another_module():
    assert private_imports(ROOT / "harness") + private_imports(ROOT / "conformance") == []


def test_a_private_import_is_caught(tmp_path):
    tree = _layout(tmp_path)
    _plant(tree, "model/line.py", "from .app import _secret")
    assert any(f.startswith("model/line.py") for f in private_imports(tree / "ptpcert"))
