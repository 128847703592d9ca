"""One RK 512 fuzz example, the tester's side (:class:`RkExample`): the state of the
exchange (the tester's request, the IUT's, the command the tester owes an answer), taking
what the IUT sends (:meth:`~RkExample.react`), sending the tester's frames over the link
(:meth:`~RkExample.frame_out`), choosing the next action, bringing the exchange to rest and
writing the vector with its expected STATUS events and request results.

What the tester does in each role of the IUT is mixed in: :class:`~.passive.PassiveSide`
(the tester commands, the IUT serves) and :class:`~.active.ActiveSide` (the IUT requests,
the tester answers).
"""

from __future__ import annotations

from hypothesis import reject
from hypothesis import strategies as st

from ptpcert.fuzz.kit import ms, send_receive_codes
from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import codec as link
from ptpcert.procedures.rk512.model.codec import Kind, classify, describe
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector

from .active import ActiveSide
from .cosim import DLE, STX, RkCoSim
from .passive import PassiveSide
from .requests import OpenRequest

#: what an example may see raised besides what it requires (see :meth:`RkExample.vector`): every
#: send/receive event of RK 512 and of the link, the responder's class-06 events, the
#: informational ones
_LINK_CODES = send_receive_codes("RK 512") | send_receive_codes("3964(R)")
_CLASS06 = frozenset(range(0x0601, 0x0613))
INFORMATIONAL = frozenset({0x0701, 0x0801, 0x0702, 0x0815})


