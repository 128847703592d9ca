"""Capture formats (ptpcert.capture): capture JSON, results transcripts, the hex log and
pcap with LINKTYPE_RTAC_SERIAL, their round trips, their readers' errors, the pcap layout
checked against the link type's definition and against tshark, and ``ptpcert capture
convert``.

The known exchange used throughout is built from the rules: a 3964R block (Fig. 2-6), the
tester's bytes being :func:`codec.frame` of a payload, the IUT's acknowledgements DLE, each
character one character time (11 bits at 9600 baud, 8E1) after the one it answers."""

from __future__ import annotations

import datetime as dt
import io
import json
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ptpcert import capture as C
from ptpcert.cli import main as cli_main
from ptpcert.model.events import Delivered
from ptpcert.model.line import PARITY_LETTERS, LineSettings
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.results import unpack_transcript

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
LINE = C.LineSettings(9600, 8, "even", 1)
CHAR = LINE.char_time
PAYLOAD = bytes([0x31, codec.DLE, 0x32])          # a DLE in the data is doubled on the line
START = dt.datetime(2026, 1, 31, 9, 0, 0, 123456, tzinfo=dt.timezone.utc)


def known_transcript() -> list[dict]:
    """A 3964R block from the tester, acknowledged by the IUT, then a BREAK and a character
    with a parity error from the tester; times in whole microseconds as the runner logs them."""
    out: list[dict] = [{"kind": "start", "dir": "note", "t": 0.0, "step": 0}]
    t = 0.010

    def put(who: str, b: int, kind: str = "byte") -> None:
        out.append({"t": round(t, 6), "dir": who, "kind": kind, "byte": b, "step": 1})

    whole = codec.frame(PAYLOAD, "3964R")
    put("tester", whole[0])                  # STX
    t += CHAR
    put("iut", codec.DLE)                    # ready to receive
    for b in whole[1:]:                      # data (DLE doubled), DLE ETX, BCC
        t += CHAR
        put("tester", b)
    t += CHAR
    put("iut", codec.DLE)                    # block accepted
    t += 0.100
    out.append({"t": round(t, 6), "dir": "tester", "kind": "break", "duration": 0.05, "step": 2})
    t += 0.060
    put("tester", 0x41, "char_error")
    out.append({"kind": "window", "dir": "note", "step": 3, "t0": round(t, 6), "t1": round(t + 0.3, 6),
                "label": "no further bytes"})
    return out


def known_capture() -> C.Capture:
    return C.from_transcript(known_transcript(), line=LINE, start=START, notes=["the known exchange"])


# ------------------------------------------------------------------ the model and transcripts


def test_a_transcript_becomes_chunks_of_each_seat_with_every_byte_at_its_time():
    tr = known_transcript()
    cap = known_capture()
    wire = [e for e in tr if e["kind"] in ("byte", "char_error", "break")]
    # every byte was logged at its own instant: one chunk per transcript entry, in order
    assert [(c.t, c.seat) for c in cap.chunks] == [(e["t"], "a" if e["dir"] == "tester" else "b") for e in wire]
    assert cap.wire_bytes("a") == codec.frame(PAYLOAD, "3964R")
    assert cap.wire_bytes("b") == bytes([codec.DLE, codec.DLE])
    brk, err = cap.chunks[-2:]
    assert (brk.condition, brk.duration, brk.seat) == (C.Cond.BREAK, 0.05, "a")
    assert (err.condition, err.data, err.seat) == (C.Cond.PARITY, b"\x41", "a")
    assert cap.marks == [C.Mark(0.0, "the steps start")]
    assert cap.end == round(wire[-1]["t"] + 0.3, 6)   # the last window: how long the line was watched
    assert cap.seats == {"a": "tester", "b": "IUT"}


def test_bytes_logged_at_one_instant_form_one_chunk():
    tr = [{"t": 0.5, "dir": "tester", "kind": "byte", "byte": b} for b in codec.frame(b"AB", "3964R")]
    tr.insert(2, {"t": 0.5, "dir": "iut", "kind": "byte", "byte": codec.NAK})
    cap = C.from_transcript(tr)
    assert [(c.seat, c.data) for c in cap.chunks] == [
        ("a", codec.frame(b"AB", "3964R")[:2]), ("b", bytes([codec.NAK])), ("a", codec.frame(b"AB", "3964R")[2:])]


