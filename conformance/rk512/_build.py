"""Builders the RK 512 case modules share: frames from the rules of §2.2.3 (Tables 2-1,
2-2), the tester's requests and answers as macro steps over the 3964(R) link, the memory
pattern of the interface, and the case itself."""

from __future__ import annotations

from dataclasses import dataclass

from ptpcert.procedures.p3964.model import codec as link
from ptpcert.procedures.rk512.model import Rk512Params
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector
from ptpcert.status import lookup

from ._rules import rules_of

STX, DLE, ETX, NAK = 0x02, 0x10, 0x03, 0x15
CHUNK = 128                       # data bytes per frame but the last (§2.2.3, Figs. 2-14, 2-16)
SEND_DB, SEND_DX, FETCH = "A", "O", "E"   # byte 3 (Table 2-1)
WORD_TYPES = "DXTZ"               # length and address count words (Table 2-1; §6.3.2)
#: the memory pattern of the interface: the first byte of each area (DB/DX add their number)
BASE = {"E": 0x40, "A": 0xC0, "T": 0x20, "Z": 0x60}


# -- frames (Tables 2-1, 2-2) ------------------------------------------------------------------
def header(cmd: str, typ: str, b5: int, b6: int, length: int, b9: int = 0xFF, b10: int = 0x1F,
           b1: int = 0x00, b2: int = 0x00) -> bytes:
    """A first command frame's ten bytes: frame id, 00h, command letter, data type, bytes
    5/6, the length (words for D, X, T, Z; bytes for E, A, M) big-endian, flag byte, CPU
    and flag bit (``FF 1F``: no flag, CPU 1 as in Fig. 2-13)."""
    return bytes([b1, b2, ord(cmd) if isinstance(cmd, str) else cmd, ord(typ) if isinstance(typ, str) else typ,
                  b5, b6, (length >> 8) & 0xFF, length & 0xFF, b9, b10])


def cont(cmd: str, typ: str, data: bytes = b"") -> bytes:
    """A continuation command frame: ``FF 00`` and bytes 3/4 of the first frame (Table 2-1)."""
    return bytes([0xFF, 0x00, ord(cmd) if isinstance(cmd, str) else cmd,
                  ord(typ) if isinstance(typ, str) else typ]) + bytes(data)


def resp(reatel: int = 0, first: bool = True, data: bytes = b"") -> bytes:
    """A response frame: ``00`` (``FF`` continuation) ``00 00`` REATEL, and FETCH data (Table 2-2)."""
    return bytes([0x00 if first else 0xFF, 0x00, 0x00, reatel]) + bytes(data)


def chunks(data: bytes) -> list[bytes]:
    """The data of each frame: 128 bytes in every frame but the last (§2.2.3)."""
    data = bytes(data)
    return [data[i:i + CHUNK] for i in range(0, len(data), CHUNK)] or [b""]


def send_frames(hdr: bytes, data: bytes) -> list[bytes]:
    """The frames of a SEND: the header with data bytes 1..128, then ``FF 00 b3 b4`` with
    the next 128 each (Figs. 2-13, 2-14)."""
    parts = chunks(data)
    return [hdr + parts[0]] + [bytes([0xFF, 0x00, hdr[2], hdr[3]]) + c for c in parts[1:]]


def wire_bytes(typ: str, length: int) -> int:
    """The bytes a request of ``length`` (header units) moves (Table 2-1)."""
    return 2 * length if typ in WORD_TYPES else length


def pattern(area: str, number: int, start: int, n: int) -> bytes:
    """The start contents of the interface's memory "pattern": DB n byte i = (n + i) & FFh,
    DX n byte i = (n + i + 80h) & FFh, E (40h + i), A (C0h + i), T (20h + i), Z (60h + i),
    M all 00h."""
    if area == "D":
        base = number
    elif area == "X":
        base = number + 0x80
    elif area == "M":
        return bytes(n)
    else:
        base = BASE[area]
    return bytes((base + start + i) & 0xFF for i in range(n))


def seq_data(n: int, seed: int = 0x10) -> bytes:
    """Test data: byte i = (seed + 7 i) & FFh (the script default of the interface, so the
    first byte is a DLE)."""
    return bytes((seed + 7 * i) & 0xFF for i in range(n))


