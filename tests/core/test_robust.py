"""ptpcert under bad input and misbehaving IUTs.

* One battery drives every bad input through the ``ptpcert`` program (a process of its own,
  all started at once): each ends with exit status 2 and ONE line on stderr that names the
  file or option, the key and what is allowed, never a traceback.
* Reports always arrive: after one Ctrl-C, two Ctrl-Cs or SIGTERM, and when the IUT cannot
  even start; the JUnit file of an interrupted run has an error testcase for it.
* A flooding IUT gives bounded reports, written quickly.
* No IUT process outlives its use, in ``ptpcert run`` and ``ptpcert fuzz``.
"""

from __future__ import annotations

import json
import os
import signal
import struct
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from argparse import Namespace
from pathlib import Path

import pytest

from ptpcert import results as R

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
IUT = f"{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk"
FAKES = ROOT / "tests" / "fakes"

VECTOR = '''id = "X.BAD"
title = "a broken vector"
reference = "§2.2.2"
rule = "r"
group = "receive"
iut_role = "receiver"
steps = [ {STEPS} ]
[params]
procedure = "3964R"
'''


def vector_dir(root: Path, name: str, steps: str | None = None, raw: bytes | None = None) -> str:
    d = root / name
    d.mkdir()
    (d / "x.toml").write_bytes(raw if raw is not None else VECTOR.replace("{STEPS}", steps).encode())
    return str(d)


