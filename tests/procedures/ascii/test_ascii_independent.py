"""An ASCII driver written by someone else from the manual (tests/independent/ascii/iut_ascii.py,
one correct station and broken variants), driven only through the issue's interface: the
profile's keys as its command-line options, the echo application, PARMRK line conditions,
STATUS lines on stderr, and the ``slow_reader`` setup as its ``--echo-delay-ms``. The correct
one passes the suite in every end criterion, with and without XON/XOFF, at 7 and 8 data bits;
every broken one fails it. These run in real time (``@pytest.mark.realtime``)."""

import json
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
PY = sys.executable
INDEPENDENT = ROOT / "tests" / "independent" / "ascii" / "iut_ascii.py"
#: its application reads a stored frame 3 s late (the cases allow 10 s)
SETUPS = {"slow_reader": "--echo-delay-ms 3000"}


def profile_text(settings: dict) -> str:
    """The issue's profile for these settings ([iut] and [ascii] keys as the issue names them)."""
    iut = dict(procedure="ASCII", character_delay_ms=20, baud_rate=9600, send_trigger="echo",
               line_conditions="parmrk", status_from_stderr=True)
    ascii_ = dict(end_criterion="end_chars", end_chars=[0x03])
    for k, v in settings.items():
        (iut if k in ("character_delay_ms", "baud_rate", "data_bits", "parity", "stop_bits") else ascii_)[k] = v
    lines = ["[iut]"] + [f"{k} = {json.dumps(v)}" for k, v in iut.items()]
    lines += ["", "[ascii]"] + [f"{k} = {json.dumps(v)}" for k, v in ascii_.items()]
    lines += ["", "[iut.setups]"] + [f"{k} = {json.dumps(v)}" for k, v in SETUPS.items()]
    return "\n".join(lines) + "\n"


def command(settings: dict, variant: str | None = None) -> str:
    """The independent station's command line for these profile settings: one option per key."""
    words = [PY, str(INDEPENDENT), "--cdt-ms", str(settings.get("character_delay_ms", 20)), "--parmrk"]
    opt = {"baud_rate": "--baud", "data_bits": "--data-bits", "parity": "--parity", "stop_bits": "--stop-bits",
           "end_criterion": "--end-criterion", "fixed_length": "--fixed-length", "send_variant": "--send-variant",
           "flow_control": "--flow-control", "xon_wait_ms": "--xon-wait-ms", "buffer_frames": "--buffer-frames"}
    s = dict(end_criterion="end_chars", end_chars=[0x03]) | settings
    for k, v in s.items():
        if k in opt:
            words += [opt[k], str(v)]
    words += ["--end-chars", ",".join(f"{c:02X}" for c in s["end_chars"])]
    if "prevent_overwrite" in s:
        words.append("--prevent-overwrite" if s["prevent_overwrite"] else "--no-prevent-overwrite")
    if "send_pause" in s:
        words.append("--send-pause" if s["send_pause"] else "--no-send-pause")
    if variant:
        words += ["--break", variant]
    return " ".join(shlex.quote(w) for w in words)


def run(tmp_path: Path, settings: dict, scheme: str = "exec", variant: str | None = None,
        select: list[str] = (), *extra: str):
    prof = tmp_path / "p.toml"
    prof.write_text(profile_text(settings))
    cmd = command(settings, variant)
    iut = f"exec:{cmd}" if scheme == "exec" else f"pty:{cmd} --device {{port}}"
    j = tmp_path / "r.json"
    args = [PY, "-m", "ptpcert.cli", "run", "--iut", iut, "--profile", str(prof), "--json", str(j), "-q", *extra]
    for glob in select:
        args += ["--select", glob]
    p = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert j.exists(), p.stdout[-1000:] + p.stderr[-2000:]
    return p, json.loads(j.read_text())


#: the correct station, the whole suite: each end criterion, with and without XON/XOFF, at 7
#: and 8 data bits, over exec: and pty:; a CDT of 50 ms, so that a process scheduled late on a
#: loaded machine does not cut its own frames
CORRECT = {
    "cdt-none-8-exec": (dict(end_criterion="cdt", character_delay_ms=50), "exec"),
    "ec-xon-8-exec": (dict(end_criterion="end_chars", end_chars=[0x03], character_delay_ms=50,
                           flow_control="xon_xoff", xon_wait_ms=1000), "exec"),
    "ec2-append-7-pty": (dict(end_criterion="end_chars", end_chars=[0x0D, 0x0A], send_variant="len_append_end",
                              character_delay_ms=50, data_bits=7), "pty"),
    "fl-xon-7-exec": (dict(end_criterion="fixed_length", fixed_length=8, character_delay_ms=50, data_bits=7,
                           flow_control="xon_xoff", xon_wait_ms=1000, buffer_frames=4), "exec"),
}