def test_line_events_drive_a_model_station_that_delivers_the_block():
    """What the analyze phase does with a capture: the station in seat b receives what seat a
    sent, at the capture's times, and delivers the payload the frame carried."""
    cap = known_capture()
    st_b = Station3964(Params3964(procedure="3964R", priority="low"), name="b")
    st_b.power_on(0.0)
    delivered, sent = [], []

    def until(t: float) -> None:
        while (d := st_b.next_deadline()) is not None and d < t:
            st_b.handle_timer(d)
            sent.extend(st_b.pop_output(d))

    events = cap.line_events("a")
    assert [k for _, _, k, _ in events] == ["bytes"] * len(codec.frame(PAYLOAD, "3964R")) + ["break", "invalid"]
    for t, seat, kind, value in events:
        if kind == "break":
            break
        until(t)
        st_b.line_event(t, kind, value)
        delivered += [e.payload for e in st_b.pop_events() if isinstance(e, Delivered)]
    until(cap.chunks[-2].t)
    delivered += [e.payload for e in st_b.pop_events() if isinstance(e, Delivered)]
    assert delivered == [PAYLOAD]
    # and what it sent back is what the IUT sent in the capture: DLE, DLE (after its start-up NAK)
    sent.extend(st_b.pop_output())
    assert bytes(b for _, b in sent) == bytes([codec.NAK]) + cap.wire_bytes("b")
    # a chunk's time is when its character was complete: the model's start plus a character time
    # (to the microsecond the formats keep)
    assert [start + CHAR for start, _ in sent[1:]] == pytest.approx([c.t for c in cap.chunks if c.seat == "b"],
                                                                    abs=1e-6)


def test_line_settings():
    # the capture's line settings are the model's (ptpcert.model.line), in the notation 9600 8E1
    assert C.LineSettings is LineSettings
    assert CHAR == pytest.approx(11 / 9600)
    assert str(LINE) == "9600 8E1" and C.parse_line("9600 8e1") == LINE == LineSettings.parse("9600 8E1")
    assert C.parse_line("- 7N2") == C.LineSettings(None, 7, "none", 2)
    assert str(C.LineSettings(None, 5, "space", 2)) == "- 5S2"
    assert C.LineSettings(None).char_time == 0.0     # no baud rate: no line timing
    for bad in ("9600", "9600 9E1", "fast 8E1", "9600 8X1"):
        with pytest.raises(C.CaptureError, match="9600 8E1"):
            C.parse_line(bad)
        with pytest.raises(ValueError, match="9600 8E1"):
            LineSettings.parse(bad)
    with pytest.raises(C.CaptureError, match="baud rate 0 is not a positive whole number"):
        C.parse_line("0 8E1")


def test_a_capture_json_that_omits_line_settings_takes_no_baud_rate_and_8N1():
    d = C.to_dict(C.Capture(line=LINE))
    assert d["line"] == {"baud_rate": 9600, "data_bits": 8, "parity": "even", "stop_bits": 1}
    d["line"] = {}
    assert C.from_dict(d).line == C.LineSettings(None, 8, "none", 1)
    d["line"] = {"baud_rate": 19200, "parity": "odd"}
    assert C.from_dict(d).line == C.LineSettings(19200, 8, "odd", 1)
    d["line"] = None
    assert C.from_dict(d).line is None


@pytest.mark.parametrize("line, msg", [
    ({"baud_rate": 9600.0}, "baud rate 9600.0 is not a positive whole number"),
    ({"baud_rate": True}, "baud rate True is not a positive whole number"),
    ({"data_bits": 9}, "data bits 9: 5, 6, 7 or 8"),
    ({"parity": "blue"}, "parity 'blue': one of none, odd, even, mark, space"),
    ({"stop_bits": 3}, "stop bits 3: 1 or 2"),
    ([9600, 8, "even", 1], "line settings must be an object"),
])
def test_a_capture_refuses_line_settings_no_uart_has(line, msg):
    d = C.to_dict(C.Capture())
    d["line"] = line
    with pytest.raises(C.CaptureError, match="^cap.json: " + re.escape(msg)):
        C.from_dict(d, "cap.json")
    if isinstance(line, dict):
        with pytest.raises(C.CaptureError, match=re.escape(msg)):
            C.Capture(line=C.LineSettings(**{**C.LINE_DEFAULTS, **line}))


@pytest.mark.parametrize("kw, msg", [
    (dict(t=-0.1, seat="a", data=b"\x02"), "negative"),
    (dict(t=0.0, seat="c", data=b"\x02"), "neither a nor b"),
    (dict(t=0.0, seat="a"), "neither bytes nor a line condition"),
    (dict(t=0.0, seat="a", data=b"\x02", condition="break"), "carries no bytes"),
    (dict(t=0.0, seat="a", condition="hiccup"), "not a line condition"),
    (dict(t=0.0, seat="a", data=b"\x02", duration=0.1), "only a BREAK"),
    (dict(t=0.0, seat="a", condition="modem", lines=frozenset({"XYZ"})), "not a modem line"),
])
def test_a_chunk_refuses_what_it_cannot_be(kw, msg):
    with pytest.raises(C.CaptureError, match=msg):
        C.Chunk(**kw)


def test_a_capture_cannot_end_before_its_last_chunk():
    with pytest.raises(C.CaptureError, match="before its last chunk"):
        C.Capture([C.Chunk(1.0, "a", b"\x02")], end=0.5)


# ------------------------------------------------------------------ round trips


def _text_line():
    """One line of text without blanks at its ends (the hex log trims them)."""
    return st.text(alphabet="abcXYZ0189 _.,:;()#§/-", min_size=1, max_size=16).map(str.strip).filter(bool)