def bad_inputs(root: Path) -> dict[str, tuple[list[str], list[str]]]:
    """name -> (ptpcert arguments, what the one line on stderr must say)."""
    P = str(PROFILE)
    utf16 = "[iut]\nprocedure = \"3964R\"\n".encode("utf-16")          # with its BOM
    noise = bytes(range(128, 256)) * 2
    (root / "utf16.toml").write_bytes(utf16)
    (root / "noise.toml").write_bytes(noise)
    (root / "adir.toml").mkdir()
    (root / "list.json").write_text("[]")
    (root / "noise.json").write_bytes(noise)
    case = {"id": "X.A", "title": "t", "reference": "r", "rule": "r", "group": "receive", "iut_role": "receiver",
            "verdict": "banana"}
    (root / "banana.json").write_text(json.dumps({"schema": R.SCHEMA, "cases": [case]}))
    (root / "good.json").write_text(json.dumps({"schema": R.SCHEMA, "cases": [dict(case, verdict="pass")]}))
    (root / "typo.toml").write_text(PROFILE.read_text() + '"3964R.D08.DLE-OTHR" = "known issue 12"\n')
    (root / "a-file").write_text("")
    run = ["run", "--iut", "sim:", "--profile", P]
    fuzz = ["fuzz", "--iut", "sim:", "--profile", P]
    # output paths that are not regular files: a FIFO, a symlink to a device (checked before the
    # capture is even read, so the capture named need not exist)
    fifo, link = root / "a-fifo", root / "null-link.json"
    os.mkfifo(fifo)
    link.symlink_to("/dev/null")
    cap = str(root / "cap.pcap")
    analyze = ["analyze", cap, "--profile", P]
    monitor = ["monitor", "--a", "loop://", "--b", "loop://", "--profile", P]
    # input files with nothing to judge, or JSON the reader cannot take
    (root / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    (root / "digits.json").write_text('{"format": "ptpcert-capture/1", "end": ' + "9" * 5000 + "}")
    (root / "digits-results.json").write_text('{"schema": "' + R.SCHEMA + '", "wall_time": ' + "9" * 5000 + "}")
    (root / "empty.hexlog").write_text("")
    pcap_header = struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, 250)
    (root / "header-only.pcap").write_bytes(pcap_header)
    body = struct.pack(">IIBBH", 0, 0, 0x42, 0, 0) + b"AB"        # event type 0x42: none of RTAC serial's
    (root / "unknown-events.pcap").write_bytes(pcap_header + struct.pack("<IIII", 1, 0, len(body), len(body)) + body)
    # a capture of a run of another procedure than the profile's
    (root / "rk512-run.hexlog").write_text("# ptpcert-hexlog 1\n# line: 9600 8E1\n# note: run of 1 case against sim:\n"
                                           "# note: procedure: RK 512\n0.000000 b 15\n")
    rk = (ROOT / "conformance" / "profiles" / "rk512-reference.toml").read_text()
    assert "--cf-set {flag}@{reset_ms}" in rk
    for name, words in (("flagg", "--cf-set {flagg}@{reset_ms}"), ("brace", "--cf-set {flag@{reset_ms}"),
                        ("quote", "--cf-set '{flag}@{reset_ms}")):
        (root / f"setup-{name}.toml").write_text(rk.replace("--cf-set {flag}@{reset_ms}", words))
    vlink = root / "v-link"
    vlink.mkdir()
    first = sorted((ROOT / "vectors" / "rk512").glob("*.toml"))[0].read_text()
    (vlink / "x.toml").write_text(first.replace('[params]', '[params]\nlink = "9999"', 1)
                                  if 'link = ' not in first else
                                  __import__("re").sub(r'(?m)^link = .*$', 'link = "9999"', first, count=1))
    other = root / "v-ascii"
    other.mkdir()
    (other / "x.toml").write_text((ROOT / "vectors" / "ascii" / "buf-fifo.toml").read_text())
    return {
        # input files: nothing to judge is not a pass; JSON the reader cannot take is named
        "analyze []": (["analyze", str(root / "list.json"), "--profile", P], ["list.json", "empty array"]),
        "capture convert []": (["capture", "convert", str(root / "list.json"), str(root / "l.hexlog")],
                               ["list.json", "empty array"]),
        "analyze, JSON nested 100,000 deep": (["analyze", str(root / "deep.json"), "--profile", P],
                                              ["deep.json", "nested too deep"]),
        "capture convert, JSON nested 100,000 deep": (["capture", "convert", str(root / "deep.json"), "-"],
                                                      ["deep.json", "nested too deep"]),
        "report, JSON nested 100,000 deep": (["report", str(root / "deep.json")], ["deep.json", "nested too deep"]),
        "analyze, a 5000-digit number": (["analyze", str(root / "digits.json"), "--profile", P],
                                         ["digits.json", "a number of more than 4300 digits"]),
        "capture convert, a 5000-digit number": (["capture", "convert", str(root / "digits.json"), "-"],
                                                 ["digits.json", "a number of more than 4300 digits"]),
        "report, a 5000-digit number": (["report", str(root / "digits-results.json")],
                                        ["digits-results.json", "a number of more than 4300 digits"]),
        "analyze an empty hex log": (["analyze", str(root / "empty.hexlog"), "--profile", P],
                                     ["empty.hexlog", "no characters and no line conditions", "nothing to judge"]),
        "analyze a header-only pcap": (["analyze", str(root / "header-only.pcap"), "--profile", P],
                                       ["header-only.pcap", "nothing to judge"]),
        "analyze a pcap of unknown event types": (["analyze", str(root / "unknown-events.pcap"), "--profile", P],
                                                  ["unknown-events.pcap", "event type 0x42 is unknown",
                                                   "nothing to judge"]),
        "analyze a capture of another procedure": (["analyze", str(root / "rk512-run.hexlog"), "--profile", P],
                                                   ["rk512-run.hexlog", "a run of RK 512",
                                                    "the profile is for 3964/3964R"]),
        # a setup's words are checked when the profile loads, not as errors of the cases
        "setup with an unknown placeholder": (["run", "--iut", "sim:", "--profile", str(root / "setup-flagg.toml")],
                                              ["iut.setups.flag_set", "no placeholder {flagg}", "{flag}, {reset_ms}"]),
        "setup with unpaired braces": (["run", "--iut", "sim:", "--profile", str(root / "setup-brace.toml")],
                                       ["iut.setups.flag_set", "braces of its placeholders do not pair"]),
        "setup with an open quote": (["run", "--iut", "sim:", "--profile", str(root / "setup-quote.toml")],
                                     ["iut.setups.flag_set", "cannot be split as a shell would"]),
        # messages that name the right thing
        "vector with link 9999": (["vectors", "--dir", str(vlink)], ["params.link", "'9999' is not allowed",
                                                                       '"3964R", "3964"']),
        "monitor --capture x.bin": (monitor + ["--capture", str(root / "x.bin")],
                                    ["--capture", "x.bin", "name it .pcap"]),
        "run --vectors-only, none for the procedure": (run + ["--vectors", str(other), "--vectors-only"],
                                                       ["no case to run", "v-ascii", "is for 3964/3964R"]),
        # every command that writes a file checks every output path first, and never replaces
        # a device or a FIFO with a regular file
        "analyze --json /dev/null": (analyze + ["--json", "/dev/null"], ["--json /dev/null", "not a regular file"]),
        "analyze --junit FIFO": (analyze + ["--junit", str(fifo)], ["--junit", "a-fifo", "not a regular file"]),
        "analyze --html symlink to a device": (analyze + ["--html", str(link)],
                                               ["--html", "null-link.json", "not a regular file"]),
        "analyze --html in /proc": (analyze + ["--html", "/proc/x/y"], ["--html /proc/x/y", "cannot be created"]),
        "analyze, one file, two reports": (analyze + ["--html", str(root / "s.out"), "--junit", str(root / "s.out")],
                                           ["--html", "is also --junit", "give each report its own file"]),
        "analyze over its own capture": (analyze + ["--json", cap], ["--json", "is also the file read"]),
        "analyze --tolerance-ms nan": (analyze + ["--tolerance-ms", "nan"], ["--tolerance-ms", "from 0 to 60000 ms"]),
        "analyze --tolerance-ms -5": (analyze + ["--tolerance-ms", "-5"], ["--tolerance-ms", "from 0 to 60000 ms"]),
        "analyze --resolution-ms nan": (analyze + ["--resolution-ms", "nan"], ["--resolution-ms", "from 0 to 60000"]),
        "analyze --resolution-ms 1e308": (analyze + ["--resolution-ms", "1e308"], ["--resolution-ms", "from 0 to"]),
        "analyze --resolution-ms -1": (analyze + ["--resolution-ms", "-1"], ["--resolution-ms", "from 0 to"]),
        "monitor --duration nan": (monitor + ["--duration", "nan"], ["--duration", "from 0.001 to 604800 seconds"]),
        "monitor --duration -1": (monitor + ["--duration", "-1"], ["--duration", "from 0.001 to 604800"]),
        "monitor --fifo -3": (monitor + ["--fifo", "-3"], ["--fifo", "from 1 to 4096 characters"]),
        "monitor --latency-ms -1": (monitor + ["--latency-ms", "-1"], ["--latency-ms", "from 0 to 60000 ms"]),
        "monitor --capture /dev/null": (monitor + ["--capture", "/dev/null"], ["--capture /dev/null", "not a regular"]),
        "monitor --capture FIFO": (monitor + ["--capture", str(fifo)], ["--capture", "a-fifo", "not a regular"]),
        "monitor --html in /proc": (monitor + ["--html", "/proc/x/y"], ["--html /proc/x/y", "cannot be created"]),
        "monitor, capture and report one file": (monitor + ["--capture", str(root / "m.pcap"), "--json",
                                                            str(root / "m.pcap")], ["--capture", "is also a report"]),
        "capture convert onto /dev/null": (["capture", "convert", cap, "/dev/null", "--to", "hexlog"],
                                           ["/dev/null", "not a regular file"]),
        "capture convert onto a FIFO": (["capture", "convert", cap, str(fifo), "--to", "hexlog"],
                                        ["a-fifo", "not a regular file"]),
        "capture convert onto its input": (["capture", "convert", cap, cap], ["cap.pcap", "is also the input"]),
        "fuzz --export in /proc": (fuzz + ["--export", "/proc/x/y"], ["--export /proc/x/y", "cannot be created"]),
        "fuzz --export a file": (fuzz + ["--export", str(root / "a-file")], ["--export", "not a directory"]),
        "fuzz --database in /proc": (fuzz + ["--database", "/proc/x/y"], ["database /proc/x/y", "cannot be created"]),
        "fuzz --database a file": (fuzz + ["--database", str(root / "a-file")], ["database", "not a directory"]),
        # files that are not UTF-8: profiles and vectors, under each command, with the file name
        "profile UTF-16": (["run", "--iut", "sim:", "--profile", str(root / "utf16.toml")],
                           ["utf16.toml", "is not UTF-8 text", "save the profile as UTF-8"]),
        "profile random bytes": (["run", "--iut", "sim:", "--profile", str(root / "noise.toml")],
                                 ["noise.toml", "is not UTF-8 text"]),
        "profile UTF-16 (fuzz)": (["fuzz", "--iut", "sim:", "--profile", str(root / "utf16.toml")],
                                  ["utf16.toml", "is not UTF-8 text"]),
        "profile is a directory": (["run", "--iut", "sim:", "--profile", str(root / "adir.toml")],
                                   ["adir.toml", "is a directory"]),
        "profile is a device": (["run", "--iut", "sim:", "--profile", "/dev/zero"],
                                ["/dev/zero", "is a device, not a profile file"]),
        "profile missing": (["run", "--iut", "sim:", "--profile", str(root / "none.toml")],
                            ["none.toml", "no such file"]),
        "vector UTF-16 (run)": (run + ["--vectors", vector_dir(root, "v-utf16", raw=utf16)],
                                ["v-utf16/x.toml", "is not UTF-8 text"]),
        "vector random bytes (vectors)": (["vectors", "--dir", vector_dir(root, "v-noise", raw=noise)],
                                          ["v-noise/x.toml", "is not UTF-8 text"]),
        # vector expressions that load but would break at run time
        "repeat count": (["vectors", "--dir", vector_dir(root, "v-repeat", '{ send = "41*99999999999" }')],
                         ["steps[0].send", "at most 2056 repetitions"]),
        "name in hex": (["vectors", "--dir", vector_dir(root, "v-name", '{ send = "STX" }')],
                        ["steps[0].send", "'STX': names are not allowed here", "02 for STX"]),
        "division by zero": (["vectors", "--dir", vector_dir(root, "v-div", '{ send = "02" }, { expect = "10", within = "CDT/0" }')],
                             ["steps[1].within", "'CDT/0' cannot be computed"]),
        "negative window": (["vectors", "--dir", vector_dir(root, "v-neg", '{ send = "02" }, { expect = "10", within = "-CDT" }')],
                            ["steps[1].within", "a window cannot close before the reference point"]),
        "overflowing window": (["vectors", "--dir", vector_dir(root, "v-inf", '{ send = "02" }, { expect = "10", within = "1e400*CDT" }')],
                               ["steps[1].within", "is not a finite duration"]),
        # saved results that are not a results object
        "report on []": (["report", str(root / "list.json")], ["list.json", "the JSON is an array"]),
        "report, unknown verdict": (["report", str(root / "banana.json")],
                                    ["banana.json", "'banana' is not a verdict", "allowed: fail, xpass"]),
        "report, not UTF-8": (["report", str(root / "noise.json")], ["noise.json", "is not UTF-8 text"]),
        "report on a device": (["report", "/dev/zero"], ["/dev/zero", "is a device, not a results file"]),
        "report over its own input": (["report", str(root / "good.json"), "--html", str(root / "good.json")],
                                      ["--html", "is also the file read"]),
        # numeric options
        "--tolerance-ms nan": (run + ["--tolerance-ms", "nan"], ["--tolerance-ms", "from 0 to 10000 milliseconds"]),
        "--tolerance-ms -5": (run + ["--tolerance-ms", "-5"], ["--tolerance-ms", "from 0 to 10000"]),
        "--startup-timeout -1": (run + ["--startup-timeout", "-1"], ["--startup-timeout", "from 0.1 to 600 seconds"]),
        "--startup-timeout inf": (run + ["--startup-timeout", "inf"], ["--startup-timeout", "from 0.1 to 600"]),
        "--max-failures -3": (run + ["--max-failures", "-3"], ["--max-failures", "0 or more (0: no limit)"]),
        "--edge-attempts 0": (run + ["--edge-attempts", "0"], ["--edge-attempts", "from 1 to 100"]),
        "--budget nan": (fuzz + ["--budget", "nan"], ["--budget", "from 1 to 604800 seconds"]),
        "--budget 1e-9": (fuzz + ["--budget", "1e-9"], ["--budget", "from 1 to 604800"]),
        "--budget inf": (fuzz + ["--budget", "inf"], ["--budget", "from 1 to 604800"]),
        "--max-actions 0": (fuzz + ["--max-actions", "0"], ["--max-actions", "from 1 to 100"]),
        # a typo in [expected_failures] would silently disable the expectation
        "expected failure typo": (["run", "--iut", "sim:", "--profile", str(root / "typo.toml")],
                                  ["typo.toml", "expected_failures", "'3964R.D08.DLE-OTHR' matches no case",
                                   "nearest: 3964R.D08.DLE-OTHER"]),
        # IUT URLs
        "unknown mutant": (["run", "--iut", "sim:?mutant=nosuch", "--profile", P],
                           ["mutant='nosuch'", "known: ", "no-dle-doubling"]),
        "scheme typo": (["run", "--iut", "exce:ptpcert iut", "--profile", P],
                        ["--iut exce:ptpcert iut", "unknown scheme 'exce:'", "did you mean exec:",
                         "exec:COMMAND", "rfc2217://HOST:PORT"]),
        # selections that match nothing
        "vectors --select NOPE*": (["vectors", "--select", "NOPE*"], ["no vector matches --select NOPE*"]),
        "run --select NOPE*": (run + ["--select", "NOPE*"], ["no case matches --select NOPE*"]),
        # report paths, checked before the first case
        "--json a directory": (run + ["--json", str(root)], ["--json", "is a directory"]),
        "--junit in /proc": (run + ["--junit", "/proc/ptpcert-junit.xml"], ["--junit", "no file can be written in /proc"]),
        "--html under a file": (run + ["--html", str(root / "a-file" / "r.html")],
                                ["--html", "a-file", "cannot be created"]),
        "--json /dev/null": (run + ["--json", "/dev/null"], ["--json /dev/null", "not a regular file"]),
        "one file, two reports": (run + ["--json", str(root / "r.out"), "--junit", str(root / "r.out")],
                                  ["--json", "is also --junit", "give each report its own file"]),
    }