# -- steps ------------------------------------------------------------------------------------
def h(data) -> bytes:
    return bytes.fromhex(data.replace("|", " ")) if isinstance(data, str) else bytes(data)


def send(data, at: str = "0", gap: str = "0", note: str = "") -> Step:
    return Step("send", h(data), at=Expr(at), gap=Expr(gap), note=note)


def expect(data, within: str = "ADT", after: str = "0", *, max_gap: str | None = None, partial: bool = False,
           optional: bool = False, absent_grade: str = "pass", alternatives=(), alt_grade: str = "pass",
           since: str = "previous", note: str = "") -> Step:
    return Step("expect", h(data), after=Expr(after), within=Expr(within), max_gap=Expr(max_gap) if max_gap else None,
                partial=partial, optional=optional, absent_grade=absent_grade,
                alternatives=tuple(h(a) for a in alternatives), alt_grade=alt_grade, since=since, note=note)


def silence(duration: str, note: str = "") -> Step:
    return Step("silence", duration=Expr(duration), note=note)


def wait(duration: str, note: str = "") -> Step:
    return Step("wait", duration=Expr(duration), note=note)


def prime(frame, at: str = "0", note: str = "") -> Step:
    """The tester sends ``frame`` as a conforming 3964(R) sender (STX, DLE, block, DLE)."""
    return Step("prime", h(frame), at=Expr(at), note=note)


def receive(frame, within: str = "TRES", after: str = "0", *, alternatives=(), alt_grade: str = "pass",
            optional: bool = False, absent_grade: str = "pass", since: str = "previous", note: str = "",
            or_end: int | None = None) -> Step:
    """The IUT sends ``frame`` (or one of ``alternatives``), its STX within ``within``; the
    tester receives it as a conforming 3964(R) receiver. ``or_end``: where an alternative
    came, the case ends after this many further steps."""
    return Step("receive", h(frame), after=Expr(after), within=Expr(within),
                alternatives=tuple(h(a) for a in alternatives), alt_grade=alt_grade, optional=optional,
                absent_grade=absent_grade, since=since, note=note, or_end=or_end)


def tester_send(hdr: bytes, data: bytes, note: str = "") -> list[Step]:
    """The tester SENDs: each frame, then the IUT's (continuation) response 00h, no data."""
    out = []
    for k, f in enumerate(send_frames(hdr, data)):
        out.append(prime(f, note=note if k == 0 else ""))
        out.append(receive(resp(0, first=k == 0)))
    return out


def line_chars(p: Rk512Params, *frames: bytes) -> int:
    """The characters ``frames`` put on the line as blocks: STX, the receiver's DLE, the
    block (DLEs doubled, DLE ETX, BCC), the receiver's DLE (§2.2.2)."""
    return sum(len(link.frame(f, p.procedure)) + 2 for f in frames)


def under_tres(p: Rk512Params, frac: float, *frames: bytes) -> str:
    """A pause of ``frac`` of what the IUT's shortest T_RES (TRES_MIN) leaves once ``frames``
    have crossed the line: held that long before them, they still arrive within T_RES at
    any baud rate (§2.2.3 Figs. 2-18, 2-19)."""
    return f"{frac}*(TRES_MIN - {line_chars(p, *frames)}*CHAR)"


def unprompted(p: Rk512Params, frame: bytes) -> str:
    """How long the tester watches the IUT send nothing unprompted before ``frame``: 2 ADT,
    or less where that and ``frame`` would not fit the IUT's T_RES."""
    if 2 * p.adt + line_chars(p, frame) * p.char_time <= 0.8 * p.t_res_min:
        return "2*ADT"
    return under_tres(p, 0.5, frame)


def tester_fetch(hdr: bytes, data: bytes, pause: str | None = None) -> list[Step]:
    """The tester FETCHes: the command, the first response with data bytes 1..128, then a
    4-byte continuation FETCH per further chunk, each answered ``FF 00 00 00`` + chunk.
    ``pause``: the IUT stays silent that long before each continuation FETCH (it sends
    no chunk unprompted)."""
    out = []
    for k, c in enumerate(chunks(data)):
        if k and pause:
            out.append(silence(pause, note="the IUT waits for the continuation FETCH: no chunk unprompted"))
        out.append(prime(hdr if k == 0 else cont(hdr[2], hdr[3])))
        out.append(receive(resp(0, first=k == 0, data=c)))
    return out