_times = st.integers(0, 2_000_000_000).map(lambda us: us / 1_000_000)
_seats = st.sampled_from(C.SEATS)
_chunks = st.one_of(
    st.builds(lambda t, s, d: C.Chunk(t, s, d), _times, _seats, st.binary(min_size=1, max_size=24)),
    st.builds(lambda t, s, d: C.Chunk(t, s, condition=C.Cond.BREAK, duration=d), _times, _seats,
              st.none() | st.integers(0, 4_000_000_000).map(lambda us: us / 1_000_000)),
    st.builds(lambda t, s, c, d: C.Chunk(t, s, d, c), _times, _seats,
              st.sampled_from([C.Cond.PARITY, C.Cond.FRAMING]), st.binary(max_size=3)),
    st.builds(lambda t, s, ls: C.Chunk(t, s, condition=C.Cond.MODEM, lines=frozenset(ls)), _times, _seats,
              st.sets(st.sampled_from(C.MODEM_LINES))),
    st.builds(lambda t, s, c: C.Chunk(t, s, condition=c), _times, _seats,
              st.sampled_from([C.Cond.OVERRUN, C.Cond.LOST])),
)
_lines = st.none() | st.builds(C.LineSettings, st.none() | st.sampled_from([300, 9600, 76800, 115200]),
                               st.sampled_from([5, 6, 7, 8]), st.sampled_from(list(PARITY_LETTERS)),
                               st.sampled_from([1, 2]))
_starts = st.none() | st.datetimes(dt.datetime(1971, 1, 1), dt.datetime(2100, 1, 1),
                                   timezones=st.just(dt.timezone.utc))


@st.composite
def captures(draw, seats=None):
    chunks = draw(st.lists(_chunks, max_size=25))
    last = max((c.t for c in chunks), default=0.0)
    end = draw(st.none() | st.integers(0, 10_000_000).map(lambda us: round(last + us / 1_000_000, 6)))
    names = seats or {"a": draw(_text_line()), "b": draw(_text_line())}
    return C.Capture(chunks, names, draw(_lines), draw(_starts), end,
                     draw(st.lists(_text_line(), max_size=3)),
                     draw(st.lists(st.builds(C.Mark, _times, _text_line()), max_size=3)))


def _wire(cap: C.Capture):
    """What pcap carries: the chunks, the start and the end."""
    return cap.chunks, cap.start, cap.end


@settings(max_examples=100, deadline=None)
@given(captures())
def test_capture_json_and_hex_log_carry_everything(cap):
    assert C.from_dict(json.loads(C.dumps(cap, "json"))) == cap
    assert C.read_hexlog(C.hexlog_text(cap)) == cap


@settings(max_examples=100, deadline=None)
@given(captures())
def test_pcap_carries_everything(cap):
    """The chunks, the start and the end in the link type's records; the line settings, seat
    names, notes, marks and timing in ptpcert's own (the start record's payload, marks as
    STATUS_CHANGE records that change no line)."""
    back = C.read_pcap(C.pcap_bytes(cap))
    assert _wire(back) == _wire(cap)
    assert back == cap


@settings(max_examples=60, deadline=None)
@given(captures(seats=dict(C.RUN_SEATS)))
def test_a_results_object_carries_everything_but_seat_names(cap):
    run = json.loads(C.dumps(cap, "results", case_id="X.1"))
    assert [c["id"] for c in run["cases"]] == ["X.1"]
    assert C.from_results(run) == cap
    assert C.from_results(run, case="X.1") == cap


@settings(max_examples=40, deadline=None)
@given(captures(seats=dict(C.RUN_SEATS)))
def test_conversions_between_all_formats_agree(cap):
    """results -> hex log -> pcap -> capture JSON -> results: what pcap carries survives the
    whole chain; the other fields survive every step that carries them."""
    r1 = C.from_results(json.loads(C.dumps(cap, "results")))
    h = C.read_hexlog(C.hexlog_text(r1))
    p = C.read_pcap(C.pcap_bytes(h))
    j = C.from_dict(json.loads(C.dumps(p, "json")))
    r2 = C.from_results(json.loads(C.dumps(j, "results")))
    assert h == cap
    assert _wire(r2) == _wire(cap)


def test_a_known_exchange_round_trips_through_every_format(tmp_path):
    cap = known_capture()
    for ext in (".json", ".hexlog", ".pcap"):
        C.save(cap, tmp_path / f"k{ext}")
    C.save(cap, tmp_path / "k-results.json", "results")
    assert C.load(tmp_path / "k.json") == cap
    assert C.load(tmp_path / "k.hexlog") == cap
    assert _wire(C.load(tmp_path / "k.pcap")) == _wire(cap)
    back = C.load(tmp_path / "k-results.json")
    assert (back.chunks, back.start, back.end, back.line, back.marks, back.notes) == \
        (cap.chunks, cap.start, cap.end, cap.line, cap.marks, cap.notes)
    # the transcript written into the results object is the one we started from, byte by byte
    tr = json.loads((tmp_path / "k-results.json").read_text())["cases"][0]["transcript"]
    key = lambda e: (e["t"], e["dir"], e["kind"], e.get("byte"), e.get("duration"))  # noqa: E731
    assert [key(e) for e in tr if e["kind"] in ("byte", "char_error", "break")] == \
        [key(e) for e in known_transcript() if e["kind"] in ("byte", "char_error", "break")]


