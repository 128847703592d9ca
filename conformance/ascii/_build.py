"""Small builders the ASCII case modules share: steps, payloads that keep clear of the
profile's control codes, what an echo IUT sends back, and the case itself."""

from __future__ import annotations

from ptpcert.model.hexbytes import parse_hex
from ptpcert.procedures.ascii.description import MODEM_LINES, echo_frames
from ptpcert.procedures.ascii.model import AsciiParams
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector
from ptpcert.status import lookup

from ._rules import rules_of

#: an idle line that ends a frame by any measure, and a gap that ends none (§4 of the
#: manual's CDT rules: keep stimuli clear of the edge); the "edge" pair is closer, for the
#: cases that check both sides of the CDT
IDLE, GAP = "3*CDT", "0.5*CDT"
UNDER, OVER = "0.6*CDT", "1.4*CDT"
#: the receive errors an ASCII driver may enter for a damaged or cut frame (Table 8-1):
#: which one is the manual's is derived (16#0806 CDT, 16#080A no room, 16#080C character
#: error, 16#0816 too long), so a case that needs "an error" accepts each of them
RX_ERRORS = "16#0806|16#080A|16#080C|16#0816"
#: how long a slow application (the slow_reader setup) may take to read a frame
SLOW = "10s"
SLOW_SETUP = ("slow_reader", {"ms": 5000})


def h(data) -> bytes:
    return parse_hex(data) if isinstance(data, str) else bytes(data)


def send(data, at: str = "0", gap: str = "0", note: str = "", mark: bool = False) -> Step:
    return Step("send", h(data), at=Expr(at), gap=Expr(gap), note=note, mark=mark)


def send_error(data, at: str = "0", note: str = "a character with a parity error") -> Step:
    return Step("send_error", h(data), at=Expr(at), note=note)


def brk(duration: str = "20*CHAR", at: str = "0", note: str = "BREAK") -> Step:
    return Step("break", duration=Expr(duration), at=Expr(at), note=note)


def expect(data, within: str, after: str = "0", *, max_gap: str | None = None, partial: bool = False,
           optional: bool = False, absent_grade: str = "pass", alternatives=(), alt_grade: str = "pass",
           since: str = "previous", resume: bool = False, note: str = "") -> Step:
    return Step("expect", h(data), after=Expr(after), within=Expr(within), max_gap=Expr(max_gap) if max_gap else None,
                partial=partial, optional=optional, absent_grade=absent_grade,
                alternatives=tuple(h(a) for a in alternatives), alt_grade=alt_grade, since=since,
                resume=resume, note=note)


def silence(duration: str, note: str = "") -> Step:
    return Step("silence", duration=Expr(duration), note=note)


def wait(duration: str, note: str = "", mark: bool = False) -> Step:
    return Step("wait", duration=Expr(duration), note=note, mark=mark)


# ------------------------------------------------------------------ payloads
def forbidden(p: AsciiParams) -> set[int]:
    """Codes that cannot be user data in this profile (§2.2.4 'code transparency'): the end
    characters and the XON/XOFF codes."""
    out: set[int] = set()
    if p.end_criterion == "end_chars":
        out |= set(p.end_chars)
    if p.flow_control == "xon_xoff":
        out |= {p.xon, p.xoff}
    return out


def safe_bytes(p: AsciiParams) -> list[int]:
    """Printable codes that are data in this profile, letters first."""
    bad = forbidden(p)
    order = list(range(0x41, 0x5B)) + list(range(0x30, 0x3A)) + list(range(0x61, 0x7B)) + list(range(0x20, 0x30))
    return [b for b in order if b not in bad]


def data(p: AsciiParams, n: int, start: int = 0) -> bytes:
    """``n`` data bytes for this profile, cycling through its safe codes from ``start``."""
    pool = safe_bytes(p)
    return bytes(pool[(start + i) % len(pool)] for i in range(n))


def transparent(p: AsciiParams) -> bytes:
    """Every code the frame can carry that is data in this profile (00..FF, or 00..7F with
    7 data bits), control codes included."""
    bad = forbidden(p)
    return bytes(b for b in range(p.code_max + 1) if b not in bad)


def frame_of(p: AsciiParams, n: int, start: int = 0) -> bytes:
    """A complete frame of ``n`` bytes in the profile's criterion: n data bytes (CDT), the
    data ending with the end character(s), or exactly the fixed length (``n`` ignored)."""
    if p.end_criterion == "fixed_length":
        return data(p, p.fixed_length, start)
    if p.end_criterion == "end_chars":
        return data(p, max(0, n - len(p.end_chars)), start) + p.end_sequence
    return data(p, n, start)


def echoes(p: AsciiParams, frames) -> list[bytes]:
    """What the tester receives when an echo IUT sends ``frames`` back (send variant applied,
    split by the tester's criterion)."""
    return echo_frames([h(f) for f in frames], p)


def no_flow(p: AsciiParams) -> bool:
    """The receiver never holds its partner (no XON/XOFF, no RTS/CTS): a frame of 1024 bytes
    or a full buffer can be reached without the partner being stopped."""
    return p.flow_control in ("none", "auto_v24")


def quiet_flow(p: AsciiParams) -> bool:
    """No XOFF can come between the bytes of a few echoed frames: without XON/XOFF, or with a
    buffer that holds several frames (an XON may come anywhere: reading Q15)."""
    return p.flow_control != "xon_xoff" or p.buffer_frames >= 4


