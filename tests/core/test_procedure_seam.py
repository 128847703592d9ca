"""The procedure seam, tested from outside: a toy line procedure in a distribution of its own
(tests/toy_procedure: a model, a description, three cases, one golden vector and a rules
catalogue; ENQ is answered with ACK after a reply delay) is installed next to ptpcert, built
as a wheel, in a fresh virtual environment. Without a change to any file of ptpcert it shows
up in the command line, its profile table is validated, its cases and vector run against
sim: and against ``ptpcert iut`` over exec:, the reports are written, and ``ptpcert rules``
traces its catalogue."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TOY = ROOT / "tests" / "toy_procedure"

PROFILE = """[iut]
procedure = "TOY"
baud_rate = 9600
send_trigger = "none"
line_conditions = "none"
status_from_stderr = false

[toy]
reply_delay_ms = 30
"""


@pytest.fixture(scope="module")
def toy(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("seam")
    venv = tmp / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    py = venv / "bin" / "python"
    toy = shutil.copytree(TOY, tmp / "toy", ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    p = subprocess.run([str(py), "-m", "pip", "install", "-q", str(ROOT), str(toy)], capture_output=True, text=True,
                       timeout=900)
    assert p.returncode == 0, p.stderr[-3000:]
    work = tmp / "work"
    work.mkdir()
    (work / "toy.toml").write_text(PROFILE)
    env = {**os.environ, "PATH": f"{venv / 'bin'}{os.pathsep}{os.environ['PATH']}"}
    env.pop("PYTHONPATH", None)

    def run(*args, timeout=300):
        return subprocess.run(["ptpcert", *args], cwd=work, env=env, capture_output=True, text=True, timeout=timeout)
    return run, work


@pytest.mark.realtime
def test_the_toy_procedure_is_one_of_the_procedures(toy):
    run, _ = toy
    p = run("run", "--help")
    assert p.returncode == 0 and "Toy ENQ/ACK: TOY" in " ".join(p.stdout.split())
    p = run("iut", "--help")
    assert "TOY" in p.stdout and "--reply-delay-ms" in p.stdout


@pytest.mark.realtime
@pytest.mark.parametrize("table,key", [
    ('[toy]\nreply_delay_ms = 5\n', "toy.reply_delay_ms"),
    ('[toy]\nreply_delay_ms = 30\ncolour = "red"\n', "toy.colour"),
    ('[toy]\nreply_delay_ms = 30\n[rk512]\nlink = "3964R"\n', "rk512"),
])
def test_its_profile_table_is_validated(toy, table, key):
    run, work = toy
    bad = work / f"bad-{abs(hash(table))}.toml"
    bad.write_text(PROFILE.split("[toy]")[0] + table)
    p = run("run", "--iut", "sim:", "--profile", str(bad))
    assert p.returncode == 2 and not p.stdout
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], p.stderr


@pytest.mark.realtime
@pytest.mark.parametrize("iut", ["sim:", "exec:ptpcert iut --procedure TOY --reply-delay-ms 30"])
def test_its_cases_and_vector_run_and_the_reports_are_written(toy, iut):
    run, work = toy
    out = work / ("sim" if iut == "sim:" else "exec")
    out.mkdir(exist_ok=True)
    p = run("run", "--iut", iut, "--profile", "toy.toml", "--json", str(out / "r.json"),
            "--junit", str(out / "j.xml"), "--html", str(out / "r.html"), "-q")
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    data = json.loads((out / "r.json").read_text())
    ids = {c["id"]: c["verdict"] for c in data["cases"]}
    assert ids == {"TOY.SUITE.ENQ-ACK": "pass", "TOY.SUITE.TWO-ENQ": "pass", "TOY.SUITE.OTHER-IGNORED": "pass",
                   "TOY.ENQ-ACK": "pass"}
    suite = ET.parse(out / "j.xml").getroot()
    assert "Toy ENQ/ACK" in ET.tostring(suite, encoding="unicode")
    assert "TOY.SUITE.ENQ-ACK" in (out / "r.html").read_text()


@pytest.mark.realtime
def test_a_broken_iut_fails_the_toy_cases(toy):
    """The seam judges: an IUT of the toy procedure that answers too late fails."""
    run, work = toy
    slow = work / "slow.toml"
    slow.write_text(PROFILE.replace("reply_delay_ms = 30", "reply_delay_ms = 30"))
    p = run("run", "--iut", "exec:ptpcert iut --procedure TOY --reply-delay-ms 300", "--profile", str(slow),
            "--select", "TOY.SUITE.ENQ-ACK", "--edge-attempts", "1")
    assert p.returncode == 1, p.stdout[-2000:] + p.stderr[-2000:]


@pytest.mark.realtime
def test_its_rules_are_traced(toy):
    run, _ = toy
    p = run("rules", "--procedure", "TOY")
    assert p.returncode == 0, p.stderr
    text = p.stdout
    assert "TOY.REPLY.ACK" in text and "TOY.SUITE.ENQ-ACK" in text and "TOY.REPLY.IGNORE" in text
    assert "TOY.APP.LOG" in text and "not on the line" in text
    assert run("rules", "--procedure", "TOY", "--check").returncode == 0
    p = run("vectors", "--check", "--select", "TOY.*", "-v")
    assert p.returncode == 0 and "TOY.ENQ-ACK" in p.stdout, p.stdout + p.stderr
