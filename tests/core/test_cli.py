"""The small commands: ptpcert status, ptpcert vectors [--check], ptpcert report."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable


def cli(*args):
    return subprocess.run([PY, "-m", "ptpcert.cli", *args], cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_status_lookup_in_every_notation():
    for code in ("16#0808", "0x0808", "0808"):
        p = cli("status", code)
        assert p.returncode == 0 and p.stdout.startswith("16#0808") and "Table 8-1" in p.stdout
    p = cli("status", "--list")
    assert p.returncode == 0 and "80 events" in p.stdout and len(p.stdout.splitlines()) == 81


def test_unknown_status_is_a_clear_error():
    p = cli("status", "16#0705")
    assert p.returncode == 2 and "16#0705 is not in the CP 341 catalogue" in p.stderr
    p = cli("status", "hello")
    assert p.returncode == 2 and "not a STATUS code" in p.stderr


def test_vectors_list_and_check():
    p = cli("vectors")
    assert p.returncode == 0 and "3964R.FIG2-6.RECEIVE" in p.stdout
    n = int(p.stdout.strip().splitlines()[-1].split()[0])
    assert n >= 40
    p = cli("vectors", "--check")
    assert p.returncode == 0 and p.stdout.strip().endswith(f"{n} vectors, {n} passed, 0 failed")


def test_vectors_check_fails_on_a_wrong_vector_and_reports_a_broken_one(tmp_path):
    src = (ROOT / "vectors/p3964/fig2-6-receive.toml").read_text()
    (tmp_path / "wrong.toml").write_text(src.replace('expect = "10", within = "ADT", note = "DLE: the block',
                                                     'expect = "15", within = "ADT", note = "DLE: the block'))
    p = cli("vectors", "--check", "--dir", str(tmp_path))
    assert p.returncode == 1 and "1 vectors, 0 passed, 1 failed" in p.stdout and "FAIL 3964R.FIG2-6.RECEIVE" in p.stdout
    (tmp_path / "broken.toml").write_text(src.replace('group = "receive"', 'group = "recieve"'))
    p = cli("vectors", "--dir", str(tmp_path))
    assert p.returncode == 2 and "broken.toml: group:" in p.stderr


def test_report_renders_a_saved_run(tmp_path):
    j = tmp_path / "r.json"
    p = cli("run", "--iut", "sim:", "--profile", str(ROOT / "conformance/profiles/reference-20ms.toml"),
            "--select", "3964R.D0*", "--json", str(j), "-q")
    assert p.returncode == 0
    p = cli("report", str(j), "--junit", str(tmp_path / "j.xml"), "--html", str(tmp_path / "r.html"))
    assert p.returncode == 0 and (tmp_path / "j.xml").exists() and (tmp_path / "r.html").exists()
    data = json.loads(j.read_text())
    assert data["schema"] == "ptpcert-results/2" and all("transcript" in c for c in data["cases"])
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    p = cli("report", str(bad))
    assert p.returncode == 2 and "not a ptpcert results object" in p.stderr


def test_the_reference_iut_starts_without_what_it_does_not_need():
    """An exec: IUT is started for every case, so its start-up is part of every case's
    time: `ptpcert iut` (3964R) loads neither the ASCII station nor the capture and
    analysis modules."""
    done = subprocess.run([PY, "-X", "importtime", "-m", "ptpcert.cli", "iut", "--cdt-ms", "20",
                           "--adt-ms", "20", "--parmrk"], stdin=subprocess.DEVNULL, capture_output=True,
                          text=True, timeout=60)
    loaded = {line.rsplit("|", 1)[-1].strip() for line in done.stderr.splitlines() if line.startswith("import time:")}
    assert "ptpcert.procedures.p3964.model.station" in loaded and "ptpcert.iut" in loaded   # the import log is read
    for heavy in ("ptpcert.procedures.ascii.model.station", "ptpcert.capture", "ptpcert.cli.analyze", "ptpcert.cli.rules"):
        assert heavy not in loaded, f"ptpcert iut loads {heavy}"


def test_the_ascii_model_loads_each_name_on_first_use():
    import ptpcert.procedures.ascii.model as m

    for name in m.__all__:
        assert getattr(m, name) is not None
    assert m.AsciiStation.__module__ == "ptpcert.procedures.ascii.model.station"
    with pytest.raises(AttributeError):
        m.NoSuchName


def test_profile_examples_keys_and_check_from_an_empty_directory(tmp_path):
    """From a directory with nothing in it, a user gets a bundled example profile to start
    from, which loads as it is; every key of each procedure's schema is listed; a profile
    file is checked without running anything, and a typo is answered with the nearest name."""
    from ptpcert.registry import procedures
    from ptpcert.schema import COMMON

    def here(*args):
        return subprocess.run([PY, "-m", "ptpcert.cli", *args], cwd=tmp_path, capture_output=True, text=True,
                              timeout=300)
    listed = here("profile", "--list")
    assert listed.returncode == 0
    names = [ln.split()[0] for ln in listed.stdout.splitlines()[:-1]]
    assert len(names) >= 3
    for name in names:
        ex = here("profile", "--example", name)
        assert ex.returncode == 0 and "[iut]" in ex.stdout
        (tmp_path / f"{name}.toml").write_text(ex.stdout)
        ok = here("profile", "--check", f"{name}.toml")
        assert ok.returncode == 0 and "a valid" in ok.stdout, ok.stderr
    typo = here("profile", "--example", names[0][:-1] + "x")
    assert typo.returncode == 2 and f"did you mean {names[0]}?" in typo.stderr
    for proc in procedures():
        keys = here("profile", "--keys", proc.names[0])
        assert keys.returncode == 0
        for k in (*COMMON, *proc.profile_schema()):
            assert f"[{k.table}] {k.name}: {k.domain()}" in keys.stdout
    (tmp_path / "bad.toml").write_text(here("profile", "--example", names[0]).stdout.replace(
        "[iut]", "[iut]\nbogus_key = 1", 1))
    bad = here("profile", "--check", "bad.toml")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "bogus_key" in bad.stderr


def test_the_console_says_each_divergence_once():
    """A failed case's divergence is printed once, with its step and time, not again in the
    message's own words; the timer tolerance line is left out in virtual time when none is
    declared."""
    p = cli("run", "--iut", "sim:?mutant=no-dle-doubling", "--profile",
            str(ROOT / "conformance" / "profiles" / "reference-20ms.toml"), "--select", "3964R.FIG2-5.SEND")
    assert p.returncode == 1, p.stderr
    tail = p.stdout[p.stdout.index("not passed:"):]
    assert tail.count("step 7") == 1 and "step 7, at " in tail, tail
    assert "IUT timer tolerance" not in p.stdout


def test_the_reference_iut_s_options_are_held_to_the_profile_s_validation(tmp_path):
    """One validation for `ptpcert iut`'s options and for profiles: the default options of
    every procedure make a valid profile (no false refusal), and settings a profile refuses
    are refused as options too, in one line naming the same key."""
    from ptpcert.cli.iut import _options_problem
    from ptpcert.cli.main import build_parser
    from ptpcert.registry import by_name, procedures

    for proc in procedures():
        args = build_parser("iut").parse_args(["iut", "--procedure", proc.names[0]])
        assert _options_problem(proc, proc.params_from_iut(args), args) is None, proc.title
    p = cli("iut", "--procedure", "ASCII", "--end-criterion", "end_chars", "--end-chars", "03,0D,0A")
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and "end_chars" in p.stderr, p.stderr
    prof = tmp_path / "a.toml"
    prof.write_text((ROOT / "conformance" / "profiles" / "ascii-reference.toml").read_text().replace(
        "end_chars = [0x03]", "end_chars = [0x03, 0x0D, 0x0A]"))
    q = cli("profile", "--check", str(prof))
    assert q.returncode == 2 and "ascii.end_chars" in q.stderr, q.stderr
    assert by_name("ASCII") is not None
