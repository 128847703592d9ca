"""The RK 512 procedure's parts outside the suite: the request script per case and the
command it goes into, the RESULT/FETCHED judge, the frames of a transcript, the macro
steps, ``ptpcert iut --procedure RK512`` and ``ptpcert status`` for RK 512 codes."""

import subprocess
from pathlib import Path

import pytest

from ptpcert.registry import by_id, by_name
from ptpcert.scenario import Step, Vector, expand, vector_from_dict

from rk512_profiles import PY, ROOT, rk_profile
from rk512_rules import body, header, response

RK = by_id("rk512")


def _vector(**extra):
    return Vector(id="T", title="t", reference="§2.2.3", rule="r.", group="active-command", iut_role="sender",
                  params=rk_profile().params, steps=(Step("wait", b""),), procedure="rk512", extra=extra)


def test_the_procedure_is_registered_under_its_profile_name():
    assert by_name("RK512") is RK and RK.tables == ("rk512",) and "TRES" in RK.time_names
    assert RK.setups == ("cpu_stop", "flag_set") and RK.send_triggers == ("none",)
    assert "AMB-01" in RK.readings and "AMB-37" in RK.readings


def test_the_request_script_is_written_per_case_and_put_for_requests(tmp_path):
    v = _vector(requests=["send DB10:DW0:LEN=2:DATA=0102", "wait 100"])
    cmd = RK.command("my-iut --script {requests} --x", v, {}, str(tmp_path))
    path = cmd.split()[2]
    assert Path(path).read_text() == "send DB10:DW0:LEN=2:DATA=0102\nwait 100\n"
    # a case without requests gets the one empty script, the command every such case shares
    empty = RK.command("my-iut --script {requests}", _vector(), {}, str(tmp_path))
    assert empty == RK.command("my-iut --script {requests}", None, {}, str(tmp_path))
    assert Path(empty.split()[2]).read_text() == ""
    # a set-up's words are appended with its arguments
    from dataclasses import replace
    flag = replace(_vector(), setup=("flag_set", {"flag": "12.3", "reset_ms": 500}))
    assert RK.command("iut {requests}", flag, {"flag_set": "--cf-set {flag}@{reset_ms}"},
                      str(tmp_path)).endswith("--cf-set 12.3@500")
    assert RK.command("iut {requests}", flag, {}, str(tmp_path)) is None
    # an IUT that acts from its start is not started ahead of its case
    assert not RK.start_ahead(v) and not RK.start_ahead(flag) and RK.start_ahead(_vector())


@pytest.mark.parametrize("want,got,ok", [
    (["RESULT send:DB1:DW0:LEN=2 OK"], ["STATUS 16#0701", "RESULT send:DB1:DW0:LEN=2 OK"], True),
    (["RESULT send:DB1:DW0:LEN=2 OK"], ["RESULT send:DB1:DW0:LEN=2 STATUS 16#0A05"], False),
    (["RESULT x STATUS 16#0517 || RESULT x STATUS 16#1E41"], ["RESULT x STATUS 16#1e41"], True),
    (["FETCHED f:E:0:LEN=2 *", "RESULT f:E:0:LEN=2 OK"], ["FETCHED f:E:0:LEN=2 4142\nRESULT f:E:0:LEN=2 OK"], True),
    (["FETCHED f:E:0:LEN=2 4142"], ["FETCHED f:E:0:LEN=2 4143"], False),
    (["RESULT a OK", "RESULT b OK"], ["RESULT a OK"], False),
    ([], ["RESULT a OK"], False),
    ([], ["STATUS 16#0808", "something else"], True),
])
def test_result_lines_are_judged_in_order(want, got, ok):
    problems = RK.judge_reports(_vector(results=want), got)
    assert (problems == []) is ok, problems