# ------------------------------------------------------------------ results of a real run


@pytest.fixture(scope="module")
def sim_results(tmp_path_factory):
    """A results.json of ``ptpcert run`` against the model (sim:), with blocks both ways,
    BREAKs and character errors among its cases."""
    path = tmp_path_factory.mktemp("run") / "results.json"
    rc = cli_main(["run", "--iut", "sim:", "--profile", str(PROFILE), "--json", str(path),
                   "--select", "3964R.FIG2-6.*", "--select", "3964R.FIG2-7.*", "--select", "*BREAK*",
                   "--select", "*CHAR*", "--select", "SUITE.STARTUP.THEN-IDLE"])
    assert rc == 0
    return path


def test_each_case_of_a_run_becomes_a_capture_of_its_transcript(sim_results):
    run = json.loads(sim_results.read_text())
    assert len(run["cases"]) >= 5
    kinds = set()
    for case in run["cases"]:
        cap = C.load(sim_results, case=case["id"])
        tr = unpack_transcript(case["transcript"])   # results.json keeps bytes as runs
        for seat, who in (("a", "tester"), ("b", "iut")):
            sent = bytes(e["byte"] for e in sorted((e for e in tr if e["dir"] == who and e["kind"] == "byte"),
                                                   key=lambda e: e["t"]))
            assert cap.wire_bytes(seat) == sent, case["id"]
        n_cond = sum(1 for e in tr if e["kind"] in ("break", "char_error"))
        assert sum(1 for c in cap.chunks if c.condition) >= min(n_cond, 1), case["id"]
        kinds |= {c.condition for c in cap.chunks}
        assert cap.line == C.LineSettings(case["params"]["baud_rate"], case["params"]["data_bits"],
                                          case["params"]["parity"], case["params"]["stop_bits"])
        assert cap.notes[0].startswith(f"case {case['id']}")
    assert {None, C.Cond.BREAK, C.Cond.PARITY} <= kinds


def test_a_whole_run_is_one_capture_with_its_cases_one_after_the_other(sim_results):
    run = json.loads(sim_results.read_text())
    cap = C.load(sim_results)
    starts = [m for m in cap.marks if m.text.startswith("case ")]
    with_tr = [c for c in run["cases"] if c["transcript"]]
    assert [m.text.split()[1] for m in starts] == [c["id"] for c in with_tr]
    # sim: restarts its clock for every case, so the cases are laid end to end, a gap apart
    for (m1, m2) in zip(starts, starts[1:]):
        inside = [c.t for c in cap.chunks if m1.t <= c.t < m2.t]
        assert inside and m2.t >= max(inside) + C.CASE_GAP
    assert len(cap.chunks) == sum(len(C.load(sim_results, case=c["id"]).chunks) for c in with_tr)
    # it survives pcap
    assert _wire(C.read_pcap(C.pcap_bytes(cap))) == _wire(cap)



def test_a_run_capture_carries_its_cases_parameters(sim_results, tmp_path):
    """A mark "parameters {JSON}" at a case whose parameters differ from the previous case's
    (the first case's always); read alone, a case's parameters are a note. The analysis, which
    restarts at "case " marks, is not misled by them."""
    run = json.loads(sim_results.read_text())
    with_tr = [c for c in run["cases"] if c["transcript"]]
    with_tr[1]["params"] = {**with_tr[1]["params"], "procedure": "3964"}   # one case with other settings
    changed = tmp_path / "results.json"
    changed.write_text(json.dumps(run))
    cap = C.load(changed)
    said, expected = None, []
    for c in with_tr:
        if c["params"] != said:
            expected.append(c["params"])
            said = c["params"]
    marks = [m for m in cap.marks if m.text.startswith(C.PARAMS_TAG)]
    assert [json.loads(m.text[len(C.PARAMS_TAG):]) for m in marks] == expected
    assert len(expected) == 3       # the first case, the one changed, the one after it
    starts = {m.t for m in cap.marks if m.text.startswith("case ")}
    assert {m.t for m in marks} <= starts and not any(m.text.lower().startswith("case ") for m in marks)
    one = C.load(changed, case=with_tr[-1]["id"])
    assert C.params_text(with_tr[-1]["params"]) in one.notes
    # pcap carries the marks and the note
    assert [m.text for m in C.read_pcap(C.pcap_bytes(cap)).marks if m.text.startswith(C.PARAMS_TAG)] == \
        [m.text for m in marks]
    assert C.params_text(with_tr[-1]["params"]) in C.read_pcap(C.pcap_bytes(one)).notes


# ------------------------------------------------------------------ the hex log reader


