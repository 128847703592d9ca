"""Two ASCII model stations over model.link.Link, in virtual time: frames exchanged in each
end criterion, with and without XON/XOFF, RTS/CTS over a null-modem cable."""

import pytest

from ptpcert.driver import Endpoint, drive_station
from ptpcert.model.codes import Code
from ptpcert.model.events import Delivered, SendDone, SendFailed, Status
from ptpcert.model.link import CORRUPT, DELIVER, Link
from ptpcert.procedures.ascii.model import AsciiHost, AsciiParams, AsciiStation
from ptpcert.procedures.ascii.model.events import FrameDiscarded

CRITERIA = {
    "cdt": dict(end_criterion="cdt"),
    "end_chars": dict(end_criterion="end_chars", end_chars=(0x03,)),
    "end_chars2": dict(end_criterion="end_chars", end_chars=(0x0D, 0x0A), send_variant="len_append_end"),
    "fixed_length": dict(end_criterion="fixed_length", fixed_length=6),
}


def payloads(crit, n=5):
    """n different frames a user program would send in this criterion: without end
    characters in the data; with LEN = the fixed length; ending with the end character for
    the up-to-end variant."""
    out = []
    for i in range(n):
        data = bytes(0x41 + (i + k) % 26 for k in range(6))
        if crit == "end_chars":
            data = data[:5] + b"\x03"
        out.append(data)
    return out


def on_line(p: AsciiParams, data: bytes) -> bytes:
    """What the receiver gets for a job of ``data`` (the variant's rule)."""
    if p.end_criterion == "end_chars" and p.send_variant == "len_append_end":
        return data + p.end_sequence
    return data


def host(st, app, read_delay=0.0):
    return AsciiHost(st, app, read_delay=read_delay)


def make_link(params_a, params_b=None, *, echo=("b",), read_delay_b=0.0, hook=None):
    a = AsciiStation(params_a, name="a")
    b = AsciiStation(params_b or params_a, name="b")
    link = Link(a, b, hook=hook, echo=set(echo),
                host_factory=lambda st, app: host(st, app, read_delay_b if st.name == "b" else 0.0))
    link.power_on(0.0)
    link.run_until(0.01)
    return link, a, b


def delivered(link, st):
    return [e.payload for e in link.events_of(st, Delivered)]


def codes(link, st):
    return [e.code for e in link.events_of(st, Status)]


@pytest.mark.parametrize("flow", ["none", "xon_xoff"])
@pytest.mark.parametrize("crit", list(CRITERIA))
def test_frames_go_there_and_back(crit, flow):
    p = AsciiParams(flow_control=flow, **CRITERIA[crit])
    link, a, b = make_link(p)
    sent = payloads(crit)
    for data in sent:
        link.request(a, data)
    assert link.run_until_quiet(10.0)
    there = [on_line(p, d) for d in sent]
    assert delivered(link, b) == there
    # b echoes each frame as one job with LEN = the frame's length; with the appended end
    # characters the echo carries them twice, and the first pair already ends a frame
    # (§2.2.4: the end-character criterion is not code transparent)
    back = []
    for f in there:
        back += [f, p.end_sequence] if p.send_variant == "len_append_end" and crit == "end_chars2" else [f]
    assert delivered(link, a) == back
    assert [e.payload for e in link.events_of(a, SendDone)] == sent
    assert codes(link, a) == codes(link, b) == []
    if flow == "xon_xoff":
        assert [w.byte for w in link.wire if w.src == "a"][:1] == [0x11]


@pytest.mark.parametrize("crit", ["cdt", "end_chars", "fixed_length"])
def test_xon_xoff_holds_a_fast_sender_without_loss(crit):
    # b keeps at most two frames and reads one every 50 ms; a has ten frames to send at
    # once: b holds a with XOFF, lets it go with XON, and nothing is lost
    p = AsciiParams(flow_control="xon_xoff", buffer_frames=2, xon_wait_ms=2000, **CRITERIA[crit])
    link, a, b = make_link(p, echo=(), read_delay_b=0.05)
    link._hosts["b"].app = "none"
    sent = payloads(crit, 10)
    for data in sent:
        link.request(a, data)
    assert link.run_until_quiet(20.0)
    assert delivered(link, b) == sent
    assert codes(link, a) == codes(link, b) == []
    xoffs = [w for w in link.wire if w.src == "b" and w.byte == 0x13]
    assert xoffs, "b never held a"
    assert [e.payload for e in link.events_of(a, SendDone)] == sent