def _in_process(argv: list[str]) -> tuple[int, str, str]:
    """``ptpcert ARGV`` through the program's entry point in this process."""
    import contextlib
    import io
    import traceback

    from ptpcert.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(argv)
        except SystemExit as exc:      # argparse
            rc = exc.code if isinstance(exc.code, int) else 2
        except BaseException:          # what would reach the user as a traceback
            err.write(traceback.format_exc())
            rc = 1
    return rc, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def battery(tmp_path_factory):
    """Every bad input through the program's entry point, in this process (milliseconds)."""
    root = tmp_path_factory.mktemp("bad")
    out = {"root": root}
    for name, (argv, want) in bad_inputs(root).items():
        out[name] = (*_in_process(argv), want)
    return out


@pytest.fixture(scope="module")
def program_battery(tmp_path_factory):
    """Every bad input, each run by the ptpcert program as a process, all at once."""
    root = tmp_path_factory.mktemp("bad-program")
    procs = {name: (subprocess.Popen([PY, "-m", "ptpcert.cli", *argv], cwd=root, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True), want)
             for name, (argv, want) in bad_inputs(root).items()}
    out = {"root": root}
    for name, (p, want) in procs.items():
        stdout, stderr = p.communicate(timeout=300)
        out[name] = (p.returncode, stdout, stderr, want)
    return out