def test_the_hex_log_is_what_the_module_documents():
    text = C.hexlog_text(known_capture())
    lines = text.splitlines()
    assert lines[0] == "# ptpcert-hexlog 1"
    assert "# start: 2026-01-31T09:00:00.123456+00:00" in lines and "# line: 9600 8E1" in lines
    assert "# a: tester" in lines and "# b: IUT" in lines and "# note: the known exchange" in lines
    assert "0.010000 a 02" in lines
    assert f"{round(0.010 + CHAR, 6):.6f} b 10" in lines
    assert any(x.endswith(" a BREAK 50.000ms") for x in lines)
    assert any(x.endswith(" a PARITY 41") for x in lines)
    assert "0.000000 - MARK the steps start" in lines
    assert lines[-1].endswith(" - END")


def test_the_hex_log_reader_is_tolerant():
    text = ("# a hand-written log; no version line\n# a: tester\n# b: CP341\n  # line: 9600 8e1\n\n"
            "10ms   Tester  02     # STX, and a comment after it\n"
            "0.0111\tcp341\t10\n"
            "0.0125 a 3110 10 32 1003\n"
            "0.5 b break 20ms\n0.6 A parity\n0.7 b modem cts dsr ring\n.8 - mark  hello  # there\n1s - end\n")
    cap = C.read_hexlog(text)
    assert cap.seats == {"a": "tester", "b": "CP341"} and cap.line == LINE
    assert [(c.t, c.seat, c.data, c.condition) for c in cap.chunks][:3] == [
        (0.01, "a", b"\x02", None), (0.0111, "b", b"\x10", None), (0.0125, "a", bytes.fromhex("3110103210 03"), None)]
    assert cap.chunks[3].duration == 0.02 and cap.chunks[4].condition is C.Cond.PARITY and not cap.chunks[4].data
    assert cap.chunks[5].lines == {"CTS", "DSR", "RI"}
    assert cap.marks == [C.Mark(0.8, "hello  # there")] and cap.end == 1.0


def test_pcap_records_out_of_time_order_are_sorted():
    base = 1_700_000_000_000_000
    cap = C.read_pcap(_foreign([(base + 500, 0x01, 0, 0, b"\x02"), (base, 0x02, 0, 0, b"\x15")]))
    assert cap.start == C.EPOCH + dt.timedelta(microseconds=base)
    assert [(c.t, c.seat, c.data) for c in cap.chunks] == [(0.0, "b", b"\x15"), (0.0005, "a", b"\x02")]


def test_hex_log_lines_may_come_out_of_order():
    cap = C.read_hexlog("0.2 b 10\n0.1 a 02\n0.2 a 03\n")
    assert [(c.t, c.seat) for c in cap.chunks] == [(0.1, "a"), (0.2, "b"), (0.2, "a")]


@pytest.mark.parametrize("line, msg", [
    ("0,5 a 02", "time '0,5' is not a number of seconds"),
    ("-1 a 02", "time '-1' is not a number of seconds"),
    ("0.5 x 02", "seat 'x' is not one of a, b, tester, IUT"),
    ("0.5 a 0", "'0' has an odd number of hex digits"),
    ("0.5 a 02 G1", "'G1' is neither hex bytes nor a condition"),
    ("0.5 a", "no bytes and no condition after the seat"),
    ("0.5", "expected a time, a seat and bytes or a condition"),
    ("0.5 a BREAK soon", "BREAK duration 'soon' is not a number of seconds"),
    ("0.5 a BREAK 1ms 2ms", "BREAK takes at most a duration"),
    ("0.5 a PARITY 4", "PARITY takes the character"),
    ("0.5 a MODEM CTS XON", "'XON' is not a modem line"),
    ("0.5 a LOST 02", "LOST takes no arguments"),
    ("0.5 - 02", "a line with seat '-' is '- MARK text' or '- END'"),
])
def test_a_wrong_hex_log_line_is_named_with_its_number_and_fault(line, msg):
    text = "# ptpcert-hexlog 1\n# a: tester\n# b: IUT\n0.1 a 02\n" + line + "\n"
    with pytest.raises(C.CaptureError) as exc:
        C.read_hexlog(text, "cap.log")
    assert str(exc.value).startswith("cap.log:5: ") and msg in str(exc.value), str(exc.value)
    assert exc.value.line == 5


def test_hex_log_header_errors_and_versions():
    with pytest.raises(C.CaptureError, match="cap.log:1: hex log version 2 is newer"):
        C.read_hexlog("# ptpcert-hexlog 2\n", "cap.log")
    with pytest.raises(C.CaptureError, match="cap.log:2: line settings '9600 8E' are not"):
        C.read_hexlog("# ptpcert-hexlog 1\n# line: 9600 8E\n", "cap.log")
    with pytest.raises(C.CaptureError, match="cap.log:1: start 'yesterday' is not an ISO 8601"):
        C.read_hexlog("# start: yesterday\n", "cap.log")
    with pytest.raises(C.CaptureError, match="cap.log: the recording cannot end at 0.100000 s"):
        C.read_hexlog("0.2 a 02\n0.1 - END\n", "cap.log")
    # after the first record, '# key: value' is a comment like any other
    assert C.read_hexlog("0.1 a 02\n# a: late\n").seats["a"] == "a"


