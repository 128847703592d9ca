"""ptpcert as a user gets it: a wheel installed (not editable) into a fresh virtual
environment, run from an empty directory. The golden vectors and profiles must come from
the installation, findings must land in the current directory, and only ``ptpcert`` may be
added to site-packages as a top-level import name."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
from no_false_alarm import judged

ROOT = Path(__file__).resolve().parents[2]


def _packages_in_tree() -> set[str]:
    """Every folder with an __init__.py under the mapped top-level folders, as the import
    name it gets in the wheel."""
    mapping = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-dir"]
    out = set()
    for name, folder in mapping.items():
        base = ROOT / folder
        for init in base.rglob("__init__.py"):
            rel = init.parent.relative_to(base)
            out.add(".".join((name, *rel.parts)) if rel.parts else name)
    return out


def test_every_package_folder_is_listed_in_pyproject():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    missing = _packages_in_tree() - listed
    assert not missing, f"add these packages to [tool.setuptools] packages: {sorted(missing)}"


def test_the_version_lives_in_one_place():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert "version" not in project and "version" in project["dynamic"]
    import ptpcert
    from importlib.metadata import version
    assert version("ptpcert") == ptpcert.__version__


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A wheel built from the checkout, installed into a fresh venv."""
    tmp = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(tmp / "dist"), str(ROOT)],
                   check=True, capture_output=True, timeout=600)
    (wheel,) = (tmp / "dist").glob("ptpcert-*.whl")
    venv = tmp / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q", str(wheel)],
                   check=True, capture_output=True, timeout=900)
    work = tmp / "empty"
    work.mkdir()
    env = {**os.environ, "PATH": f"{venv / 'bin'}{os.pathsep}{os.environ['PATH']}"}
    env.pop("PYTHONPATH", None)
    return {"wheel": wheel, "venv": venv, "work": work, "env": env}


def _site_packages(venv: Path) -> Path:
    (sp,) = (venv / "lib").glob("python3*/site-packages")
    return sp


def _run(inst, *args, timeout=600):
    return subprocess.run(["ptpcert", *args], cwd=inst["work"], env=inst["env"], capture_output=True,
                          text=True, timeout=timeout)


@pytest.mark.realtime
def test_wheel_has_every_data_file_of_the_checkout(installed):
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    for folder, prefix in (("vectors", "ptpcert/vectors"), ("conformance/profiles", "ptpcert/conformance/profiles")):
        for f in (ROOT / folder).rglob("*.toml"):
            rel = f.relative_to(ROOT / folder).as_posix()
            assert f"{prefix}/{rel}" in names, f"{folder}/{rel} is missing from the wheel"
    assert "ptpcert/status_catalogue.toml" in names
    assert "ptpcert/capture/wireshark/ptpcert.lua" in names, "the Wireshark dissector is missing from the wheel"
    for f in (ROOT / "harness" / "rules").glob("*.toml"):
        assert f"ptpcert/rules/{f.name}" in names, f"the rules catalogue {f.name} is missing from the wheel"
    tops = {n.split("/")[0] for n in names if not n.split("/")[0].endswith((".dist-info", ".data"))}
    assert tops == {"ptpcert"}, f"the wheel installs top-level names {sorted(tops)}"


@pytest.mark.realtime
def test_installed_ptpcert_shows_and_installs_its_wireshark_dissector(installed, tmp_path):
    p = _run(installed, "capture", "--wireshark-plugin")
    assert p.returncode == 0, p.stderr
    where = Path(p.stdout.strip())
    assert where.is_file() and where.is_relative_to(_site_packages(installed["venv"]))
    assert where.read_bytes() == (ROOT / "harness" / "capture" / "wireshark" / "ptpcert.lua").read_bytes()
    p = _run(installed, "capture", "--wireshark-plugin", "install", "--plugin-dir", str(tmp_path / "plugins"))
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "plugins" / "ptpcert.lua").read_bytes() == where.read_bytes()


@pytest.mark.realtime
def test_installed_ptpcert_finds_its_vectors_from_an_empty_directory(installed):
    n_golden = len(list((ROOT / "vectors").rglob("*.toml")))
    p = _run(installed, "vectors", "--check")
    assert p.returncode == 0, p.stdout + p.stderr
    assert p.stdout.strip().splitlines()[-1] == f"{n_golden} vectors, {n_golden} passed, 0 failed"
    # an unrelated ./vectors in the current directory is not used instead of the golden ones
    (installed["work"] / "vectors").mkdir(exist_ok=True)
    (installed["work"] / "vectors" / "junk.toml").write_text("this is not a vector")
    try:
        p = _run(installed, "vectors")
        assert p.returncode == 0 and f"{n_golden} vectors" in p.stdout.strip().splitlines()[-1]
    finally:
        (installed["work"] / "vectors" / "junk.toml").unlink()


@pytest.mark.realtime
def test_installed_ptpcert_runs_the_reference_and_fuzzes_without_touching_the_installation(installed):
    work = installed["work"]
    profile = work / "my-profile.toml"
    profile.write_text((ROOT / "conformance/profiles/reference-20ms.toml").read_text())
    p = _run(installed, "run", "--iut", "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk", "--profile",
             str(profile), "--select", "3964R.D0*", "--select", "SUITE.RECEIVE.*", "-q",
             "--junit", "out/junit.xml", "--json", "out/r.json")
    # no false alarm; a harness timing fault of a loaded machine is an error, never a fail
    cases = judged(p, work / "out" / "r.json")
    assert sum(c["verdict"] == "pass" for c in cases) >= 30, p.stdout
    assert (work / "out" / "junit.xml").exists()
    assert ("overall PASS" if p.returncode == 0 else "overall ERROR") in p.stdout
    # the IUT command resolved to the venv's ptpcert, not a development checkout
    assert Path(subprocess.run(["which", "ptpcert"], env=installed["env"], capture_output=True, text=True)
                .stdout.strip()).parent == installed["venv"] / "bin"

    sp = _site_packages(installed["venv"])
    before = sorted(str(x.relative_to(sp)) for x in sp.rglob("*") if "__pycache__" not in x.parts)
    p = _run(installed, "fuzz", "--iut", "sim:?mutant=no-dle-doubling", "--profile", str(profile),
             "--budget", "20", "--seed", "1")
    assert p.returncode == 1, p.stdout + p.stderr
    found = list((work / "vectors" / "regressions").glob("*.toml"))
    assert found, "a finding is written to ./vectors/regressions in the current directory"
    after = sorted(str(x.relative_to(sp)) for x in sp.rglob("*") if "__pycache__" not in x.parts)
    assert before == after, "ptpcert fuzz changed the installation"
    p = _run(installed, "vectors", "--check", "--dir", str(work / "vectors" / "regressions"))
    assert p.returncode == 0, p.stdout + p.stderr