def _names() -> list[str]:
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        return list(bad_inputs(Path(d)))


BOTH = ["entry point", pytest.param("program", marks=pytest.mark.realtime)]


@pytest.mark.parametrize("how", BOTH)
@pytest.mark.parametrize("name", _names())
def test_bad_input_is_one_line_and_exit_2(request, how, name):
    """Each bad input: exit status 2, ONE line on stderr naming the file or option, the key
    and what is allowed, no traceback, nothing run. Through the program's entry point in
    this process (fast), and as the ptpcert program itself (realtime: a process each)."""
    results = request.getfixturevalue("battery" if how == "entry point" else "program_battery")
    rc, stdout, stderr, want = results[name]
    assert "Traceback" not in stderr + stdout
    assert rc == 2, (rc, stderr, stdout[-500:])
    lines = stderr.splitlines()
    assert len(lines) == 1, stderr
    for text in want:
        assert text in lines[0], (text, lines[0])
    assert not stdout.strip(), stdout[-500:]   # nothing ran, nothing printed


@pytest.mark.parametrize("how", BOTH)
def test_nothing_is_written_when_the_usage_is_bad(request, how):
    # the checks come before the first case: no report, and no temporary or probe file left
    root = request.getfixturevalue("battery" if how == "entry point" else "program_battery")["root"]
    assert not (root / "r.out").exists()
    left = [p.name for p in root.rglob("*") if p.name.endswith((".tmp", ".probe"))]
    assert left == []