def test_frames_are_decoded_in_each_direction_and_labelled():
    cmd = header("E", "D", 10, 0, 3)
    rsp = response(0, data=bytes([0x10, 0x20, 0x30, 0x40, 0x50, 0x60]))
    log, t = [], 0.0

    def put(d, data):
        nonlocal t
        for b in data:
            t += 0.001
            log.append({"t": t, "dir": d, "kind": "byte", "byte": b})
    put("tester", b"\x02"); put("iut", b"\x10"); put("tester", body(cmd)); put("iut", b"\x10")
    put("iut", b"\x02"); put("tester", b"\x10"); put("iut", body(rsp)[:-1] + bytes([body(rsp)[-1] ^ 1]))
    put("tester", b"\x15")
    frames = RK.describe_frames(log, rk_profile().params)
    assert [f["dir"] for f in frames] == ["tester", "iut"]
    assert frames[0]["label"] == "FETCH DB10 DW0 6 bytes, accepted (DLE)"
    assert frames[1]["label"].startswith("response REATEL 00 + 6 data bytes (BCC wrong)")
    assert frames[1]["label"].endswith("refused (NAK)") and frames[1]["frame"].startswith("00 00 00 00 10 20")
    assert frames[0]["t0"] < frames[0]["t1"] < frames[1]["t0"]


def test_the_macro_steps_expand_to_the_3964r_exchange():
    raw = {"id": "X", "procedure": "RK512", "title": "t", "reference": "§2.2.3", "rule": "r.", "group": "passive-send",
           "iut_role": "receiver", "params": {"link": "3964R"},
           "steps": [{"prime": "00 00 45 44 0A 00 00 03 FF 1F", "at": "ADT"},
                     {"receive": "00 00 00 10", "within": "TRES", "optional": True, "absent_grade": "informational"}]}
    steps = expand(vector_from_dict(raw))
    assert [(s.kind, s.data.hex()) for s in steps] == [
        ("send", "02"), ("expect", "10"), ("send", body(header("E", "D", 10, 0, 3)).hex()), ("expect", "10"),
        ("expect", "02"), ("send", "10"), ("expect", body(response(0x10)).hex()), ("send", "10")]
    assert str(steps[0].at) == "ADT" and str(steps[4].within) == "TRES"
    assert steps[4].optional and steps[4].skip == 3 and steps[4].absent_grade == "informational"
    # the macro steps round-trip through the file format
    from ptpcert.scenario import dump_vector, load_vector_text
    v = vector_from_dict(raw)
    assert load_vector_text(dump_vector(v), "x").steps == v.steps


def _iut(*args, stdin=b""):
    return subprocess.run([PY, "-m", "ptpcert.cli", "iut", "--procedure", "RK512", *args], cwd=ROOT, input=stdin,
                          capture_output=True, timeout=60)


def test_the_reference_iut_refuses_a_bad_script_or_flag(tmp_path):
    bad = tmp_path / "s.txt"
    bad.write_text("send DB10:DW0:LEN=2\nfetch Q:1:LEN=2\n")
    p = _iut("--requests", str(bad))
    assert p.returncode == 2 and b"line 2" in p.stderr
    p = _iut("--requests", str(tmp_path / "missing.txt"))
    assert p.returncode == 2 and b"--requests" in p.stderr
    p = _iut("--cf-set", "12.9@100")
    assert p.returncode == 2 and b"bit number" in p.stderr


def test_the_reference_iut_reports_request_results_on_stderr(tmp_path):
    # a request that cannot go out (LEN 0) is reported at once; then the line ends (EOF)
    s = tmp_path / "s.txt"
    s.write_text("fetch DB10:DW0:LEN=0\n")
    p = _iut("--baud", "0", "--requests", str(s))
    assert p.returncode == 0
    assert p.stdout[:1] == b"\x15"          # the link's start-up NAK
    lines = p.stderr.decode().splitlines()
    assert lines == ["STATUS 16#1E41", "RESULT fetch:DB10:DW0:LEN=0 STATUS 16#1E41"]


def _status(*args):
    return subprocess.run([PY, "-m", "ptpcert.cli", "status", *args], cwd=ROOT, capture_output=True, text=True)


def test_status_maps_reatel_both_ways():
    p = _status("--reatel", "34")
    assert p.returncode == 0
    assert "16#090C" in p.stdout and all(c in p.stdout for c in ("16#0608", "16#060B", "16#060C", "16#0611"))
    p = _status("--reatel", "0x42")
    assert "16#090E" in p.stdout and "not in Table 8-3" in p.stdout
    p = _status("16#0608", "16#090C", "16#0610")
    assert "answers with 34h" in p.stdout and "raised by 34h" in p.stdout and "none listed" in p.stdout
    p = _status("16#0A05", "16#051A")
    assert p.returncode == 0 and "monitoring time" in p.stdout and "REATEL" not in p.stdout
    assert _status("--reatel", "1FF").returncode == 2
