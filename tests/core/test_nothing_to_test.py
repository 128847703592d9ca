"""A profile that leaves nothing to test is no pass (issue 25, item 5): where every case of
the run is unsupported for the profile and the IUT, `run`, `fuzz` (one campaign or several
workers) and the pytest plugin refuse in one line that says why, and exit as for bad usage,
before anything runs. A CI gate must never read "0 failures of 0 judged" as a certificate."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from ptpcert.profile import load_profile
from ptpcert.runner import Runner
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
RK512 = ROOT / "conformance" / "profiles" / "rk512-reference.toml"


def idle_profile(tmp_path) -> Path:
    """The bundled RK 512 reference as an IUT that only requests, and makes no request the
    harness can drive: no case of the suite applies to it."""
    text = RK512.read_text()
    text = text.replace('roles = ["passive", "active"]', 'roles = ["active"]')
    text = text.replace('requests = "script"', 'requests = "none"')
    assert 'roles = ["active"]' in text and 'requests = "none"' in text
    p = tmp_path / "idle.toml"
    p.write_text(text)
    return p


def cli(tmp_path, *args, timeout=300):
    return subprocess.run([PY, "-m", "ptpcert.cli", *args], cwd=tmp_path, capture_output=True, text=True,
                          timeout=timeout)


def one_line(text: str) -> str:
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert len(lines) == 1, text
    return lines[0]


def test_the_runner_tells_why_nothing_can_be_tested(tmp_path):
    idle = load_profile(idle_profile(tmp_path))
    full = load_profile(RK512)
    vectors = load_vector_sets()
    for profile, nothing in ((idle, True), (full, False)):
        factory = make_factory("sim:", profile)
        try:
            why = Runner(factory, profile).nothing_to_test(load_suite(profile, vectors))
        finally:
            factory.shutdown()
        assert bool(why) is nothing, why
    assert why is None


def test_run_refuses_a_profile_with_nothing_to_test(tmp_path):
    prof = idle_profile(tmp_path)
    p = cli(tmp_path, "run", "--iut", "sim:", "--profile", str(prof), "-q", "--json", "r.json")
    assert p.returncode == 2, p.stdout + p.stderr
    line = one_line(p.stderr)
    assert line.startswith("ptpcert run: nothing to test: every one of the ") and "passive" in line, line
    assert "overall PASS" not in p.stdout and not (tmp_path / "r.json").exists()


def test_fuzz_refuses_a_profile_with_nothing_to_test(tmp_path):
    prof = idle_profile(tmp_path)
    for extra in ((), ("--workers", "2")):
        p = cli(tmp_path, "fuzz", "--iut", "sim:", "--profile", str(prof), "--budget", "3", *extra)
        assert p.returncode == 2, p.stdout + p.stderr
        assert one_line(p.stderr).startswith("ptpcert fuzz: nothing to test:"), p.stderr
        assert "examples in" not in p.stdout


def test_the_pytest_plugin_refuses_a_profile_with_nothing_to_test(tmp_path):
    prof = idle_profile(tmp_path)
    p = subprocess.run([PY, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--ptpcert-iut", "sim:",
                        "--ptpcert-profile", str(prof)], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert p.returncode == 4, p.stdout + p.stderr   # pytest's usage error
    assert "ptpcert: nothing to test: every one of the " in p.stdout + p.stderr
    assert "passed" not in p.stdout and "skipped" not in p.stdout