# ------------------------------------------------------------------ reports always arrive
def _run_and_signal(tmp_path, send):
    """Start a run of the whole suite against the reference IUT; once three cases are
    done, ``send(proc)``; return (exit status, stdout, stderr, the report paths)."""
    paths = {k: tmp_path / f"r.{k}" for k in ("json", "junit", "html")}
    args = [PY, "-m", "ptpcert.cli", "run", "--iut", f"exec:{IUT}", "--profile", str(PROFILE)]
    for k, p in paths.items():
        args += [f"--{k}", str(p)]
    proc = subprocess.Popen(args, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    out, done = [], 0
    while done < 3:
        line = proc.stdout.readline()
        assert line, "the run ended before three cases"
        out.append(line)
        done += line.startswith("[")
    send(proc)
    rest, err = proc.communicate(timeout=120)
    return proc.returncode, "".join(out) + rest, err, paths


def _two_sigints(proc):
    proc.send_signal(signal.SIGINT)
    time.sleep(0.05)          # the second one comes while the IUT is stopped and the reports written
    proc.send_signal(signal.SIGINT)


def _sigint_storm(proc):
    proc.send_signal(signal.SIGINT)
    while proc.poll() is None:   # then more, every few milliseconds, until it ends
        time.sleep(0.005)
        try:
            proc.send_signal(signal.SIGINT)
        except ProcessLookupError:
            break


@pytest.mark.realtime
@pytest.mark.parametrize("how", ["one Ctrl-C", "two Ctrl-Cs", "Ctrl-C storm", "SIGTERM"])
def test_an_interrupted_run_leaves_every_report(tmp_path, how):
    send = {"one Ctrl-C": lambda p: p.send_signal(signal.SIGINT), "two Ctrl-Cs": _two_sigints,
            "Ctrl-C storm": _sigint_storm, "SIGTERM": lambda p: p.send_signal(signal.SIGTERM)}[how]
    rc, out, err, paths = _run_and_signal(tmp_path, send)
    assert rc == 2, (out[-2000:], err)
    assert "Traceback" not in err
    data = json.loads(paths["json"].read_text())
    assert data["interrupted"] is True and data["schema"] == R.SCHEMA
    verdicts = [c["verdict"] for c in data["cases"]]
    assert "pass" in verdicts and "not-run" in verdicts and len(verdicts) > 100
    suite = ET.parse(paths["junit"]).getroot()
    cases = suite.findall(".//testcase")
    assert len(cases) == len(verdicts) + 1          # every case, and the interruption
    (stop,) = [c for c in cases if c.get("classname") == "ptpcert.run"]
    assert stop.find("error") is not None and "interrupted" in stop.find("error").get("message")
    html = paths["html"].read_text()
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>") and "interrupted" in html
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in paths.values())   # no temp file