def iut_request(frames: list[bytes], responses: list[bytes], first_within: str = "STARTUP") -> list[Step]:
    """The IUT's request on the wire: each of its command frames, answered by the tester."""
    out = []
    for k, (f, r) in enumerate(zip(frames, responses)):
        out.append(receive(f, within=first_within if k == 0 else "TRES",
                           note="the IUT's request" if k == 0 else ""))
        out.append(prime(r))
    return out


# -- outcomes ---------------------------------------------------------------------------------
def status(required=(), optional=()) -> StatusSpec:
    req = tuple(frozenset(lookup(c).code for c in item.split("|")) for item in required)
    return StatusSpec(req, frozenset(lookup(c).code for c in optional))


def label(line: str) -> str:
    """The label of a script line's request: ``send:SPEC`` or ``fetch:SPEC``."""
    op, _, spec = line.strip().partition(" ")
    return f"{op}:{spec.strip()}"


def ok(label: str) -> str:
    return f"RESULT {label} OK"


def failed(label: str, *codes: str) -> str:
    return " || ".join(f"RESULT {label} STATUS {c}" for c in codes)


def fetched(label: str, data: bytes | None) -> str:
    return f"FETCHED {label} *" if data is None else f"FETCHED {label} {bytes(data).hex().upper()}"


@dataclass(frozen=True)
class Ctx:
    """What the cases need to know of the IUT: its parameters and the areas they use. The
    pattern is read from DB ``db`` (never written by a case), SENDs go to DB ``db_w``;
    the same for DX."""

    p: Rk512Params
    db: int
    db_w: int
    dx: int | None
    dx_w: int | None

    @classmethod
    def of(cls, p: Rk512Params) -> "Ctx":
        lo, hi = p.db_range
        db = 10 if lo <= 10 <= hi - 1 else lo
        db_w = db + 1 if db + 1 <= hi else db
        dx = dx_w = None
        if p.dx_range:
            lo, hi = p.dx_range
            dx = 7 if lo <= 7 <= hi - 1 else lo
            dx_w = dx + 1 if dx + 1 <= hi else dx
        return cls(p, db, db_w, dx, dx_w)

    @property
    def pattern_known(self) -> bool:
        return self.p.memory == "pattern"

    @property
    def fw(self) -> int:
        """The data words of the small FETCH that header checks send with one field wrong:
        3 (6 bytes, as Example 3), or the whole DB where it is smaller, so that every other
        field of the frame is valid for the profile's memory."""
        return min(3, self.p.db_bytes // 2)

    @property
    def pause(self) -> str:
        """How long the tester keeps silent where it checks that the IUT sends nothing
        unprompted while it waits for the tester (its T_RES running): 2 ADT, or half the
        shortest T_RES it may have where that is shorter (a long ADT would outlast it)."""
        return "2*ADT" if 2 * self.p.adt <= 0.5 * self.p.t_res_min else "0.5*TRES_MIN"


def case(c: Ctx, id: str, title: str, reference: str, rule: str, group: str, role: str,
         steps: list[Step], *, iut=((), ()), requests=(), results=(), needs=None, setup=None,
         readings=(), provenance: str = "", notes: str = "", timing_sensitive: bool = False) -> Vector:
    extra: dict = {}
    if requests:
        extra["requests"] = list(requests)
    if requests or results:
        extra["results"] = list(results)
    if needs:
        extra["needs"] = dict(needs)
    return Vector(
        id=f"SUITE.RK512.{id}", title=title, reference=reference, rule=rule, group=group, iut_role=role,
        params=c.p, steps=tuple(steps), expected=Expected(status(*iut), StatusSpec()),
        readings=tuple(readings), provenance=provenance, notes=notes, source=f"conformance/rk512/{group}",
        binds=(), timing_sensitive=timing_sensitive, procedure="rk512", setup=setup, extra=extra,
        rules=rules_of(id, c.p.link),
    )
