"""The tester's side of an RK 512 fuzz example where the IUT is passive (Fig. 2-19): the
tester sends SEND and FETCH commands, valid or with one thing wrong (a header byte, the
frame class, the area, the data length against the header, the chunk boundaries, the frame
order against its open request, the link's BCC and timing), goes on with its open request
frame by frame, and crosses the IUT's STX with its own (an initialization conflict, §2.2.2
Fig. 2-8). It notes the memory the vector needs of the IUT for its commands.

:class:`PassiveSide` is mixed into :class:`~.example.RkExample`, whose state and link
methods (``frame_out``, ``react``, ``iut_frame``) it uses; the commands it sends are drawn by
the example's generator (``gen.valid_command``).
"""

from __future__ import annotations

from hypothesis import reject
from hypothesis import strategies as st

from ptpcert.procedures.p3964.model import codec as link
from ptpcert.procedures.rk512.model.codec import describe
from ptpcert.scenario import Expr, Step

from . import rules as R
from .cosim import DLE, STX, rule_of
from .requests import OpenRequest, command_header


class PassiveSide:
    """The tester commands the IUT (a mixin of :class:`~.example.RkExample`)."""

    def start_own(self, data, req: OpenRequest) -> None:
        """The tester starts its request ``req``: its first frame goes out, and a request of
        more than one frame stays open for its continuations."""
        self._note_areas(req)
        frame = req.hdr + (req.chunk(0) if not req.fetch else b"")
        self.mine = req if req.frames > 1 else None
        self.awaiting = True
        if self.frame_out(frame):
            self.react()
        else:
            self.mine, self.awaiting = None, False

    def _note_areas(self, req: OpenRequest) -> None:
        """What the vector needs of the IUT's memory for the tester's command ``req``."""
        self.commanded = True
        h = req.hdr
        if h[3] == ord("D") and h[2] in (0x41, 0x45):
            self.used_db.add(h[4])
        elif h[3] == ord("X") or h[2] == 0x4F:
            self.used_dx.add(h[4])
        if req.fetch:
            self.fetched = True

    def continue_own(self, data) -> None:
        """The tester's request waits for its next frame: send it (in time or after T_RES),
        or send it wrong (bytes 3/4, its length, a FETCH continuation with data), or a new
        first command instead."""
        p = self.p
        req = self.mine
        k = req.k
        body = b"" if req.fetch else req.chunk(k)
        cont = bytes([0xFF, 0x00, req.hdr[2], req.hdr[3]])
        how = data.draw(st.sampled_from(["ok", "ok", "ok", "late", "byte3", "byte4", "length", "new-first"]),
                        label="continuation")
        at, at_expr = 0.0, None
        if how == "ok":
            frac = data.draw(st.sampled_from([0.0, 0.0, 0.7]), label="T_RES fraction")
            at, at_expr = frac * p.t_res, (Expr(f"{frac}*TRES") if frac else None)
        elif how == "late":
            at, at_expr = 1.5 * p.t_res, Expr("1.5*TRES")
        frame = cont + body
        if how == "byte3":
            frame = cont[:2] + bytes([0x4F if req.hdr[2] == 0x41 else 0x41]) + cont[3:] + body
        elif how == "byte4":
            frame = cont[:3] + bytes([0x58 if req.hdr[3] != 0x58 else 0x44]) + body
        elif how == "length":
            frame = frame + b"\x00" if req.fetch or data.draw(st.booleans(), label="longer") else frame[:-1]
        elif how == "new-first":
            self.mine = None
            return self.start_own(data, self.gen.valid_command(data))
        self.awaiting = True
        if not self.frame_out(frame, at, at_expr):
            self.awaiting = False
            return
        if how != "ok":
            self.mine = None          # the request is over one way or another
        self.react()

    def from_idle(self, data) -> None:
        """Nothing is open: wait, or (where the IUT is passive) send a command, valid or with
        one thing wrong - a header byte or nibble, an area the IUT lacks, the data length, a
        first chunk of 127 or 129 bytes, the frame class, a frame too short, DLEs where they
        are rare, a wrong BCC, a pause inside the block, a second command crossing the
        response to the first."""
        p = self.p
        g = self.gen
        kinds = ["wait"]
        if g.passive:
            kinds += ["command", "command", "command", "header", "header", "header", "area", "area", "length",
                      "chunk", "class", "short", "dle", "bcc" if p.procedure == "3964R" else "dle", "gap", "crossing"]
        kind = data.draw(st.sampled_from(kinds), label="idle action")
        if kind == "wait":
            frac = data.draw(st.sampled_from([0.3, 1.5]), label="wait")
            self.sim.quiet_for(frac * p.t_res, Expr(f"{frac}*TRES")) or self.react()
            return
        req = g.valid_command(data)
        self._note_areas(req)
        frame = req.hdr + (req.chunk(0) if not req.fetch else b"")
        if kind == "command":
            return self.start_own(data, req)
        if kind == "header":
            i = data.draw(st.integers(0, 10), label="header byte")   # 10: a nibble of byte 10
            frame = bytearray(frame)
            if i == 10:
                hi = data.draw(st.booleans(), label="high nibble")
                v = data.draw(st.integers(0, 15), label="nibble")
                frame[9] = (v << 4 | frame[9] & 0x0F) if hi else (frame[9] & 0xF0 | v)
                if not hi and frame[8] == 0xFF and data.draw(st.booleans(), label="flag byte"):
                    frame[8] = data.draw(st.integers(0, 20), label="flag byte value")
            else:
                frame[i] = data.draw(st.one_of(st.sampled_from([0x00, 0xFF, 0x01, 0x10, 0x41, 0x43, 0x44, 0x45, 0x4F,
                                                                0x58, 0x5A, 0x54]), st.integers(0, 255)),
                                     label="header value")
            frame = bytes(frame)
        elif kind == "area":
            frame = self._area_error(data)
        elif kind == "length":
            delta = data.draw(st.sampled_from([-2, -1, 1, 2]), label="data delta")
            frame = frame + bytes(delta) if delta > 0 else frame[:max(10, len(frame) + delta)]
        elif kind == "chunk":
            # a multi-frame SEND whose first frame carries 127 or 129 bytes
            n = data.draw(st.sampled_from([127, 129]), label="first chunk")
            hdr = command_header(0x41, 0x44, self.gen.block_number(data), 0, 100)
            self.used_db.add(hdr[4])
            frame = hdr + bytes(n)
        elif kind == "class":
            which = data.draw(st.sampled_from(["continuation", "response", "continuation-response"]), label="class")
            frame = {"continuation": bytes([0xFF, 0x00, frame[2], frame[3]]) + frame[10:],
                     "response": bytes(4), "continuation-response": bytes([0xFF, 0, 0, 0])}[which]
        elif kind == "short":
            frame = frame[:data.draw(st.integers(1, 9), label="short length")]
        elif kind == "dle":
            # DLEs where they are rare: DB/DW 16, a length of 16 units, data of 10h
            hdr = command_header(0x41, 0x44, 16 if self._has_db(16) else self.gen.block_number(data), 16, 16)
            if self.p.db_bytes < 64:
                hdr = command_header(0x41, 0x44, hdr[4], 0, 1)
            self.used_db.add(hdr[4])
            n = 2 * ((hdr[6] << 8) | hdr[7])
            req = OpenRequest(hdr, False, bytes([0x10]) * n)
            return self.start_own(data, req)
        elif kind in ("bcc", "gap"):
            how = "bcc" if kind == "bcc" else data.draw(st.sampled_from(["gap-short", "gap-long"]), label="gap")
            self.frame_out(frame, mutate_link=how)
            return
        elif kind == "crossing":
            return self._crossing(data, req, frame)
        if self.frame_out(frame):
            self.react()

    def cross(self, data) -> None:
        """The IUT's STX is answered by the tester's own STX: an initialization conflict
        (§2.2.2 Fig. 2-8) while the IUT has a frame to send. Low priority, the IUT yields and
        takes the tester's command first; high, it waits for the tester to yield."""
        sim = self.sim
        t_stx, _ = sim.rx[sim.pos]
        sim.pos += 1
        d = t_stx - sim.ref
        sim.ref = t_stx
        sim.steps.append(Step("expect", bytes([STX]), within=sim.window(d), note=R.note(R.SETUP_STX, "the IUT's STX")))
        req = self.gen.valid_command(data, single=True)
        self._note_areas(req)
        frame = req.hdr + (req.data if not req.fetch else b"")
        sim.send(bytes([STX]), note="the tester's STX crosses it (an initialization conflict)")
        if self.p.priority == "low":
            nb = sim.peek(sim.ref + 2 * self.p.adt)
            if nb is None or nb[1] != DLE:
                reject()
            sim.take_bytes()
            sim.steps[-1] = Step("expect", bytes([DLE]), within=Expr("ADT"),
                                 note=R.note(R.LOW_DEFERS, "the IUT (low) yields and answers the tester's STX"))
            sim.send(link.body(frame, self.p.procedure), note=f"the tester sends {describe(frame)}")
            nb = sim.peek(sim.ref + 2 * self.p.adt)
            if nb is None or nb[1] != DLE:
                reject()
            sim.take_bytes()
            self.awaiting = True
            return
        if not sim.quiet_for(0.25 * self.p.adt, Expr("0.25*ADT")):
            reject()
        sim.steps[-1] = Step("silence", duration=Expr("0.25*ADT"),
                             note=R.note(R.HIGH_WAITS, "the IUT (high) does not answer the tester's STX"))
        sim.send(bytes([DLE]), note="the tester (low) yields")
        raw = sim.read_body()
        f = link.parse_body(raw, self.p.procedure)
        sim.steps.append(Step("expect", raw, within=Expr("CDT"), note=rule_of(f)))
        sim.send(bytes([DLE]), note="DLE")
        self.iut_frame(f)
        self.start_own(data, req)

    def _area_error(self, data) -> bytes:
        """A command whose area does not fit the IUT's memory: a missing DB or DX, DB 0, a start
        address or a length beyond the area, length 0, over 1024 bytes."""
        p = self.p
        lo, hi = p.db_range
        which = data.draw(st.sampled_from(["db-missing", "db0", "dx-missing", "beyond", "length0", "too-long",
                                           "over-1k"]), label="area error")
        fetch = data.draw(st.booleans(), label="fetch")
        cmd = 0x45 if fetch else 0x41
        if which == "db-missing" and hi < 255:
            return command_header(cmd, 0x44, hi + 1, 0, 1) + (b"" if fetch else bytes(2))
        if which == "dx-missing":
            return command_header(0x45 if fetch else 0x4F, 0x58 if fetch else 0x44, (p.dx_range[1] + 1) if p.dx_range and
                        p.dx_range[1] < 255 else 0, 0, 1) + (b"" if fetch else bytes(2))
        if which == "beyond":
            size = p.byte_area_bytes
            return command_header(0x45, 0x45, (size >> 8) & 0xFF, size & 0xFF, 2)
        if which == "length0":
            return command_header(cmd, 0x44, lo, 0, 0)
        if which == "too-long":
            return command_header(0x45, 0x44, lo, 0, p.db_bytes // 2 + 1)
        if which == "over-1k":
            return command_header(0x45, 0x44, lo, 0, 513)
        return command_header(cmd, 0x44, 0, 0, 1) + (b"" if fetch else bytes(2))

    def _has_db(self, n: int) -> bool:
        lo, hi = self.p.db_range
        return lo <= n <= hi

    def _crossing(self, data, req: OpenRequest, frame: bytes) -> None:
        """The tester's next command right after the IUT took its first: its STX crosses the
        IUT's response STX (only with the IUT low: it must yield, whatever its speed)."""
        sim = self.sim
        if self.p.priority != "low" or req.frames > 1:
            if self.frame_out(frame):
                self.react()
            return
        if not self.frame_out(frame):
            return
        second = self.gen.valid_command(data)
        self._note_areas(second)
        if second.frames > 1:
            second = OpenRequest(second.hdr[:6] + bytes([0, 1]) + second.hdr[8:], second.fetch,
                              bytes(2) if not second.fetch else bytes(2))
        f2 = second.hdr + (second.data if not second.fetch else b"")
        sim.send(bytes([STX]), note="the tester's next command at once: its STX crosses the IUT's response")
        nb = sim.peek(sim.ref + 2 * self.p.adt)
        if nb is None:
            reject()
        got = sim.take_bytes()
        sim.steps[-1] = Step("expect", got, after=sim.steps[-1].after, within=sim.steps[-1].within,
                             alternatives=(bytes([DLE]), bytes([STX, DLE])) if got in (b"\x10", b"\x02\x10") else (),
                             note=R.note(R.LOW_DEFERS, "the IUT (low) answers the tester's STX, after its own if that crossed"))
        if got not in (b"\x10", b"\x02\x10"):
            reject()
        sim.send(link.body(f2, self.p.procedure), note="the second command")
        self.react()
