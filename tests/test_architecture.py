"""The architecture's rules, as import-linter contracts in pyproject.toml: the model is
pure, transports never import the runner, the suite or the reports, nothing below the
command line imports the conformance suite, and the reports import only the results and
the catalogue. The package is laid out as it is installed (harness/ as ptpcert,
conformance/ as ptpcert.conformance) in a temporary directory, so the check sees exactly
what a wheel contains."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LINT = shutil.which("lint-imports") or str(Path(sys.executable).parent / "lint-imports")


def _layout(tmp: Path) -> Path:
    pkg = tmp / "ptpcert"
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    shutil.copytree(ROOT / "harness", pkg, ignore=ignore)
    shutil.copytree(ROOT / "conformance", pkg / "conformance", ignore=ignore)
    shutil.copytree(ROOT / "vectors", pkg / "vectors", ignore=ignore)
    return tmp


def _lint(tree: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return subprocess.run([LINT, "--config", str(ROOT / "pyproject.toml"), "--no-cache"], cwd=tree, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def linter():
    if not Path(LINT).exists():
        pytest.fail("lint-imports is not installed: pip install -e '.[test]' installs import-linter")
    return LINT


def test_the_layers_hold(linter, tmp_path):
    p = _lint(_layout(tmp_path))
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-2000:]
    assert "4 kept, 0 broken" in p.stdout


@pytest.mark.parametrize("module,line,contract", [
    ("model/codec.py", "import time", "The model is pure"),
    ("transport/base.py", "from .. import runner", "Transports never import"),
    ("runner.py", "from . import conformance", "Nothing below the command line"),
    ("html.py", "from . import scenario", "The reports import only"),
])
def test_a_break_of_each_rule_is_caught(linter, tmp_path, module, line, contract):
    tree = _layout(tmp_path)
    f = tree / "ptpcert" / module
    f.write_text(f.read_text() + f"\n{line}  # probe\n")
    p = _lint(tree)
    assert p.returncode != 0
    broken = [ln for ln in p.stdout.splitlines() if ln.rstrip().endswith("BROKEN")]
    assert any(contract in ln for ln in broken), p.stdout[-3000:]
