"""The RK 512 fuzz kit's co-simulation (:class:`RkCoSim`): the model IUT behind a ``sim:``
transport in virtual time, driven exactly as the runner will replay the vector being
written, and the steps of that vector.

The examples (:mod:`.example`) write the tester's bytes through it and take the IUT's as a
conforming 3964(R) partner would: its blocks as ``receive`` steps (or, where the tester
answers them late or refuses them, as the link's single steps), its other bytes as
``expect`` steps, its quiet periods as ``silence``. Every stimulus keeps a margin from the
model's deadlines (:meth:`RkCoSim.clear`), so a real process cannot see the two in the
other order. The notes name the rule that makes a conforming IUT send a frame
(:func:`rule_of`).
"""

from __future__ import annotations

from ptpcert.fuzz.kit import ms
from ptpcert.procedures.p3964.model import codec as link
from ptpcert.scenario import ZERO, Expr, Step, Vector

from . import rules as R

#: the 3964(R) control characters the tester and the IUT exchange around RK 512 frames
STX, DLE, ETX, NAK = 0x02, 0x10, 0x03, 0x15


def rule_of(frame: bytes) -> str:
    """The note of a frame the IUT sends: the rule that makes a conforming IUT send it."""
    return R.frame_note(frame)


class RkCoSim:
    """The model IUT behind a ``sim:`` transport in virtual time, driven as the runner will
    drive the vector being written: every tester byte at the time the runner sends it, every
    IUT byte taken when the runner would take it."""

    def __init__(self, proc, profile, lines: list[str], readings, setup=None):
        from ptpcert.transport import sim_factory

        p = profile.params
        self.proc, self.p = proc, p
        self.char = p.char_time
        self.bcc = p.procedure == "3964R"
        self.lines = list(lines)
        stub = Vector(id="FUZZ.STUB", title="", reference="", rule="", group="regression", iut_role="both",
                      params=p, steps=(Step("wait", duration=Expr("0")),), procedure=proc.id,
                      extra={"requests": self.lines}, setup=setup)
        self.setup = setup
        self.tr = sim_factory(proc, {"app": proc.apps()[0]}, readings=readings)(stub, p)
        self.tr.open()
        self.station = self.tr.station
        self.edge_margin = 0.15 * min(p.cdt, p.adt) + 2 * self.char
        self.rx: list[tuple[float, int]] = []
        self.pos = 0
        self.steps: list[Step] = []
        self.start = self.tr.now()
        self.ref = self.start
        first = self.peek(self.start + 2.0)       # the runner's prologue takes the start-up NAK
        if first is not None and first[1] == NAK:
            self.pos += 1
            self.ref = max(self.tr.now(), first[0])
        self.codes: list[int] = []
        self.lines_out: list[str] = []

    @property
    def t(self) -> float:
        return self.tr.now() - self.start

    # -- the line -------------------------------------------------------------------------
    def _pump(self, until: float) -> None:
        while self.tr.now() < until:
            self.rx += self.tr.read(until)

    def peek(self, deadline: float):
        """The IUT's next byte not taken yet, as (time, byte), running the model up to
        ``deadline`` for it; None when the IUT sends nothing by then. Taking it (moving
        ``pos`` on) is the caller's."""
        while self.pos >= len(self.rx):
            if self.tr.now() >= deadline:
                return None
            self.rx += self.tr.read(deadline)
        return self.rx[self.pos]

    def write(self, data: bytes, at: float = 0.0, gap: float = 0.0) -> None:
        """The tester's ``data`` onto the line, its first byte ``at`` after the reference
        point and ``gap`` between the bytes, without a step in the vector (the caller
        records what it stands for); the reference point moves to the last byte."""
        start = self.ref + at
        t = start
        for k, b in enumerate(data):
            t = start + k * (self.char + gap) + self.char
            self._pump(t)
            self.tr.write(bytes([b]))
        self.ref = t

    def send(self, data: bytes, at: float = 0.0, at_expr: Expr | None = None, gap: float = 0.0, note: str = "") -> None:
        self.write(bytes(data), at, gap)
        self.steps.append(Step("send", bytes(data), at=at_expr or ms(at), gap=ms(gap), note=note))

    def window(self, d: float) -> Expr:
        """The window for an IUT reply that the model sent ``d`` after the reference point:
        the monitoring time, or more where the model itself took longer (a request after a
        script's wait)."""
        return Expr("TRES") if d <= 0.5 * self.p.t_res else Expr(f"{1000 * d:.3f}ms + ADT")

    # -- the IUT's blocks and bytes --------------------------------------------------------
    def read_body(self) -> bytes:
        """The IUT's block after the tester's DLE, up to DLE ETX (and the BCC)."""
        raw = bytearray()
        esc = bcc_next = False
        while True:
            nb = self.peek(self.ref + 60.0)
            if nb is None:
                raise RuntimeError("the model stopped inside its block")
            t, b = nb
            self.pos += 1
            raw.append(b)
            self.ref = t
            if bcc_next:
                return bytes(raw)
            if esc:
                esc = False
                if b == ETX:
                    if not self.bcc:
                        return bytes(raw)
                    bcc_next = True
            elif b == DLE:
                esc = True

    def take_block(self, dle_at: float = 0.0, refuse: int = 0) -> bytes | None:
        """The IUT has sent STX (not taken yet): receive its block as a conforming receiver
        (DLE, the block, DLE) and record it as a receive step. ``dle_at``: the tester's DLE
        that fraction of ADT after the STX; ``refuse``: the tester answers the first blocks
        with NAK instead of DLE (the IUT repeats them, §2.2.2 Fig. 2-10). Returns the frame,
        or None when the IUT gave it up."""
        attempt = 0
        while True:
            t_stx, _ = self.rx[self.pos]
            self.pos += 1
            d = t_stx - self.ref
            self.ref = t_stx
            self.write(bytes([DLE]), dle_at * self.p.adt)
            raw = self.read_body()
            frame = link.parse_body(raw, self.p.procedure)
            no = attempt < refuse
            self.write(bytes([NAK if no else DLE]))
            # no lower bound: the model's own pace is no rule (a faster IUT conforms), and the
            # STX came after the reference point (the tester's last byte), so no offset is
            # negative (what exported vectors promise)
            after = ZERO
            note = rule_of(frame)
            if dle_at or refuse:
                self.steps += [
                    Step("expect", bytes([STX]), after=after, within=self.window(d), note=R.note(R.SETUP_STX, "the IUT's STX")),
                    Step("send", bytes([DLE]), at=Expr(f"{dle_at}*ADT") if dle_at else Expr("0"),
                         note=f"DLE {dle_at} ADT later" if dle_at else "DLE"),
                    Step("expect", raw, within=Expr("CDT"), note=note),
                    Step("send", bytes([NAK if no else DLE]), note="NAK: the tester refuses the block" if no else "DLE")]
            else:
                self.steps.append(Step("receive", frame, after=after, within=self.window(d), note=note))
            if not no:
                return frame
            attempt += 1
            nb = self.peek(self.ref + 2 * self.p.adt + 10 * self.char)
            if nb is None:
                return None
            if nb[1] != STX:
                self.take_bytes()          # the sender gives up: its NAK (§2.2.2 Fig. 2-10)
                return None

    def take_bytes(self) -> bytes:
        """Bytes of the IUT that are not a block (a NAK of the link...): taken as they come,
        each within CDT of the previous, recorded as one expect step."""
        t0, b0 = self.rx[self.pos]
        d = t0 - self.ref
        got = bytearray([b0])
        self.pos += 1
        last = t0
        while True:
            nb = self.peek(last + self.p.cdt)
            if nb is None or nb[1] == STX:
                break
            got.append(nb[1])
            last = nb[0]
            self.pos += 1
        self.ref = last
        self.steps.append(Step("expect", bytes(got), after=ZERO,
                               within=Expr(f"{max(1000 * d, 0):.3f}ms + ADT"),
                               note=R.note(R.LINK_ANSWER, "the IUT's answer on the line")))
        return bytes(got)

    def quiet_for(self, duration: float, expr: Expr) -> bool:
        """The model stays quiet for ``duration`` after the reference point: recorded as a
        silence step. False (nothing recorded) when it sends something."""
        if self.peek(self.ref + duration) is not None:
            return False
        self._pump(self.ref + duration)
        self.ref += duration
        self.steps.append(Step("silence", duration=expr,
                               note=R.note(R.QUIET, "the IUT sends nothing")))
        return True

    def clear(self, at: float) -> float | None:
        """When a stimulus ``at`` after the reference point may start: never so close to one of
        the model's deadlines that a real process could see the two in either order. None
        when the IUT starts sending before: it must be taken first."""
        while True:
            start = self.ref + at
            if self.peek(start + self.char) is not None:
                return None
            d = self.station.next_deadline()
            if d is None or not (start - self.edge_margin < d < start + self.char + self.edge_margin):
                return at
            at = d + self.edge_margin - self.ref
