"""The tester's side of an RK 512 fuzz example where the IUT is active (Fig. 2-18): the IUT
has sent a command or continuation of its request script and waits for the response. The
tester answers it right, late around T_RES, with a wrong REATEL, frame id, frame class or
data length, not at all, or sends a command of its own first (quasi-full-duplex, Fig.
2-17).

:class:`ActiveSide` is mixed into :class:`~.example.RkExample`, whose state (the command
owed an answer, the IUT's open request) and link methods (``frame_out``, ``react``) it uses;
its passive side (:mod:`.passive`) starts the tester's own command.
"""

from __future__ import annotations

from hypothesis import strategies as st

from ptpcert.procedures.rk512.model.codec import REATEL_STATUS
from ptpcert.scenario import Expr

from .requests import CHUNK, OpenRequest


class ActiveSide:
    """The tester answers the IUT's requests (a mixin of :class:`~.example.RkExample`)."""

    def answer(self, data) -> None:
        """The IUT waits for the response to its command: answer it, right or wrong, in
        time or not, or send a command of the tester's own first (quasi-full-duplex)."""
        p = self.p
        frame, req = self.owed, self.theirs
        first = frame[0] == 0x00
        how = data.draw(st.sampled_from(["ok", "ok", "ok", "late-ok", "withhold", "reatel", "bad-id", "class",
                                         "length", "own-first"]), label="answer")
        at, at_expr = 0.0, None
        if how in ("ok", "late-ok"):
            frac = 1.5 if how == "late-ok" else data.draw(st.sampled_from([0.0, 0.3, 0.7]), label="T_RES fraction")
            at, at_expr = frac * p.t_res, (Expr(f"{frac}*TRES") if frac else None)
        resp = self.right_response(frame, req)
        if how == "reatel":
            r = data.draw(st.sampled_from(sorted(REATEL_STATUS) + [0x01, 0x42, 0xFF]), label="REATEL")
            resp = bytes([0x00 if first else 0xFF, 0, 0, r])
        elif how == "bad-id":
            resp = bytes([0x01]) + resp[1:]
        elif how == "class":
            resp = bytes([0xFF if first else 0x00]) + resp[1:]
        elif how == "length":
            if req is not None and req.fetch:
                resp = resp + b"\x00" if data.draw(st.booleans(), label="longer") or len(resp) <= 4 else resp[:-1]
            else:
                resp = resp + b"\x00"
        elif how == "withhold":
            if self.sim.quiet_for(1.5 * p.t_res, Expr("1.5*TRES")):
                self.owed = None
                self.theirs = None
            self.react()
            return
        elif how == "own-first" and self.mine is None and self.gen.passive:
            self.start_own(data, self.gen.valid_command(data))
            return
        if self.frame_out(resp, at, at_expr):
            self.owed = None
            if resp[3] != 0 or how in ("bad-id", "class", "length", "late-ok"):
                self.theirs = None
            elif req is not None and req.fetch:
                req.k += 1
            self.react()

    def right_response(self, frame: bytes, req: OpenRequest | None) -> bytes:
        """The response a conforming partner gives to the IUT's command or continuation
        ``frame``: no error (REATEL 0) and, for a FETCH, the next chunk of the requested
        data (a ramp from A0h over the request's bytes)."""
        first = frame[0] == 0x00
        head = bytes([0x00 if first else 0xFF, 0, 0, 0])
        if req is None or not req.fetch:
            return head
        done = req.k * CHUNK
        n = min(CHUNK, req.nbytes - done)
        return head + bytes((0xA0 + done + i) & 0xFF for i in range(max(0, n)))