def test_xon_wait_shorter_than_the_hold_fails_a_job():
    p = AsciiParams(flow_control="xon_xoff", buffer_frames=1, xon_wait_ms=100,
                    end_criterion="end_chars", end_chars=(0x03,))
    link, a, b = make_link(p, echo=(), read_delay_b=0.5)
    link._hosts["b"].app = "none"
    for data in payloads("end_chars", 3):
        link.request(a, data)
    assert link.run_until_quiet(20.0)
    assert Code.XON_CTS_WAIT_EXPIRED in codes(link, a)
    failed = [e.payload for e in link.events_of(a, SendFailed)]
    done = [e.payload for e in link.events_of(a, SendDone)]
    assert failed and sorted(failed + done) == sorted(payloads("end_chars", 3))


def test_rts_cts_over_a_null_modem_cable():
    p = AsciiParams(flow_control="rts_cts", buffer_frames=1, xon_wait_ms=2000,
                    end_criterion="end_chars", end_chars=(0x03,))
    link, a, b = make_link(p, echo=(), read_delay_b=0.05)
    link._hosts["b"].app = "none"
    sent = payloads("end_chars", 4)
    for data in sent:
        link.request(a, data)
    assert link.run_until_quiet(20.0)
    assert delivered(link, b) == sent and codes(link, a) == codes(link, b) == []
    rts_b = [(v) for _, name, out, v in link.signals if name == "b" and out == "rts"]
    assert rts_b[0] == 1 and 0 in rts_b          # b dropped RTS to hold a, and raised it again
    assert link.wire and all(w.src == "a" for w in link.wire)   # no XON/XOFF characters


def test_a_corrupted_character_costs_one_frame():
    p = AsciiParams(end_criterion="end_chars", end_chars=(0x03,))
    sent = payloads("end_chars", 3)
    target = {"n": 0}

    def hook(w):
        if w.src == "a":
            target["n"] += 1
            if target["n"] == 8:   # the 2nd character of the 2nd frame
                return CORRUPT
        return DELIVER

    link, a, b = make_link(p, echo=(), hook=hook)
    link._hosts["b"].app = "none"
    for data in sent:
        link.request(a, data)
    assert link.run_until_quiet(10.0)
    assert delivered(link, b) == [sent[0], sent[2]]
    assert codes(link, b) == [Code.CHARACTER_ERROR]
    assert [e.reason for e in link.events_of(b, FrameDiscarded)] == ["character_error"]


def test_break_on_the_line_is_reported():
    p = AsciiParams()
    link, a, b = make_link(p, echo=())
    link.inject_break(b, at=0.02)
    link.run_until(0.1)
    assert codes(link, b) == [Code.LINE_BREAK]


def test_the_one_driver_loop_runs_an_ascii_station():
    # ptpcert.driver.drive_station, on a virtual line: the echo comes back paced at the
    # character time, after the frame's end character
    p = AsciiParams(end_criterion="end_chars", end_chars=(0x03,))

    class VirtualLine(Endpoint):
        def __init__(self):
            self.t = 0.0
            self.inputs = [(0.010 + i * p.char_time, "byte", b) for i, b in enumerate(b"AB\x03")]
            self.written = []

        def now(self):
            return self.t

        def poll(self, deadline):
            nxt = self.inputs[0][0] if self.inputs else float("inf")
            self.t = max(self.t, min(deadline, nxt))
            out = [x for x in self.inputs if x[0] <= self.t]
            self.inputs = [x for x in self.inputs if x[0] > self.t]
            return out

        def write(self, data):
            self.written.append((self.t, data))
            return self.t

    st = AsciiStation(p, name="iut")
    line = VirtualLine()
    st.power_on(0.0)
    drive_station(AsciiHost(st, "echo"), line, until=0.5)
    assert b"".join(d for _, d in line.written) == b"AB\x03"
    end_of_frame = 0.010 + 2 * p.char_time
    assert [t for t, _ in line.written] == pytest.approx([end_of_frame + (i + 1) * p.char_time for i in range(3)])