@pytest.mark.realtime
def test_an_iut_that_dies_at_start_up_still_gets_reports(tmp_path):
    paths = {k: tmp_path / "out" / f"r.{k}" for k in ("json", "junit", "html")}
    args = ["run", "--iut", f"exec:{PY} {FAKES / 'dies_at_startup.py'}", "--profile", str(PROFILE),
            "--select", "3964R.*"]
    for k, p in paths.items():
        args += [f"--{k}", str(p)]
    p = subprocess.run([PY, "-m", "ptpcert.cli", *args], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "the IUT ended at start-up (exit status 3): fake IUT: cannot open its configuration" in p.stderr
    data = json.loads(paths["json"].read_text())
    assert data["cases"] and {c["verdict"] for c in data["cases"]} == {"error"}
    assert all("cannot open its configuration" in c["message"] for c in data["cases"])
    errors = ET.parse(paths["junit"]).getroot().findall(".//testcase/error")
    assert len(errors) == len(data["cases"]) and "could not be started" in errors[0].get("message")
    assert "cannot open its configuration" in paths["html"].read_text()


def test_a_signal_while_the_reports_are_written_is_only_counted(tmp_path, monkeypatch):
    """In process, deterministic: the HTML writer is hit by SIGINT and SIGTERM; the reports
    are still all written, and the run exits 2."""
    from ptpcert.cli import run as cli_run
    from ptpcert.report import html

    real = html.write_html
    hits = []

    def interrupted_writer(result, path, view=None):
        os.kill(os.getpid(), signal.SIGINT)
        os.kill(os.getpid(), signal.SIGTERM)
        hits.append(path)
        real(result, path, view)

    monkeypatch.setattr(html, "write_html", interrupted_writer)
    old = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    args = Namespace(iut="sim:", profile=str(PROFILE), select=["3964R.D0*"], vectors=[], vectors_only=False,
                     tolerance_ms=50.0, startup_timeout=2.0, edge_attempts=4, max_failures=0, quiet=True,
                     json=str(tmp_path / "r.json"), junit=str(tmp_path / "j.xml"), html=str(tmp_path / "r.html"))
    assert cli_run.cmd_run(args) == 2
    assert hits and all((tmp_path / n).exists() for n in ("r.json", "j.xml", "r.html"))
    assert json.loads((tmp_path / "r.json").read_text())["counts"]["pass"] >= 5
    # the handlers of the caller are back (the command was not the process's last act)
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == old


# ------------------------------------------------------------------ a flooding IUT
@pytest.mark.realtime
def test_a_10_mb_flood_over_the_whole_suite_gives_small_reports_quickly(tmp_path):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        from bench_reports import flood_run
    finally:
        sys.path.pop(0)
    from ptpcert.cli.reports import write_reports

    result = flood_run(10_000_000, None)
    ran = [c for c in result.cases if c.verdict != R.UNSUPPORTED]
    assert len(ran) > 100
    flooded = 0
    for c in ran:
        assert c.verdict == R.FAIL, (c.id, c.verdict, c.message)
        iut = sum(len(v) for _, d, k, v, _ in R.wire_runs(c.transcript) if d == "iut" and k == "byte")
        assert iut <= 20000
        if "more than 20000 bytes" in c.message:
            flooded += 1
            assert iut == 20000
            (mark,) = [e for e in c.transcript if e["kind"] == "dropped"]
            assert mark["bytes"] > 0 and mark["kept"] == 20000
        # else: the case failed at the first wrong byte before the flood limit was reached
        # (random bytes can begin with the expected one, e.g. the start-up NAK, and a read
        # may end inside the flooder's first write): a fail as well, with a shorter transcript
    assert flooded >= 0.9 * len(ran), f"only {flooded} of {len(ran)} cases reached the flood limit"
    args = Namespace(json=str(tmp_path / "results.json"), junit=str(tmp_path / "junit.xml"),
                     html=str(tmp_path / "report.html"))
    t = time.monotonic()
    assert write_reports(result, args, "run") == {"json", "junit", "html"}
    elapsed = time.monotonic() - t
    size = (tmp_path / "results.json").stat().st_size
    print(f"10 MB flood, {len(result.cases)} cases: results.json {size / 1e6:.2f} MB, "
          f"all reports written in {elapsed:.2f} s")
    assert size < 5_000_000 and elapsed < 10.0
    back = R.RunResult.read_json(tmp_path / "results.json")
    assert [c.verdict for c in back.cases] == [c.verdict for c in result.cases]


# ------------------------------------------------------------------ IUTs that misbehave
@pytest.mark.realtime
def test_an_iut_that_closes_its_output_is_reported_for_what_it_is(tmp_path):
    j = tmp_path / "r.json"
    p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", f"exec:{PY} {FAKES / 'closes_stdout.py'}",
                        "--profile", str(PROFILE), "--select", "3964R.D02.*", "--json", str(j)],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert p.returncode == 1
    (case,) = json.loads(j.read_text())["cases"]
    assert case["verdict"] == "fail"
    assert "closed its side of the line" in case["message"] and "keeps running" in case["message"]
    assert "exit status None" not in case["message"]