# ------------------------------------------------------------------ the pcap layout


def _records(data: bytes):
    """Parse a little-endian microsecond pcap as the link type's definition lays it out."""
    magic, major, minor, zone, sigfigs, snaplen, network = struct.unpack_from("<IHHiIII", data)
    assert (magic, major, minor, zone, sigfigs, network) == (0xA1B2C3D4, 2, 4, 0, 0, 250)
    pos, out = 24, []
    while pos < len(data):
        sec, usec, incl, orig = struct.unpack_from("<IIII", data, pos)
        pos += 16
        assert incl == orig <= snaplen
        body = data[pos:pos + incl]
        pos += incl
        hsec, husec, event, ctrl, footer = struct.unpack_from(">IIBBH", body)
        assert (hsec, husec) == (sec, usec)         # the RTAC header repeats the record's time
        out.append((sec * 1_000_000 + usec, event, ctrl, footer, body[12:]))
    return out


def test_the_pcap_records_are_laid_out_as_the_link_type_defines():
    cap = known_capture()
    recs = _records(C.pcap_bytes(cap))
    base = (START - C.EPOCH) // dt.timedelta(microseconds=1)
    assert recs[0][:4] == (base, 0x00, 0, 0x0001)          # the start record: t = 0, nothing asserted
    assert recs[0][4].startswith(C.START_TAG + b"\nline: 9600 8E1\n")   # and the capture's header
    assert recs[-1] == (base + round(cap.end * 1e6), 0x06, 0, 0, b"")   # CAPTURE_COMPLETE at the end
    marks = [r for r in recs[1:-1] if r[1] == 0x00]
    assert [(r[0], r[4]) for r in marks] == [(base + round(m.t * 1e6), C.MARK_TAG + b"\n" + m.text.encode())
                                             for m in cap.marks]
    body = [r for r in recs[1:-1] if r[1] != 0x00]
    assert len(body) == len(cap.chunks)
    for (us, event, ctrl, footer, payload), c in zip(body, cap.chunks):
        assert us == base + round(c.t * 1e6)
        assert ctrl == 0
        if c.condition is None:
            assert (event, footer, payload) == ({"a": 0x01, "b": 0x02}[c.seat], 0, c.data)
        elif c.condition is C.Cond.BREAK:
            assert (event, footer, payload) == (0x09, 0x0001, struct.pack(">I", 50_000))
        else:
            assert (event, footer, payload) == (0x08, 0x0001, b"\x41")


def test_modem_lines_travel_in_the_control_line_byte():
    cap = C.Capture([C.Chunk(0.1, "a", condition=C.Cond.MODEM, lines=frozenset({"RTS", "DTR"})),
                     C.Chunk(0.2, "a", b"\x02"),
                     C.Chunk(0.3, "b", condition=C.Cond.MODEM, lines=frozenset({"CTS"})),
                     C.Chunk(0.4, "b", b"\x10")])
    recs = _records(C.pcap_bytes(cap))
    assert [(r[1], r[2], r[3]) for r in recs[1:]] == [
        (0x00, 0x08 | 0x10, 0x0001),       # seat a's RTS and DTR
        (0x01, 0x18, 0),                   # seat a's lines stay on its data record
        (0x00, 0x01, 0x0002),              # seat b's CTS, tagged b
        (0x02, 0x18, 0)]                   # the control-line byte is seat a's
    assert C.read_pcap(C.pcap_bytes(cap)).chunks == cap.chunks


def _foreign(records, order="<", magic=0xA1B2C3D4, network=250, nano=False):
    out = struct.pack(order + "IHHiIII", magic, 2, 4, 0, 0, 65535, network)
    for us, event, ctrl, footer, payload in records:
        sec, usec = divmod(us, 1_000_000)
        body = struct.pack(">IIBBH", sec, usec, event, ctrl, footer) + payload
        out += struct.pack(order + "IIII", sec, usec * 1000 if nano else usec, len(body), len(body)) + body
    return out


