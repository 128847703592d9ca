"""Small builders the case modules share: steps, framed blocks, the common exchanges."""

from __future__ import annotations

from ptpcert.model.hexbytes import parse_hex
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector
from ptpcert.status import lookup

STX, DLE, ETX, NAK = b"\x02", b"\x10", b"\x03", b"\x15"

#: The window for what the IUT sends on its own initiative, with no partner timer running: a
#: retry STX, its final NAK, a deferred STX after a conflict, its echo's first STX. The manual
#: sets no guard time here (A8): any delay is conforming, so the window only bounds how long
#: the tester waits; T_BLOCK is how long a CP 341 receiver would still wait for a repetition.
RETRY = "ADT + BLOCK"
#: A payload for cases that are not about DLE or length: one rule per case (no DLE in the
#: data unless the case is about DLE, at most 64 bytes unless it is about length).
PLAIN = b"\x31\x32\x33"


def h(data) -> bytes:
    return parse_hex(data) if isinstance(data, str) else bytes(data)


def send(data, at: str = "0", gap: str = "0", note: str = "", mark: bool = False) -> Step:
    return Step("send", h(data), at=Expr(at), gap=Expr(gap), note=note, mark=mark)


def send_error(data, at: str = "0", note: str = "") -> Step:
    return Step("send_error", h(data), at=Expr(at), note=note)


def brk(duration: str = "20*CHAR", at: str = "0", note: str = "BREAK") -> Step:
    return Step("break", duration=Expr(duration), at=Expr(at), note=note)


def seven_bit(p: Params3964, data) -> bytes:
    """The payload as a character frame of ``p`` can carry it: with 7 data bits only 00..7F
    (Table 2-5), so the top bit is dropped."""
    data = h(data)
    return bytes(b & 0x7F for b in data) if p.data_bits == 7 else data


def plain_1024(p: Params3964) -> bytes:
    """1024 user bytes without a DLE (so the count is the same before and after doubling,
    A17) and within the frame's values."""
    values = [b for b in range(0x20, 0x80 if p.data_bits == 7 else 0x100) if b != 0x10]
    return bytes(values[i % len(values)] for i in range(1024))


def bcc_of(data) -> int:
    """The BCC a 3964R sender appends after the data bytes as sent (already doubled)."""
    return codec.bcc(h(data))


def expect(data, within: str = "ADT", after: str = "0", *, max_gap: str | None = None, partial: bool = False,
           optional: bool = False, absent_grade: str = "pass", alternatives=(), alt_grade: str = "pass",
           since: str = "previous", note: str = "") -> Step:
    return Step("expect", h(data), after=Expr(after), within=Expr(within), max_gap=Expr(max_gap) if max_gap else None,
                partial=partial, optional=optional, absent_grade=absent_grade,
                alternatives=tuple(h(a) for a in alternatives), alt_grade=alt_grade, since=since, note=note)


def maybe(data, grade: str, *, within: str, after: str = "0", since: str = "previous", note: str = "") -> Step:
    """The IUT may send ``data`` (graded ``grade``) or nothing (pass); anything else is left
    for the next step or the end of the case, which then fails it. (The step expects
    ``data`` twice in a row, which no IUT sends, and accepts ``data`` once as the alternative
    with the grade; absent, it passes.)"""
    d = h(data)
    return expect(d + d, within=within, after=after, optional=True, alternatives=[d], alt_grade=grade,
                  since=since, note=note)


def settle(window: str) -> Step:
    """After an optional step with the window ``window``: a wait long enough for the step's
    watching (its window, a character gap, the harness's tolerances) to be over, so that the
    next stimulus is timed from a point already passed (an optional reply that did not come
    leaves the reference point where it was)."""
    return Step("wait", duration=Expr(f"2*({window}) + CDT + 8*CHAR + 150ms"),
                note="the line settles after the optional reply's window")


def partner(duration: str, note: str) -> Step:
    """For at most ``duration`` the tester plays a conforming station (the case's tester
    parameters) and answers whatever the IUT sends, until both are at rest: for what the
    manual lets go either way (an echo that may or may not come, a job that may resume)."""
    return Step("partner", duration=Expr(duration), note=note)