# ------------------------------------------------------------------ no process outlives its use
def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.realtime
@pytest.mark.parametrize("command", ["run", "fuzz"])
def test_no_iut_process_is_left_behind(tmp_path, command):
    pids = tmp_path / "pids"
    iut = f"exec:{PY} {FAKES / 'pidlog.py'} {pids} {IUT}"
    args = ["--iut", iut, "--profile", str(PROFILE)]
    args += (["--select", "3964R.D0*", "--json", str(tmp_path / "r.json")] if command == "run"
             else ["--budget", "6", "--seed", "3", "--export", str(tmp_path / "found")])
    p = subprocess.run([PY, "-m", "ptpcert.cli", command, *args], cwd=ROOT, capture_output=True, text=True,
                       timeout=300)
    assert p.returncode in (0, 1), p.stdout[-2000:] + p.stderr
    started = [int(x) for x in pids.read_text().split()]
    assert len(started) >= 5
    assert [pid for pid in started if _alive(pid)] == []


@pytest.mark.realtime
def test_the_fuzzer_stops_each_iut_when_its_example_is_judged():
    from ptpcert.fuzz import Campaign
    from ptpcert.procedures.p3964.description import reference_profile
    from ptpcert.runner import Runner, RunOptions
    from ptpcert.transport import ProcessFactory
    from ptpcert.transport.process import ExecTransport

    class Watched(ProcessFactory):
        def __init__(self, *a, **kw):
            self.every, self.handed = [], []
            super().__init__(*a, **kw)

        def _started(self, command):
            t = super()._started(command)
            self.every.append(t)
            return t

        def __call__(self, vector, params):
            t = super().__call__(vector, params)
            self.handed.append(t)
            return t

    profile = reference_profile()
    factory = Watched(ExecTransport, IUT, parmrk=True, status=True, prespawn=2, max_idle=3.0)
    camp = Campaign(profile, Runner(factory, profile, RunOptions(check_status=False)), 8.0, 3)
    checks = []

    def judged(v):
        res = Runner.run_case(camp.runner, v)
        # the example's own IUT has ended; only those started ahead for the next wait
        assert all(t.proc.poll() is not None for t in factory.handed)
        assert factory.alive() <= factory.prespawn
        now = time.monotonic()
        assert all(now - since <= factory.max_idle + 3.0 for r in factory._ready.values() for since, _ in r)
        checks.append(res.verdict)
        return res

    camp._run_vector = judged
    try:
        camp.run()
        assert checks, "no example ran"
        assert factory.alive() == 0           # the campaign's last round released them
        assert [t for t in factory.every if t.proc.poll() is None] == []
    finally:
        factory.shutdown()