class RkExample(PassiveSide, ActiveSide):
    """The tester's side of one example: its own request, the IUT's, and what to do next.
    ``gen`` is the :class:`~.generator.RkGenerator` that draws it (its profile, and the
    commands the tester may send)."""

    def __init__(self, sim: RkCoSim, gen):
        self.sim, self.gen = sim, gen
        self.p = gen.p
        self.mine: OpenRequest | None = None     # the tester's request, waiting for its next frame
        self.awaiting = False                    # the tester's frame waits for its response
        self.theirs: OpenRequest | None = None   # the IUT's request
        self.owed: bytes | None = None           # the IUT's command the tester has not answered
        self.used_db: set[int] = set()
        self.commanded = False                   # the tester sent commands: the IUT was passive too
        self.used_dx: set[int] = set()
        self.fetched = False

    @property
    def t(self) -> float:
        return self.sim.t

    @property
    def steps(self):
        return self.sim.steps

    # -- taking what the IUT sends ----------------------------------------------------------
    def react(self, data=None, quiet: float | None = None) -> None:
        """Take everything the IUT sends until it has been quiet for a while: its blocks
        (responses to the tester, its own commands) and its link bytes."""
        sim = self.sim
        q = quiet if quiet is not None else 2 * self.p.adt + 10 * self.p.char_time
        while True:
            nb = sim.peek(sim.ref + q)
            if nb is None:
                sim.quiet_for(q, Expr(f"{1000 * q:.3f}ms") if quiet is not None else Expr("2*ADT + 10*CHAR"))
                return
            if nb[1] == STX:
                how = "dle" if data is None else data.draw(
                    st.sampled_from(["dle"] * 6 + ["slow-dle", "refuse-once", "refuse-all", "cross"]), label="answer STX")
                if how == "cross" and self.owed is None and self.gen.passive:
                    self.cross(data)
                    continue
                refuse = {"refuse-once": 1, "refuse-all": self.p.line.transmission_attempts}.get(how, 0)
                frame = sim.take_block(0.5 if how == "slow-dle" else 0.0, refuse)
                if frame is not None:
                    self.iut_frame(frame)
                elif self.theirs is not None and self.owed is None:
                    self.theirs = None       # its request ended with the link's failure
            else:
                sim.take_bytes()

    def iut_frame(self, frame: bytes) -> None:
        """Book a frame the IUT sent: a command or continuation is owed an answer (and a
        first command opens the IUT's request); a response settles the tester's frame and
        moves its request on, or ends it."""
        kind = classify(frame)
        if kind in (Kind.COMMAND, Kind.CONTINUATION):
            self.owed = frame
            if kind is Kind.COMMAND and len(frame) >= 10:
                h = frame[:10]
                words = h[3] in b"DXTZ"
                n = ((h[6] << 8) | h[7]) * (2 if words else 1)
                self.theirs = OpenRequest(h, h[2] == 0x45, bytes(n))
            return
        # a response to the tester's frame
        self.awaiting = False
        if self.mine is not None and len(frame) >= 4:
            if frame[3] != 0:
                self.mine = None
            else:
                self.mine.k += 1
                if self.mine.k >= self.mine.frames:
                    self.mine = None

    # -- the tester's actions -----------------------------------------------------------------
    def frame_out(self, frame: bytes, at: float = 0.0, at_expr: Expr | None = None, mutate_link: str = "") -> bool:
        """The tester sends ``frame`` as a conforming 3964(R) sender (or with one link-level
        change). False when the IUT started sending first (taken; nothing sent)."""
        sim = self.sim
        at2 = sim.clear(at)
        if at2 is None:
            self.react()
            return False
        if at2 != at:
            at, at_expr = at2, None
        if mutate_link:
            return self._frame_out_raw(frame, at, at_expr, mutate_link)
        # the runner's prime: STX, DLE, block, DLE; the model answers as it does
        sim.write(bytes([STX]), at)
        nb = sim.peek(sim.ref + 2 * self.p.adt)
        if nb is None or nb[1] != DLE:
            reject()       # the IUT did not take the STX (it was busy): not an example to keep
        sim.pos += 1
        sim.ref = nb[0]
        sim.write(link.body(frame, self.p.procedure))
        nb = sim.peek(sim.ref + 2 * self.p.adt)
        if nb is None or nb[1] != DLE:
            raise RuntimeError("the model did not acknowledge a conforming block")
        sim.pos += 1
        sim.ref = nb[0]
        sim.steps.append(Step("prime", bytes(frame), at=at_expr or ms(at), note=f"the tester sends {describe(frame)}"))
        return True

    def _frame_out_raw(self, frame: bytes, at: float, at_expr, how: str) -> bool:
        """A block with a link-level change: a corrupted BCC, or a pause inside it."""
        sim = self.sim
        body = link.body(frame, self.p.procedure)
        sim.send(bytes([STX]), at, at_expr, note="STX")
        nb = sim.peek(sim.ref + 2 * self.p.adt)
        if nb is None or nb[1] != DLE:
            reject()
        sim.take_bytes()
        if how == "bcc" and self.p.procedure == "3964R":
            body = body[:-1] + bytes([body[-1] ^ 0x5A])
            sim.send(body, note="the block with a wrong BCC")
        elif how == "gap-short":
            k = max(1, len(body) // 2)
            sim.send(body[:k], note="the first part of the block")
            sim.send(body[k:], at=0.5 * self.p.cdt, at_expr=Expr("0.5*CDT"), note="the rest after 0.5 CDT")
        elif how == "gap-long":
            # the rest never comes: after CDT the IUT refuses the block (NAK), no response
            sim.send(body[:max(1, len(body) // 2)], note="the first part of the block, then nothing")
        else:
            sim.send(body, note="the block")
        self.react()
        return True

    def act(self, data) -> None:
        """One action of the tester, for the situation: answer the IUT's command
        (:mod:`.active`), or go on with its own request or start something from idle
        (:mod:`.passive`)."""
        if self.owed is not None:
            return self.answer(data)
        if self.mine is not None and not self.awaiting:
            return self.continue_own(data)
        return self.from_idle(data)

    # -- the end ----------------------------------------------------------------------------
    def finish(self, data=None) -> None:
        """Bring the exchange to rest: answer what the IUT still asks for, finish the
        tester's own request, until the IUT is idle and its script done."""
        sim = self.sim
        for _ in range(40):
            if self.owed is not None:
                resp = self.right_response(self.owed, self.theirs)
                if self.frame_out(resp):
                    self.owed = None
                    if self.theirs is not None and self.theirs.fetch:
                        self.theirs.k += 1
                    self.react()
                continue
            if self.mine is not None and not self.awaiting:
                req = self.mine
                body = b"" if req.fetch else req.chunk(req.k)
                self.awaiting = True
                if self.frame_out(bytes([0xFF, 0x00, req.hdr[2], req.hdr[3]]) + body):
                    self.react()
                else:
                    self.awaiting = False
                continue
            host = sim.tr.host
            if sim.station.idle and host.done:
                break
            d = sim.station.next_deadline()
            if d is None:
                break
            self.react(quiet=max(0.0, d - sim.ref) + 2 * self.p.adt + 10 * self.p.char_time)
        self.react()

    # -- the vector ---------------------------------------------------------------------------
    def vector(self, vid: str, title: str, rule: str) -> Vector:
        sim = self.sim
        codes = [c for _, c in sim.tr.status_reports()]
        lines = [x for _, text in sim.tr.report_lines() for x in text.split("\n")
                 if x.startswith(("RESULT ", "FETCHED "))]
        # required: what the wire decides without an open point - a REATEL's event (class 09)
        # and a malformed response (16#0A02..0A04); the rest may be raised
        required = tuple(frozenset({c}) for c in sorted(set(codes))
                         if c >> 8 == 0x09 or c in (Code.RESPONSE_STRUCTURE, Code.RESPONSE_DATA_LENGTH,
                                                    Code.RESPONSE_TO_SEND_WITH_DATA))
        optional = frozenset(codes) | _LINK_CODES | _CLASS06 | INFORMATIONAL | frozenset(
            c for c in (Code.RESPONSE_OUT_OF_SEQUENCE, Code.FRAME_TOO_SHORT))
        needs: dict = {}
        if self.used_db:
            needs["db"] = sorted(self.used_db)
        if self.used_dx:
            needs["dx"] = sorted(self.used_dx)
        if self.fetched:
            needs["pattern"] = True
        extra = {"requests": list(sim.lines), "results": lines} if sim.lines else {}
        if needs:
            extra["needs"] = needs
        p = self.p
        return Vector(
            id=vid, title=title, reference="§2.2.3; Figs. 2-13 to 2-19; Tables 2-1, 2-2, 8-3 (generated by ptpcert fuzz)",
            rule=rule, group="regression", params=p,
            iut_role=("both" if self.commanded else "sender") if sim.lines else "receiver",
            steps=tuple(sim.steps), expected=Expected(StatusSpec(required, optional), StatusSpec()),
            provenance="[fuzz]", procedure="rk512", extra=extra, setup=sim.setup,
            binds=("link", "priority", "cdt_ms", "adt_ms", "setup_attempts", "transmission_attempts",
                   "baud_rate", "data_bits", "parity", "stop_bits", "response_time_ms", "db_bytes",
                   "byte_area_bytes", "cell_area_cells", "db_range", "dx_range", "memory", "cell_fetch_limit_bytes",
                   "serves_dx_fetch"),
        )
