"""Small builders the case modules share: steps, framed blocks, the common exchanges."""

from __future__ import annotations

from ptpcert.model import Params3964, codec
from ptpcert.scenario import Expected, Expr, Step, StatusSpec, Vector
from ptpcert.status import lookup

STX, DLE, ETX, NAK = b"\x02", b"\x10", b"\x03", b"\x15"


def h(data) -> bytes:
    return codec.parse_hex(data) if isinstance(data, str) else bytes(data)


def send(data, at: str = "0", gap: str = "0", note: str = "", mark: bool = False) -> Step:
    return Step("send", h(data), at=Expr(at), gap=Expr(gap), note=note, mark=mark)


def send_error(data, at: str = "0", note: str = "") -> Step:
    return Step("send_error", h(data), at=Expr(at), note=note)


def brk(duration: str = "20*CHAR", at: str = "0", note: str = "BREAK") -> Step:
    return Step("break", duration=Expr(duration), at=Expr(at), note=note)


def expect(data, within: str = "ADT", after: str = "0", *, max_gap: str = "CDT", partial: bool = False,
           optional: bool = False, absent_grade: str = "pass", alternatives=(), alt_grade: str = "pass",
           since: str = "previous", note: str = "") -> Step:
    return Step("expect", h(data), after=Expr(after), within=Expr(within), max_gap=Expr(max_gap),
                partial=partial, optional=optional, absent_grade=absent_grade,
                alternatives=tuple(h(a) for a in alternatives), alt_grade=alt_grade, since=since, note=note)


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
              max_gap: str = "CDT") -> list[Step]:
    """The IUT sends ``payload`` (its echo) and the tester acknowledges it like a partner."""
    return [
        expect(STX, note="the IUT's STX"),
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
         setup=None) -> Vector:
    return Vector(
        id=f"SUITE.{id}", title=title, reference=reference, rule=rule, group=group, iut_role=role,
        params=p, steps=tuple(steps),
        expected=Expected(status(*iut), status(*tester), tuple(h(x) for x in delivered),
                          tuple(h(x) for x in sent), tuple(h(x) for x in echo_after)),
        start=start, requires=frozenset(requires), readings=tuple(readings), provenance=provenance,
        notes=notes, source=f"conformance/{group}", binds=(), tester_params=tester_params,
        timing_sensitive=timing_sensitive or group in ("timing", "conflict"), rules=tuple(rules),
        setup=setup,
    )


def long_payload(p: Params3964, byte: int = 0x41, seconds: float = 0.3) -> bytes:
    """A block long enough that the IUT is still sending it well after the tester's
    interruption reaches it: at least 64 bytes and about ``seconds`` of line time."""
    n = 64 if p.char_time == 0 else int(seconds / p.char_time)
    return bytes([byte]) * max(64, min(n, 1000))