def test_a_fault_of_ptpcert_during_the_run_still_gives_every_report(tmp_path, monkeypatch):
    """A bug in the harness outside a case (here: the runner's loop itself raises) costs
    neither the reports nor a traceback: the cases not reached are errors naming the fault."""
    from ptpcert.cli import run as cli_run
    from ptpcert.runner import Runner

    def broken(self, vectors, result, progress=None, max_failures=0):
        result.cases.append(self.run_case(list(vectors)[0]))
        raise RuntimeError("a bug in the loop")

    monkeypatch.setattr(Runner, "run", broken)
    args = Namespace(iut="sim:", profile=str(PROFILE), select=["3964R.D0*"], vectors=[], vectors_only=False,
                     tolerance_ms=50.0, startup_timeout=2.0, edge_attempts=4, max_failures=0, quiet=True,
                     json=str(tmp_path / "r.json"), junit=str(tmp_path / "j.xml"), html=str(tmp_path / "r.html"))
    assert cli_run.cmd_run(args) == 2
    data = json.loads((tmp_path / "r.json").read_text())
    verdicts = [c["verdict"] for c in data["cases"]]
    assert verdicts[0] == "pass" and set(verdicts[1:]) == {"error"} and len(verdicts) > 3
    assert "harness fault: RuntimeError: a bug in the loop" in data["cases"][1]["message"]
    assert (tmp_path / "j.xml").exists() and (tmp_path / "r.html").exists()


def test_a_file_writer_never_replaces_a_device_or_a_fifo(tmp_path):
    """Below the commands' checks, the writers themselves refuse a target that exists and is
    not a regular file (renaming a temporary file over a device, as root, replaces it)."""
    import stat

    from ptpcert import capture as C
    from ptpcert.results import write_atomic

    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    link = tmp_path / "null"
    link.symlink_to("/dev/null")
    for target in (fifo, link):
        with pytest.raises(OSError, match="not a regular file"):
            write_atomic(target, "{}")
        with pytest.raises(C.CaptureError, match="not a regular file"):
            C.save(C.Capture([], {"a": "a", "b": "b"}), target, "hexlog")
    assert stat.S_ISFIFO(os.stat(fifo).st_mode) and stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f", "null"]