def test_pcap_files_of_other_recorders_are_read_as_the_recording_device_saw_them():
    base = 1_700_000_000_000_000
    recs = [(base, 0x02, 0x05, 0, b"\x02"),          # RX with CTS and DSR asserted: b sent STX
            (base + 1146, 0x03, 0x05, 0, b"\x10"),   # TX_END: a sent DLE
            (base + 2000, 0x08, 0x05, 0, b"\x41"),   # a parity error, footer 0: on the receive line (b)
            (base + 3000, 0x09, 0x05, 0, b""),       # a BREAK without a duration, also received
            (base + 4000, 0x0B, 0x05, 0, b""),       # an event type the link type does not define
            (base + 5000, 0x00, 0x04, 0, b"")]       # STATUS_CHANGE of the device's own UART: CTS drops
    for order, nano in (("<", False), (">", False), ("<", True)):
        magic = 0xA1B23C4D if nano else 0xA1B2C3D4
        cap = C.read_pcap(_foreign(recs, order, magic, nano=nano))
        assert cap.start == C.EPOCH + dt.timedelta(microseconds=base)
        assert [(c.t, c.seat, c.condition, c.data) for c in cap.chunks] == [
            (0.0, "a", C.Cond.MODEM, b""), (0.0, "b", None, b"\x02"), (0.001146, "a", None, b"\x10"),
            (0.002, "b", C.Cond.PARITY, b"\x41"), (0.003, "b", C.Cond.BREAK, b""), (0.005, "a", C.Cond.MODEM, b"")]
        assert cap.chunks[0].lines == {"CTS", "DSR"} and cap.chunks[-1].lines == {"DSR"}
        assert cap.chunks[4].duration is None
        assert cap.notes == ["record 5: event type 0x0B is unknown; skipped"]


@pytest.mark.parametrize("make, msg", [
    (lambda: b"\x0a\x0d\x0d\x0a" + bytes(40), "this is pcapng"),
    (lambda: bytes(10), "too short for a pcap file"),
    (lambda: b"GIF89a" + bytes(40), "not a pcap file (magic number 47494638)"),
    (lambda: _foreign([], network=1), "link type 1 is not LINKTYPE_RTAC_SERIAL (250)"),
    (lambda: _foreign([(0, 1, 0, 0, b"\x02")])[:-1], "record 1 says 13 bytes, but only 12 remain"),
    (lambda: _foreign([(0, 1, 0, 0, b"\x02")]) + b"\x00" * 5, "the file ends inside the header of record 2"),
    (lambda: _foreign([]) + struct.pack("<IIII", 0, 0, 4, 4) + bytes(4), "record 1 has 4 bytes, fewer than the 12"),
    (lambda: _foreign([]) + struct.pack("<IIII", 0, 0, 12, 20) + bytes(12), "record 1 was cut to 12 of 20"),
])
def test_a_wrong_pcap_file_is_named_with_its_fault(make, msg):
    with pytest.raises(C.CaptureError) as exc:
        C.read_pcap(make(), "x.pcap")
    assert str(exc.value).startswith("x.pcap: ") and msg in str(exc.value), str(exc.value)


def test_long_chunks_are_split_into_records_and_joined_again():
    big = bytes(range(256)) * 300                    # 76800 bytes: more than one record holds
    cap = C.Capture([C.Chunk(0.25, "b", big)])
    recs = _records(C.pcap_bytes(cap))
    assert [len(r[4]) for r in recs[1:]] == [C.MAX_PAYLOAD, len(big) - C.MAX_PAYLOAD]
    assert C.read_pcap(C.pcap_bytes(cap)).chunks == cap.chunks


# ------------------------------------------------------------------ tshark