def silence(duration: str, note: str = "") -> Step:
    return Step("silence", duration=Expr(duration), note=note)


def wait(duration: str, note: str = "") -> Step:
    return Step("wait", duration=Expr(duration), note=note)


def prime(payload, note: str = "") -> Step:
    return Step("prime", h(payload), note=note or "the tester hands this block to the IUT, which sends it back")


def body(payload, p: Params3964) -> bytes:
    return codec.body(h(payload), p.procedure)


def nak_after_cdt(note: str = "NAK once the line has been quiet for CDT", since: str = "previous") -> Step:
    """The IUT's NAK after a CDT timeout or quiet wait: not before CDT, at most CDT plus
    the one-character allowance and the NAK's own character time."""
    return expect(NAK, after="CDT", within="CDT + 2*CHAR", since=since, note=note)


def receive_block(payload, p: Params3964, *, gap: str = "0", first_at: str = "0", bcc_at: str = "0",
                  note: str = "") -> list[Step]:
    """The tester sends STX, gets DLE, sends the block, gets DLE: a block the IUT must accept."""
    b = body(payload, p)
    steps = [send(STX, note="STX"), expect(DLE, note="DLE: the IUT is ready to receive")]
    if p.has_bcc and bcc_at != "0":
        steps.append(send(b[:-1], at=first_at, gap=gap, note=note or "data, DLE ETX"))
        steps.append(send(b[-1:], at=bcc_at, note="BCC"))
    else:
        steps.append(send(b, at=first_at, gap=gap, note=note or "data, DLE ETX" + (", BCC" if p.has_bcc else "")))
    steps.append(expect(DLE, note="DLE: the block is accepted"))
    return steps


def echo_send(payload, p: Params3964, *, setup_reply_at: str = "0", release_reply_at: str = "0",
              max_gap: str | None = None) -> list[Step]:
    """The IUT sends ``payload`` (its echo) and the tester acknowledges it like a partner."""
    return [
        expect(STX, within=RETRY, note="the IUT's STX (no guard time is set: A8)"),
        send(DLE, at=setup_reply_at, note="DLE"),
        expect(body(payload, p), within="CDT", max_gap=max_gap,
               note="the IUT's block: its first character within the partner's CDT"),
        send(DLE, at=release_reply_at, note="DLE: the IUT's job is done"),
    ]


def codes(*items: str) -> tuple[frozenset[int], ...]:
    return tuple(frozenset(lookup(c).code for c in item.split("|")) for item in items)


def status(required=(), optional=()) -> StatusSpec:
    opt = frozenset(lookup(c).code for c in optional)
    return StatusSpec(codes(*required), opt)


def case(p: Params3964, id: str, title: str, reference: str, rule: str, group: str, role: str,
         steps: list[Step], *, iut=((), ()), tester=((), ()), delivered=(), sent=(), echo_after=(),
         requires=(), readings=(), start: str = "idle", provenance: str = "", notes: str = "",
         tester_params: Params3964 | None = None, timing_sensitive: bool = False, rules=(),
         setup=None, extra=None) -> Vector:
    return Vector(
        procedure="p3964", id=f"SUITE.{id}", title=title, reference=reference, rule=rule, group=group, iut_role=role,
        params=p, steps=tuple(steps),
        expected=Expected(status(*iut), status(*tester), tuple(h(x) for x in delivered),
                          tuple(h(x) for x in sent), tuple(h(x) for x in echo_after)),
        start=start, requires=frozenset(requires), readings=tuple(readings), provenance=provenance,
        notes=notes, source=f"conformance/{group}", binds=(), tester_params=tester_params,
        timing_sensitive=timing_sensitive or group in ("timing", "conflict"), rules=tuple(rules),
        setup=setup, extra=dict(extra or {}),
    )


def long_payload(p: Params3964, byte: int = 0x41) -> bytes:
    """A block for interrupting the IUT while it sends: 64 bytes, the most a case that is not
    about length uses, so that an IUT with a smaller agreed length can still run it; the tester
    interrupts after the first 10."""
    return bytes([byte]) * 64
