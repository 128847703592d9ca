"""The ASCII reference implementation in real time (``ptpcert iut --procedure ASCII``) over
exec: and pty:: a representative part of the suite passes in each end criterion, with and
without XON/XOFF, at 7 and 8 data bits, and broken variants run as processes are caught.
The whole suite against every combination runs in sim: (tests/procedures/ascii/test_ascii_suite.py)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from ptpcert.procedures.ascii.description import iut_command, reference_profile
from ptpcert.procedures.ascii.mutants import MUTANTS

ROOT = Path(__file__).resolve().parents[3]
PY = sys.executable
#: the slow application of these runs reads after 3 s (the cases allow 10)
SETUPS = {"slow_reader": "--echo-delay-ms 3000", "send_job": "--send={jobs}"}

#: (settings, transport, cases of the suite, golden vectors): each end criterion, with and without XON/XOFF, at 7
#: and 8 data bits; with the CDT criterion a CDT of 50 ms, so that a process scheduled late
#: on a loaded machine does not cut its own frames
RUNS = {
    "cdt-none-8-exec": (dict(end_criterion="cdt", character_delay_ms=50), "exec",
                        ["CDT.ONE-FRAME", "CDT.GAP-MERGES", "CDT.EDGE-OVER", "CDT.CHARACTER-ERROR", "TX.PAUSE",
                         "LINE.BREAK-IN-FRAME"], ["ASCII.RX-CDT-04*"]),
    "cdt-xon-7-pty": (dict(end_criterion="cdt", character_delay_ms=50, data_bits=7, flow_control="xon_xoff",
                           xon_wait_ms=1000), "pty",
                      ["CDT.TWO-FRAMES", "CDT.EDGE-UNDER", "FC.XON-AT-START-UP", "FC.XOFF-MIDDLE",
                       "FC.XON-WAIT-EXPIRES", "TX.LEN-1"], []),
    "ec-xon-8-exec": (dict(end_criterion="end_chars", end_chars=[0x03], flow_control="xon_xoff", xon_wait_ms=1000),
                      "exec",
                      ["EC.BACK-TO-BACK", "EC.TRAILING-MERGED", "EC.NO-END-DISCARDED", "EC.COMPLETES-AT-ONCE",
                       "FC.XOFF-AFTER-FIRST", "FC.XOFF-AT-974-BYTES", "TX.UP-TO-END-CUTS"], ["ASCII.RX-EC-09*"]),
    "ec2-none-7-pty": (dict(end_criterion="end_chars", end_chars=[0x0D, 0x0A], send_variant="len_append_end",
                            data_bits=7), "pty",
                       ["EC2.LONE-FIRST-IS-DATA", "EC.TRAILING-DISCARDED", "TX.VARIANT-*", "LINE.BREAK-IDLE",
                        "TX.LEN-1025-REFUSED"], []),
    "fl-none-7-exec": (dict(end_criterion="fixed_length", fixed_length=8, data_bits=7, buffer_frames=4), "exec",
                       ["FL.BACK-TO-BACK", "FL.SHORT-MERGED", "FL.SURPLUS-DISCARDED", "FL.CHARACTER-ERROR", "TX.PAUSE",
                        "BUF.FULL-PREVENT-OVERWRITE"], []),
    "fl-xon-8-pty": (dict(end_criterion="fixed_length", fixed_length=100, flow_control="xon_xoff",
                          xon_wait_ms=1000), "pty",
                     ["FL.EXACT", "FL.EDGE-OVER", "FC.XOFF-NEAR-END", "FC.XON-WITHIN-WAIT", "FC.OVERFLOW",
                      "LINE.ALL-CODES"], []),
    # the cases added for the rules catalogue
    "cdt-none-8-exec": (dict(end_criterion="cdt", buffer_frames=12), "exec", ["LINE.ALL-CODES", "CDT.TOO-LONG"], []),
}


def write_profile(path: Path, profile) -> Path:
    d = profile.to_dict()
    table = d.pop("ascii")
    iut = {k: v for k, v in d.items() if k not in ("setups", "expected_failures")}
    lines = ["[iut]"] + [f"{k} = {json.dumps(v)}" for k, v in iut.items()]
    lines += ["", "[ascii]"] + [f"{k} = {json.dumps(v)}" for k, v in table.items()]
    lines += ["", "[iut.setups]"] + [f"{k} = {json.dumps(v)}" for k, v in SETUPS.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def ptpcert_run(tmp_path, profile, scheme, select, mutant=None, *extra):
    prof = write_profile(tmp_path / "p.toml", profile)
    cmd = iut_command(profile.params, mutant=mutant)
    iut = f"exec:{cmd}" if scheme == "exec" else f"pty:{cmd} --port {{port}}"
    j = tmp_path / "r.json"
    args = [PY, "-m", "ptpcert.cli", "run", "--iut", iut, "--profile", str(prof), "--json", str(j), "-q", *extra]
    for glob in select:
        args += ["--select", glob]
    p = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert j.exists(), p.stdout[-1000:] + p.stderr[-2000:]
    return p, json.loads(j.read_text())


@pytest.mark.realtime
@pytest.mark.parametrize("run", sorted(RUNS))
def test_the_real_time_reference_passes(tmp_path, run):
    settings, scheme, suite, vectors = RUNS[run]
    select = ["SUITE.ASCII." + c for c in suite] + vectors
    p, data = ptpcert_run(tmp_path, reference_profile(**settings), scheme, select)
    verdicts = {c["id"]: c["verdict"] for c in data["cases"]}
    bad = {c["id"]: c["message"][:300] for c in data["cases"] if c["verdict"] in ("fail", "error", "xpass")}
    assert p.returncode == 0 and not bad, (bad, p.stderr[-2000:])
    assert len(verdicts) >= len(select) and "unsupported" not in verdicts.values(), verdicts


#: broken variants as processes, each with the cases that catch it (the first failure stops the run)
REAL_MUTANTS = {
    "end-char-not-stored": ["EC.END-INCLUDED", "EC.LONE-END"],
    "no-start-up-xon": ["FC.XON-AT-START-UP"],
    "xoff-ignored": ["FC.XOFF-MIDDLE"],
    "char-error-delivered": ["CDT.CHARACTER-ERROR"],
    "send-pause-half": ["TX.PAUSE"],
}


@pytest.mark.realtime
@pytest.mark.parametrize("name", sorted(REAL_MUTANTS))
def test_real_time_mutants_are_caught(tmp_path, name):
    settings = dict(MUTANTS[name].profile)
    if settings.get("end_criterion") == "cdt":
        settings["character_delay_ms"] = 50
    select = ["SUITE.ASCII." + c for c in REAL_MUTANTS[name]]
    p, data = ptpcert_run(tmp_path, reference_profile(**settings), "exec", select, name,
                          "--max-failures", "1")
    failed = [c["id"] for c in data["cases"] if c["verdict"] == "fail"]
    assert p.returncode == 1 and failed, [(c["id"], c["verdict"], c["message"][:200]) for c in data["cases"]]