@pytest.mark.realtime
@pytest.mark.long
@pytest.mark.parametrize("name", sorted(CORRECT))
def test_independent_correct_station_passes_the_suite(tmp_path, name):
    settings, scheme = CORRECT[name]
    p, data = run(tmp_path, settings, scheme)
    bad = {c["id"]: c["message"][:300] for c in data["cases"] if c["verdict"] in ("fail", "error", "xpass")}
    assert p.returncode == 0 and not bad, bad
    ran = [c for c in data["cases"] if c["verdict"] != "unsupported"]
    # the suite adapts to the profile: its own cases run, except those needing a send job
    # (the interface has no way to start one) or modem lines
    assert len(ran) >= 15, len(ran)


#: each broken variant of the independent station, the profile settings its rule needs
#: (anything else as the issue's profile) and the cases that should catch it
BROKEN = {
    "no-startup-xon": (dict(flow_control="xon_xoff", xon_wait_ms=1000), ["SUITE.ASCII.FC.*"]),
    "xoff-late": (dict(flow_control="xon_xoff", xon_wait_ms=1000, buffer_frames=2), ["SUITE.ASCII.FC.*"]),
    "no-xon-after-read": (dict(flow_control="xon_xoff", xon_wait_ms=1000, buffer_frames=2), ["SUITE.ASCII.FC.*"]),
    "xoff-ignored": (dict(flow_control="xon_xoff", xon_wait_ms=1000), ["SUITE.ASCII.FC.*"]),
    "no-xon-wait-timeout": (dict(flow_control="xon_xoff", xon_wait_ms=1000), ["SUITE.ASCII.FC.*"]),
    "cdt-from-first-char": (dict(end_criterion="cdt", character_delay_ms=50), ["SUITE.ASCII.CDT.*"]),
    "keep-fragment-on-cdt": (dict(), ["SUITE.ASCII.EC.*"]),
    "fragment-delivered": (dict(), ["SUITE.ASCII.EC.*"]),
    "single-end-char-suffices": (dict(end_chars=[0x0D, 0x0A]), ["SUITE.ASCII.EC2.*", "SUITE.ASCII.EC.*"]),
    "fixed-length-plus-one": (dict(end_criterion="fixed_length", fixed_length=8), ["SUITE.ASCII.FL.*"]),
    "echo-drops-end-char": (dict(), ["SUITE.ASCII.EC.*"]),
    "parity-frame-stored": (dict(end_criterion="cdt", character_delay_ms=50), ["SUITE.ASCII.CDT.*"]),
    "break-ignored": (dict(), ["SUITE.ASCII.LINE.*"]),
    "overwrite-despite-prevent": (dict(buffer_frames=2), ["SUITE.ASCII.BUF.*"]),
    "echo-newest-first": (dict(), ["SUITE.ASCII.BUF.*"]),
    "no-send-pause": (dict(end_criterion="cdt", character_delay_ms=50), ["SUITE.ASCII.TX.*"]),
    "variant-c-no-append": (dict(send_variant="len_append_end"), ["SUITE.ASCII.TX.*", "SUITE.ASCII.EC.*"]),
}


def independent_variants() -> list[str]:
    out = subprocess.run([PY, str(INDEPENDENT), "--list-breaks"], capture_output=True, text=True).stdout
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def test_every_independent_variant_has_a_profile():
    assert sorted(independent_variants()) == sorted(BROKEN)


@pytest.mark.realtime
@pytest.mark.long
@pytest.mark.parametrize("variant", sorted(BROKEN))
def test_independent_broken_station_fails(tmp_path, variant):
    settings, select = BROKEN[variant]
    p, data = run(tmp_path, settings, "exec", variant, select, "--max-failures", "1")
    failed = [c["id"] for c in data["cases"] if c["verdict"] == "fail"]
    assert p.returncode == 1 and failed, [(c["id"], c["verdict"], c["message"][:200]) for c in data["cases"]
                                          if c["verdict"] != "pass"]