def _tshark(*args: str) -> str:
    p = subprocess.run(["tshark", *args], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    return p.stdout


@pytest.mark.skipif(shutil.which("tshark") is None,
                    reason="tshark is not installed (Debian package 'tshark'; .ci/run installs it where apt can)")
def test_tshark_reads_a_ptpcert_pcap_with_its_bytes_and_directions(tmp_path):
    cap = known_capture()
    path = tmp_path / "known.pcap"
    C.save(cap, path)
    rows = [r.split("\t") for r in _tshark("-r", str(path), "-T", "fields", "-E", "separator=/t",
                                           "-e", "frame.time_epoch", "-e", "rtacser.eventtype",
                                           "-e", "rtacser.footer", "-e", "data.data").splitlines()]
    # the start record and CAPTURE_COMPLETE around them; the marks as STATUS_CHANGE records
    marks = [r for r in rows[1:-1] if r[1] == "0x00"]
    rows = [r for r in rows if r not in marks]
    assert len(marks) == len(cap.marks)
    assert len(rows) == len(cap.chunks) + 2
    base = START.timestamp()
    assert rows[0][1:3] == ["0x00", "0x0001"] and float(rows[0][0]) == pytest.approx(base, abs=1e-6)
    assert rows[-1][1] == "0x06" and float(rows[-1][0]) == pytest.approx(base + cap.end, abs=1e-6)
    for (t, event, footer, data), c in zip(rows[1:-1], cap.chunks):
        assert float(t) == pytest.approx(base + c.t, abs=1e-6)
        if c.condition is None:
            assert event == {"a": "0x01", "b": "0x02"}[c.seat] and bytes.fromhex(data) == c.data
        elif c.condition is C.Cond.BREAK:
            assert (event, footer) == ("0x09", "0x0001")
        else:
            assert (event, footer, bytes.fromhex(data)) == ("0x08", "0x0001", c.data)
    # the summary names the directions as the link type does
    summary = _tshark("-r", str(path))
    assert summary.count("DATA_TX_START") == sum(1 for c in cap.chunks if c.is_data and c.seat == "a")
    assert summary.count("DATA_RX_START") == sum(1 for c in cap.chunks if c.is_data and c.seat == "b")
    assert "SERIAL_BREAK_EVENT" in summary and "PARITY_ERROR" in summary and "RTAC Serial" in summary


# ------------------------------------------------------------------ ptpcert capture convert


def test_convert_turns_a_run_into_a_pcap_and_back(sim_results, tmp_path, capsys):
    case = json.loads(sim_results.read_text())["cases"][0]["id"]
    pcap, log, js = tmp_path / "r.pcap", tmp_path / "r.hexlog", tmp_path / "r.json"
    assert cli_main(["capture", "convert", str(sim_results), str(pcap), "--case", case]) == 0
    assert cli_main(["capture", "convert", str(pcap), str(log)]) == 0
    assert cli_main(["capture", "convert", str(log), str(js)]) == 0
    want = C.load(sim_results, case=case)
    assert _wire(C.load(js)) == _wire(want)
    out = capsys.readouterr().out
    assert f"{pcap}: {len(want.chunks)} chunks" in out
    capsys.readouterr()
    assert cli_main(["capture", "convert", str(js), "-"]) == 0
    assert capsys.readouterr().out == C.hexlog_text(C.load(js))


def test_convert_names_the_format_by_flag(tmp_path):
    src = tmp_path / "capture.data"
    src.write_text(C.hexlog_text(known_capture()))
    out = tmp_path / "out.bin"
    assert cli_main(["capture", "convert", str(src), str(out), "--from", "hexlog", "--to", "pcap"]) == 0
    assert _wire(C.read_pcap(out.read_bytes())) == _wire(known_capture())


@pytest.mark.parametrize("args, msg", [
    (["nothere.pcap", "x.hexlog"], "nothere.pcap: cannot be read"),
    (["{log}", "x.weird"], "cannot tell the format of 'x.weird'"),
    (["{bad}", "x.pcap"], "bad.hexlog:2: 'ZZ' is neither hex bytes"),
    (["{log}", "x.pcap", "--case", "A"], "a hex log file has no cases"),
    (["{results}", "x.pcap", "--case", "NO.SUCH.CASE"], "no case 'NO.SUCH.CASE'"),
])
def test_convert_errors_are_one_line_and_exit_2(tmp_path, sim_results, args, msg):
    log = tmp_path / "k.hexlog"
    log.write_text(C.hexlog_text(known_capture()))
    bad = tmp_path / "bad.hexlog"
    bad.write_text("0.1 a 02\n0.2 b ZZ\n")
    args = [a.format(log=log, bad=bad, results=sim_results) for a in args]
    p = subprocess.run([sys.executable, "-m", "ptpcert.cli", "capture", "convert", *args],
                       capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ptpcert capture: ") and msg in lines[0], p.stderr


def test_save_leaves_no_half_file_behind(tmp_path):
    target = tmp_path / "missing-dir" / "x.pcap"
    with pytest.raises(C.CaptureError, match="cannot be written"):
        C.save(known_capture(), target)
    assert not target.exists() and not (tmp_path / "missing-dir").exists()


def test_streaming_writers_write_as_the_recording_goes():
    """A recorder (the monitor) writes header first and chunks as they come: both writers
    give the same file as writing the finished capture at once."""
    cap = known_capture()
    text, binary = io.StringIO(), io.BytesIO()
    hw, pw = C.HexLogWriter(text, cap), C.PcapWriter(binary, cap.start, cap.timing, cap)
    assert text.getvalue().startswith("# ptpcert-hexlog 1") and len(binary.getvalue()) > 24 + 16 + 12
    for m in cap.marks:
        hw.mark(m)
        pw.mark(m)
    for c in cap.chunks:
        hw.chunk(c)
        pw.chunk(c)
    hw.close(cap.end)
    pw.close(cap.end)
    assert C.read_hexlog(text.getvalue()) == cap
    assert binary.getvalue() == C.pcap_bytes(cap)


def test_a_capture_written_as_results_is_drawn_by_the_report_command(tmp_path):
    res, html = tmp_path / "k-results.json", tmp_path / "k.html"
    C.save(known_capture(), res, "results")
    assert cli_main(["report", str(res), "--html", str(html)]) == 0
    svg = html.read_text()[html.read_text().find("<svg"):]
    # a capture names no procedure: its bytes are drawn in hex, the block whole with its end
    whole = " ".join(f"{b:02X}" for b in codec.frame(PAYLOAD, "3964R"))
    assert ">02</text>" in svg and f">{whole[3:]}</text>" in svg and "BREAK" in svg   # STX, the block, the condition
    # results that name their procedure are drawn with its names
    data = json.loads(res.read_text())
    res.write_text(json.dumps(dict(data, procedure="3964/3964R")))
    assert cli_main(["report", str(res), "--html", str(html)]) == 0
    svg = html.read_text()[html.read_text().find("<svg"):]
    assert "STX" in svg and "DLE ETX" in svg and "BREAK" in svg    # the block, its end, the condition