# ------------------------------------------------------------------ cases
def codes(*items: str) -> tuple[frozenset[int], ...]:
    return tuple(frozenset(lookup(c).code for c in item.split("|")) for item in items)


def case(p: AsciiParams, id: str, title: str, reference: str, rule: str, group: str, role: str,
         steps: list[Step], *, status=(), optional=(), soft=(), delivered=(), echo_after=(),
         requires=("echo",), readings=(), start: str = "idle", notes: str = "", setup=None,
         timing_sensitive: bool = False, not_buildable: str = "", cites: bool = True) -> Vector:
    """A case of the suite: ``status`` must be raised (each an alternative "A|B"),
    ``optional`` may be, ``soft`` is what the model's reading of an open point raises (its
    absence grades the case informational). It cites the rules of :mod:`._rules`, unless
    it checks nothing (``not_buildable``, or ``cites=False``: a placeholder)."""
    opt = frozenset(c for item in optional for c in codes(item)[0])
    return Vector(
        id=f"SUITE.ASCII.{id}", title=title, reference=reference, rule=rule, group=group, iut_role=role,
        params=p, steps=tuple(steps),
        expected=Expected(StatusSpec(codes(*status), opt, codes(*soft)), StatusSpec(),
                          tuple(h(x) for x in delivered), (), tuple(h(x) for x in echo_after)),
        start=start, requires=frozenset(requires), readings=tuple(readings), provenance="",
        notes=notes, source=f"conformance/ascii/{group}", binds=(), procedure="ascii", setup=setup,
        timing_sensitive=timing_sensitive, not_buildable=not_buildable,
        rules=rules_of(id, p) if cites and not not_buildable else (),
    )


def receive_case(p: AsciiParams, id: str, title: str, reference: str, rule: str, steps: list[Step],
                 frames, *, echo: bool = True, **kw) -> Vector:
    """A receive case: the frames the IUT delivers, seen in what it sends back (received by
    the tester as a conforming partner after the steps; ``echo=False``: the steps expect
    them themselves)."""
    frames = [h(f) for f in frames]
    group = kw.pop("group", "end-criterion")
    return case(p, id, title, reference, rule, group, kw.pop("role", "receiver"), steps,
                delivered=frames, echo_after=echoes(p, frames) if echo else (), **kw)


def unbuilt_case(p: AsciiParams, id: str, title: str, reference: str, rule: str, group: str, why: str,
                 role: str = "receiver") -> Vector:
    """A case the profile leaves no room for: listed as unsupported with ``why``."""
    return case(p, id, title, reference, rule, group, role, [], not_buildable=why)


def modem_case(p: AsciiParams, id: str, title: str, reference: str, rule: str, readings=()) -> Vector:
    """A case about the RS 232C modem lines (RTS/CTS, automatic use of the V.24 signals):
    unsupported until a transport carries those lines."""
    return case(p, id, title, reference, rule, "flow-control", "both", [silence("CDT")],
                requires=(MODEM_LINES,), readings=readings, cites=False)


def with_echo(v: Vector, echo_after) -> Vector:
    """``v`` with these frames received back after its steps."""
    from dataclasses import replace
    return replace(v, expected=replace(v.expected, echo_after=tuple(h(x) for x in echo_after)))


def hold(p: AsciiParams) -> str:
    """How long the tester holds the IUT with XOFF in the cases that resume it: four CDTs,
    or half the wait time for XON where that is shorter."""
    return "4*CDT" if 4 * p.cdt < 0.5 * p.xon_wait else "0.5*XONWAIT"


def xon_in_time(p: AsciiParams, at: float = 0.0) -> bool:
    """The tester can lift an XOFF well inside the wait time for XON (Table 2-9): seeing that
    the IUT has stopped (the characters under way and a CDT of quiet), then ``hold(p)`` (or,
    with ``at`` > 0, ``at`` of the wait time), then the XON itself take at most three
    quarters of it (a quarter when ``at`` is given; the rest is the margin)."""
    seen = p.cdt + 4 * p.char_time
    if at:
        return seen <= (0.9 - at) * p.xon_wait
    held = 4 * p.cdt if 4 * p.cdt < 0.5 * p.xon_wait else 0.5 * p.xon_wait
    return seen + held <= 0.75 * p.xon_wait


#: the longest the tester may take to fill the buffer of an IUT whose application reads late
#: (the slow_reader setup should delay its reads by 5 to 10 s)
FILL_TIME = 2.5


def sending_time(p: AsciiParams, frames, gap_cdts: float) -> float:
    """Seconds the tester needs to send ``frames`` with ``gap_cdts`` CDTs between them."""
    return sum(len(f) for f in frames) * p.char_time + max(0, len(frames) - 1) * gap_cdts * p.cdt


def echo_steps(p: AsciiParams, frames, first: str = SLOW, late_last: bool = False) -> list[Step]:
    """Expect the echoes of ``frames`` one by one from an application that reads late: the
    first within ``first``, each further one soon after the one before (the frames waited in
    the buffer); ``late_last``: the last frame entered the buffer late (it may be read only
    a slow reader's delay after the others)."""
    from ptpcert.procedures.ascii.model import send_bytes

    out = []
    for i, f in enumerate(frames):
        within = first if i == 0 else SLOW if (late_last and i == len(frames) - 1) else "3*CDT + 20*CHAR"
        out.append(expect(send_bytes(h(f), p), within=within,
                          note="the slow application reads the oldest frame and sends it back" if i == 0
                          else f"frame {i + 1} sent back"))
    return out
