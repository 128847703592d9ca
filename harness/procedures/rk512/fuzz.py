"""The fuzzer for RK 512 (``ptpcert fuzz`` with an RK 512 profile), level 2: generated partner
behaviour against an IUT, the RK 512 model as the oracle.

For every example hypothesis draws the tester's behaviour step by step while the model plays
the IUT in virtual time (co-simulation through the ``sim:`` transport, exactly as the runner
will replay it): what the tester does next depends on what a conforming IUT has just done.
The tester sends commands, valid or with one thing wrong - a header byte 1..10 (the nibbles
of byte 10 included), the frame class, the data length against the header length, the chunk
boundaries 127/128/129, the frame order against the open request - and answers the IUT's own
requests (from a drawn request script) correctly, with a wrong response, late around T_RES
or not at all; it places DLEs in the header, the data, the REATEL and the BCC, corrupts a
BCC, pauses inside a block around CDT, and sends its STX while a response is owed (crossing
the IUT's). What the model does becomes the expectation: its frames as ``receive`` steps,
its quiet periods as silence, its request results and STATUS events. A divergence is a
finding unless a model with another reading of an open point of the manual (the fields of
:class:`~ptpcert.model.rk512.readings.Rk512Readings`) does what the IUT did.

Timing stimuli keep a margin from every limit a real process can honour: T_RES is probed at
30 %, 70 % and 150 %, CDT at 50 % and 150 %, and no stimulus lands within 15 % of the
shortest link timer (plus two characters) of one of the model's deadlines. Exact edges are
level 1's (tests/test_fuzz_rk512_model.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hypothesis import reject
from hypothesis import strategies as st

from ptpcert.fuzz.kit import FuzzKit, ms, send_receive_codes
from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import codec as link
from ptpcert.procedures.rk512.model.codec import REATEL_STATUS, Kind, classify, describe
from ptpcert.procedures.rk512.model.readings import RK512_READINGS
from ptpcert.scenario import Expected, Expr, StatusSpec, Step, Vector

STX, DLE, ETX, NAK = 0x02, 0x10, 0x03, 0x15
CHUNK = 128
_LINK_CODES = send_receive_codes("RK 512") | send_receive_codes("3964(R)")
_CLASS06 = frozenset(range(0x0601, 0x0613))
INFORMATIONAL = frozenset({0x0701, 0x0801, 0x0702, 0x0815})


def _rule_of(frame: bytes) -> str:
    """The rule that makes a conforming IUT send ``frame`` (for the notes of findings)."""
    kind = classify(frame)
    if kind in (Kind.COMMAND, Kind.CONTINUATION):
        return ("§2.2.3 Table 2-1, Figs. 2-13 to 2-16; §6.3.2 Tables 6-4 to 6-8: the IUT's request is "
                + describe(frame))
    return "§2.2.3 Table 2-2, Fig. 2-19; §8.4 Table 8-3: the IUT answers with " + describe(frame)


# ------------------------------------------------------------------ the co-simulation
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
        first = self._peek(self.start + 2.0)       # the runner's prologue takes the start-up NAK
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

    def _peek(self, deadline: float):
        while self.pos >= len(self.rx):
            if self.tr.now() >= deadline:
                return None
            self.rx += self.tr.read(deadline)
        return self.rx[self.pos]

    def _write(self, data: bytes, at: float = 0.0, gap: float = 0.0) -> None:
        start = self.ref + at
        t = start
        for k, b in enumerate(data):
            t = start + k * (self.char + gap) + self.char
            self._pump(t)
            self.tr.write(bytes([b]))
        self.ref = t

    def send(self, data: bytes, at: float = 0.0, at_expr: Expr | None = None, gap: float = 0.0, note: str = "") -> None:
        self._write(bytes(data), at, gap)
        self.steps.append(Step("send", bytes(data), at=at_expr or ms(at), gap=ms(gap), note=note))

    def window(self, d: float) -> Expr:
        """The window for an IUT reply that the model sent ``d`` after the reference point:
        the monitoring time, or more where the model itself took longer (a request after a
        script's wait)."""
        return Expr("TRES") if d <= 0.5 * self.p.t_res else Expr(f"{1000 * d:.3f}ms + ADT")

    # -- the IUT's blocks and bytes --------------------------------------------------------
    def _read_body(self) -> bytes:
        """The IUT's block after the tester's DLE, up to DLE ETX (and the BCC)."""
        raw = bytearray()
        esc = bcc_next = False
        while True:
            nb = self._peek(self.ref + 60.0)
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
            self._write(bytes([DLE]), dle_at * self.p.adt)
            raw = self._read_body()
            frame = link.parse_body(raw, self.p.procedure)
            no = attempt < refuse
            self._write(bytes([NAK if no else DLE]))
            after = ms(min(0.0, d - 2 * self.char))
            note = _rule_of(frame)
            if dle_at or refuse:
                self.steps += [
                    Step("expect", bytes([STX]), after=after, within=self.window(d), note="the IUT's STX"),
                    Step("send", bytes([DLE]), at=Expr(f"{dle_at}*ADT") if dle_at else Expr("0"),
                         note=f"DLE {dle_at} ADT later" if dle_at else "DLE"),
                    Step("expect", raw, within=Expr("CDT"), note=note),
                    Step("send", bytes([NAK if no else DLE]), note="NAK: the tester refuses the block" if no else "DLE")]
            else:
                self.steps.append(Step("receive", frame, after=after, within=self.window(d), note=note))
            if not no:
                return frame
            attempt += 1
            nb = self._peek(self.ref + 2 * self.p.adt + 10 * self.char)
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
            nb = self._peek(last + self.p.cdt)
            if nb is None or nb[1] == STX:
                break
            got.append(nb[1])
            last = nb[0]
            self.pos += 1
        self.ref = last
        self.steps.append(Step("expect", bytes(got), after=ms(min(0.0, d - 2 * self.char)),
                               within=Expr(f"{max(1000 * d, 0):.3f}ms + ADT"),
                               note="§2.2.2 (the link below RK 512): the IUT's answer on the line"))
        return bytes(got)

    def quiet_for(self, duration: float, expr: Expr) -> bool:
        """The model stays quiet for ``duration`` after the reference point: recorded as a
        silence step. False (nothing recorded) when it sends something."""
        if self._peek(self.ref + duration) is not None:
            return False
        self._pump(self.ref + duration)
        self.ref += duration
        self.steps.append(Step("silence", duration=expr,
                               note="§2.2.3 'Response message frame', Fig. 2-19: the IUT sends nothing it does not owe"))
        return True

    def clear(self, at: float) -> float | None:
        """When a stimulus ``at`` after the reference point may start: never so close to one of
        the model's deadlines that a real process could see the two in either order. None
        when the IUT starts sending before: it must be taken first."""
        while True:
            start = self.ref + at
            if self._peek(start + self.char) is not None:
                return None
            d = self.station.next_deadline()
            if d is None or not (start - self.edge_margin < d < start + self.char + self.edge_margin):
                return at
            at = d + self.edge_margin - self.ref


# ------------------------------------------------------------------ the generator
@dataclass
class _Request:
    """A request in progress, the tester's own or the IUT's: its header and data."""

    hdr: bytes
    fetch: bool
    data: bytes
    k: int = 0                       # frames done
    sent: list = field(default_factory=list)

    @property
    def nbytes(self) -> int:
        return len(self.data)

    @property
    def frames(self) -> int:
        return max(1, -(-self.nbytes // CHUNK))

    def chunk(self, k: int) -> bytes:
        return self.data[k * CHUNK:(k + 1) * CHUNK]


def _fill(kind: str, seed: int, n: int) -> bytes:
    """SEND data: all DLEs, control characters mixed in (DLE, STX, ETX, NAK, 00, FF), or a ramp."""
    if kind == "dle":
        return bytes([0x10]) * n
    if kind == "mixed":
        alphabet = (0x10, 0x00, 0xFF, 0x02, 0x41, 0x03, 0x15)
        return bytes(alphabet[(seed + 3 * i + (i * i) % 7) % len(alphabet)] for i in range(n))
    return bytes((seed + 7 * i) & 0xFF for i in range(n))


def _hdr(cmd: int, typ: int, b5: int, b6: int, length: int, b9: int = 0xFF, b10: int = 0x1F) -> bytes:
    return bytes([0, 0, cmd, typ, b5, b6, (length >> 8) & 0xFF, length & 0xFF, b9, b10])


SIZES = [2, 6, 10, 126, 128, 130, 200, 256, 300]


class RkGenerator:
    """Draws one RK 512 example, co-simulated with the model."""

    def __init__(self, profile, max_actions: int = 6, readings=RK512_READINGS):
        from ptpcert.registry import by_id

        self.profile = profile
        self.proc = by_id("rk512")
        self.p = profile.params
        self.max_actions = max_actions
        self.readings = readings
        p = self.p
        self.active = "active" in p.roles and p.requests == "script"
        self.passive = "passive" in p.roles
        self.pattern = p.memory == "pattern"
        self.flags: list[tuple[int, int]] = []

    # -- what the tester may address ----------------------------------------------------------
    def _db(self, data, dx: bool = False) -> int:
        lo, hi = self.p.dx_range if dx else self.p.db_range
        return data.draw(st.integers(lo, min(hi, lo + 20)), label="block number")

    def _valid_command(self, data, single: bool = False) -> _Request:
        p = self.p
        types = "D" + ("X" if p.dx_range else "") + ("EAMTZ" if self.pattern else "")
        fetch = self.pattern and data.draw(st.booleans(), label="fetch")
        typ = data.draw(st.sampled_from(types if fetch else "D" + ("X" if p.dx_range else "")), label="type")
        if typ in "DX":
            size = p.db_bytes
        elif typ in "TZ":
            size = 2 * p.cell_area_cells
        else:
            size = p.byte_area_bytes
        n = data.draw(st.sampled_from([s for s in SIZES if s <= min(size, 1024) and (s <= CHUNK or not single)]
                                      or [2]), label="bytes")
        words = typ in "DXTZ"
        if words and n % 2:
            n += 1
        room = min(size - n, 510 if typ in "DX" else 255)
        start = data.draw(st.integers(0, max(0, room)), label="start") if room > 0 else 0
        if words:
            start -= start % 2
        if typ in "DX":
            b5, b6 = self._db(data, typ == "X"), start // 2
        else:
            addr = start // 2 if typ in "TZ" else start
            b5, b6 = addr >> 8, addr & 0xFF
        length = n // 2 if words else n
        cmd = 0x45 if fetch else (0x4F if typ == "X" else 0x41)
        b9, b10 = 0xFF, 0x1F
        if self.flags and data.draw(st.booleans(), label="name a flag"):
            b9, b10 = data.draw(st.sampled_from(self.flags), label="flag")
        hdr = _hdr(cmd, ord("D") if not fetch and typ == "X" else ord(typ), b5, b6, length, b9, b10)
        payload = b"" if fetch else _fill(data.draw(st.sampled_from(["dle", "mixed", "ramp"]), label="data"),
                                            data.draw(st.integers(0, 255), label="data seed"), n)
        return _Request(hdr, fetch, payload if not fetch else bytes(n))

    def _script(self, data) -> list[str]:
        if not self.active:
            return []
        out = []
        for _ in range(data.draw(st.integers(0 if self.passive else 1, 2), label="requests")):
            op = data.draw(st.sampled_from(["send", "send", "fetch"]), label="op")
            area = data.draw(st.sampled_from(["DB", "DB", "DX", "M", "E", "A", "T", "Z"] if op == "fetch"
                                             else ["DB", "DB", "DX"]), label="area")
            n = data.draw(st.sampled_from([1, 2, 5, 10, 127, 128, 129, 130, 200, 300]), label="LEN")
            if area in ("DB", "DX"):
                spec = f"{area}{data.draw(st.integers(1, 40), label='number')}:" + data.draw(
                    st.sampled_from(["DW0", "DW5", "OFF=7", "DW200"]), label="address")
            else:
                spec = f"{area}:{data.draw(st.sampled_from([0, 3, 20, 100]), label='address')}"
            spec += f":LEN={n}"
            spec += data.draw(st.sampled_from(["", "", ":CPU=none", ":CPU=2", ":CF=3.5:CPU=2", ":CF=12.3:CPU=none",
                                               ":CPU=0"]), label="cpu and flag")
            if op == "send" and data.draw(st.booleans(), label="seed"):
                spec += f":SEED={data.draw(st.integers(0, 255), label='seed value')}"
            out.append(f"{op} {spec}")
        return out

    # -- one example ----------------------------------------------------------------------
    def __call__(self, data) -> "RkExample":
        lines = self._script(data)
        setups = [None] * 6
        if "cpu_stop" in self.profile.setups:
            setups.append(("cpu_stop", {}))
        if "flag_set" in self.profile.setups and self.p.byte_area_bytes > 12:
            setups.append(("flag_set", {"flag": "12.3", "reset_ms": int(3000 * self.p.t_res)}))
        setup = data.draw(st.sampled_from(setups), label="set-up")
        self.flags = [(3, 0x15)] if self.p.byte_area_bytes > 3 else []
        if setup and setup[0] == "flag_set":
            self.flags.append((12, 0x13))
        sim = RkCoSim(self.proc, self.profile, lines, self.readings, setup)
        ex = RkExample(sim, self)
        ex.react(data)
        n = data.draw(st.integers(1, self.max_actions), label="actions")
        for _ in range(n):
            ex.act(data)
        ex.finish(data)
        return ex


class RkExample:
    """The tester's side of one example: its own request, the IUT's, and what to do next."""

    def __init__(self, sim: RkCoSim, gen: RkGenerator):
        self.sim, self.gen = sim, gen
        self.p = gen.p
        self.mine: _Request | None = None      # the tester's request, waiting for its next frame
        self.awaiting = False                  # the tester's frame waits for its response
        self.theirs: _Request | None = None    # the IUT's request
        self.owed: bytes | None = None         # the IUT's command the tester has not answered
        self.used_db: set[int] = set()
        self.commanded = False                 # the tester sent commands: the IUT was passive too
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
            nb = sim._peek(sim.ref + q)
            if nb is None:
                sim.quiet_for(q, Expr(f"{1000 * q:.3f}ms") if quiet is not None else Expr("2*ADT + 10*CHAR"))
                return
            if nb[1] == STX:
                how = "dle" if data is None else data.draw(
                    st.sampled_from(["dle"] * 6 + ["slow-dle", "refuse-once", "refuse-all", "cross"]), label="answer STX")
                if how == "cross" and self.owed is None and self.gen.passive:
                    self._cross(data)
                    continue
                refuse = {"refuse-once": 1, "refuse-all": self.p.line.transmission_attempts}.get(how, 0)
                frame = sim.take_block(0.5 if how == "slow-dle" else 0.0, refuse)
                if frame is not None:
                    self._iut_frame(frame)
                elif self.theirs is not None and self.owed is None:
                    self.theirs = None       # its request ended with the link's failure
            else:
                sim.take_bytes()

    def _iut_frame(self, frame: bytes) -> None:
        kind = classify(frame)
        if kind in (Kind.COMMAND, Kind.CONTINUATION):
            self.owed = frame
            if kind is Kind.COMMAND and len(frame) >= 10:
                h = frame[:10]
                words = h[3] in b"DXTZ"
                n = ((h[6] << 8) | h[7]) * (2 if words else 1)
                self.theirs = _Request(h, h[2] == 0x45, bytes(n))
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
    def _frame_out(self, frame: bytes, at: float = 0.0, at_expr: Expr | None = None, mutate_link: str = "") -> bool:
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
        sim._write(bytes([STX]), at)
        nb = sim._peek(sim.ref + 2 * self.p.adt)
        if nb is None or nb[1] != DLE:
            reject()       # the IUT did not take the STX (it was busy): not an example to keep
        sim.pos += 1
        sim.ref = nb[0]
        sim._write(link.body(frame, self.p.procedure))
        nb = sim._peek(sim.ref + 2 * self.p.adt)
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
        nb = sim._peek(sim.ref + 2 * self.p.adt)
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
        if self.owed is not None:
            return self._answer(data)
        if self.mine is not None and not self.awaiting:
            return self._continue(data)
        return self._from_idle(data)

    def _answer(self, data) -> None:
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
        resp = self._right_response(frame, req)
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
            self._start_own(data, self.gen._valid_command(data))
            return
        if self._frame_out(resp, at, at_expr):
            self.owed = None
            if resp[3] != 0 or how in ("bad-id", "class", "length", "late-ok"):
                self.theirs = None
            elif req is not None and req.fetch:
                req.k += 1
            self.react()

    def _right_response(self, frame: bytes, req: _Request | None) -> bytes:
        first = frame[0] == 0x00
        head = bytes([0x00 if first else 0xFF, 0, 0, 0])
        if req is None or not req.fetch:
            return head
        done = req.k * CHUNK
        n = min(CHUNK, req.nbytes - done)
        return head + bytes((0xA0 + done + i) & 0xFF for i in range(max(0, n)))

    def _start_own(self, data, req: _Request) -> None:
        self._note_areas(req)
        frame = req.hdr + (req.chunk(0) if not req.fetch else b"")
        self.mine = req if req.frames > 1 else None
        self.awaiting = True
        if self._frame_out(frame):
            self.react()
        else:
            self.mine, self.awaiting = None, False

    def _note_areas(self, req: _Request) -> None:
        self.commanded = True
        h = req.hdr
        if h[3] == ord("D") and h[2] in (0x41, 0x45):
            self.used_db.add(h[4])
        elif h[3] == ord("X") or h[2] == 0x4F:
            self.used_dx.add(h[4])
        if req.fetch:
            self.fetched = True

    def _continue(self, data) -> None:
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
            return self._start_own(data, self.gen._valid_command(data))
        self.awaiting = True
        if not self._frame_out(frame, at, at_expr):
            self.awaiting = False
            return
        if how != "ok":
            self.mine = None          # the request is over one way or another
        self.react()

    def _from_idle(self, data) -> None:
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
        req = g._valid_command(data)
        self._note_areas(req)
        frame = req.hdr + (req.chunk(0) if not req.fetch else b"")
        if kind == "command":
            return self._start_own(data, req)
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
            hdr = _hdr(0x41, 0x44, self.gen._db(data), 0, 100)
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
            hdr = _hdr(0x41, 0x44, 16 if self._has_db(16) else self.gen._db(data), 16, 16)
            if self.p.db_bytes < 64:
                hdr = _hdr(0x41, 0x44, hdr[4], 0, 1)
            self.used_db.add(hdr[4])
            n = 2 * ((hdr[6] << 8) | hdr[7])
            req = _Request(hdr, False, bytes([0x10]) * n)
            return self._start_own(data, req)
        elif kind in ("bcc", "gap"):
            how = "bcc" if kind == "bcc" else data.draw(st.sampled_from(["gap-short", "gap-long"]), label="gap")
            self._frame_out(frame, mutate_link=how)
            return
        elif kind == "crossing":
            return self._crossing(data, req, frame)
        if self._frame_out(frame):
            self.react()

    def _cross(self, data) -> None:
        """The IUT's STX is answered by the tester's own STX: an initialization conflict
        (§2.2.2 Fig. 2-8) while the IUT has a frame to send. Low priority, the IUT yields and
        takes the tester's command first; high, it waits for the tester to yield."""
        sim = self.sim
        t_stx, _ = sim.rx[sim.pos]
        sim.pos += 1
        d = t_stx - sim.ref
        sim.ref = t_stx
        sim.steps.append(Step("expect", bytes([STX]), after=ms(min(0.0, d - 2 * sim.char)), within=sim.window(d),
                              note="the IUT's STX"))
        req = self.gen._valid_command(data, single=True)
        self._note_areas(req)
        frame = req.hdr + (req.data if not req.fetch else b"")
        sim.send(bytes([STX]), note="the tester's STX crosses it (an initialization conflict)")
        if self.p.priority == "low":
            nb = sim._peek(sim.ref + 2 * self.p.adt)
            if nb is None or nb[1] != DLE:
                reject()
            sim.take_bytes()
            sim.steps[-1] = Step("expect", bytes([DLE]), within=Expr("ADT"),
                                 note="§2.2.2 Fig. 2-8: the IUT (low) yields and answers the tester's STX")
            sim.send(link.body(frame, self.p.procedure), note=f"the tester sends {describe(frame)}")
            nb = sim._peek(sim.ref + 2 * self.p.adt)
            if nb is None or nb[1] != DLE:
                reject()
            sim.take_bytes()
            self.awaiting = True
            return
        if not sim.quiet_for(0.25 * self.p.adt, Expr("0.25*ADT")):
            reject()
        sim.steps[-1] = Step("silence", duration=Expr("0.25*ADT"),
                             note="§2.2.2 Fig. 2-8: the IUT (high) does not answer the tester's STX")
        sim.send(bytes([DLE]), note="the tester (low) yields")
        raw = sim._read_body()
        f = link.parse_body(raw, self.p.procedure)
        sim.steps.append(Step("expect", raw, within=Expr("CDT"), note=_rule_of(f)))
        sim.send(bytes([DLE]), note="DLE")
        self._iut_frame(f)
        self._start_own(data, req)

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
            return _hdr(cmd, 0x44, hi + 1, 0, 1) + (b"" if fetch else bytes(2))
        if which == "dx-missing":
            return _hdr(0x45 if fetch else 0x4F, 0x58 if fetch else 0x44, (p.dx_range[1] + 1) if p.dx_range and
                        p.dx_range[1] < 255 else 0, 0, 1) + (b"" if fetch else bytes(2))
        if which == "beyond":
            size = p.byte_area_bytes
            return _hdr(0x45, 0x45, (size >> 8) & 0xFF, size & 0xFF, 2)
        if which == "length0":
            return _hdr(cmd, 0x44, lo, 0, 0)
        if which == "too-long":
            return _hdr(0x45, 0x44, lo, 0, p.db_bytes // 2 + 1)
        if which == "over-1k":
            return _hdr(0x45, 0x44, lo, 0, 513)
        return _hdr(cmd, 0x44, 0, 0, 1) + (b"" if fetch else bytes(2))

    def _has_db(self, n: int) -> bool:
        lo, hi = self.p.db_range
        return lo <= n <= hi

    def _crossing(self, data, req: _Request, frame: bytes) -> None:
        """The tester's next command right after the IUT took its first: its STX crosses the
        IUT's response STX (only with the IUT low: it must yield, whatever its speed)."""
        sim = self.sim
        if self.p.priority != "low" or req.frames > 1:
            if self._frame_out(frame):
                self.react()
            return
        if not self._frame_out(frame):
            return
        second = self.gen._valid_command(data)
        self._note_areas(second)
        if second.frames > 1:
            second = _Request(second.hdr[:6] + bytes([0, 1]) + second.hdr[8:], second.fetch,
                              bytes(2) if not second.fetch else bytes(2))
        f2 = second.hdr + (second.data if not second.fetch else b"")
        sim.send(bytes([STX]), note="the tester's next command at once: its STX crosses the IUT's response")
        nb = sim._peek(sim.ref + 2 * self.p.adt)
        if nb is None:
            reject()
        got = sim.take_bytes()
        sim.steps[-1] = Step("expect", got, after=sim.steps[-1].after, within=sim.steps[-1].within,
                             alternatives=(bytes([DLE]), bytes([STX, DLE])) if got in (b"\x10", b"\x02\x10") else (),
                             note="the IUT (low) answers the tester's STX, after its own if that crossed")
        if got not in (b"\x10", b"\x02\x10"):
            reject()
        sim.send(link.body(f2, self.p.procedure), note="the second command")
        self.react()

    # -- the end ----------------------------------------------------------------------------
    def finish(self, data=None) -> None:
        """Bring the exchange to rest: answer what the IUT still asks for, finish the
        tester's own request, until the IUT is idle and its script done."""
        sim = self.sim
        for _ in range(40):
            if self.owed is not None:
                resp = self._right_response(self.owed, self.theirs)
                if self._frame_out(resp):
                    self.owed = None
                    if self.theirs is not None and self.theirs.fetch:
                        self.theirs.k += 1
                    self.react()
                continue
            if self.mine is not None and not self.awaiting:
                req = self.mine
                body = b"" if req.fetch else req.chunk(req.k)
                self.awaiting = True
                if self._frame_out(bytes([0xFF, 0x00, req.hdr[2], req.hdr[3]]) + body):
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
                   "byte_area_bytes", "cell_area_cells", "db_range", "dx_range", "memory"),
        )


# ------------------------------------------------------------------ the open points
ALTERNATIVE_READINGS = [
    ("AMB-01", dict(amb01_accept_c_for_counters=True)),
    ("AMB-03", dict(amb03_accept_send_type_x=True)),
    ("AMB-10", dict(amb10_short_command_reatel=None)),
    ("AMB-10", dict(amb10_short_response_ends_request=False)),
    ("AMB-13", dict(amb13_check_byte2=True)),
    ("AMB-14", dict(amb14_address_16bit=False)),
    ("AMB-16", dict(amb16_exact_chunks=False)),
    ("AMB-17", dict(amb17_tres_start="handed_over")),
    ("AMB-18", dict(amb18_first_command_while_waiting="execute")),
    ("AMB-18", dict(amb18_passive_timeout_status=Code.PARTNER_SEQUENCE_ERROR)),
    ("AMB-20", dict(amb20_cell_fetch_limit_bytes=32)),
    ("AMB-20", dict(amb20_cell_fetch_limit_bytes=32, amb20_cell_limit_reatel=0x0C)),
    ("AMB-20", dict(amb20_serve_dx_fetch=False)),
    ("AMB-22", dict(amb22_cpu0_nibble_without_flag=0xF)),
    ("AMB-23", dict(amb23_byte9_ff_means_no_flag=False)),
    ("AMB-25", dict(amb25_extent_beyond_area="area")),
    ("AMB-31", dict(amb31_responses_first=True)),
    ("AMB-32", dict(amb32_early_response_ends_request=True)),
    ("AMB-33", dict(amb33_error_response_with_data="reatel")),
    ("N1", dict(n1_bad_id_reply_frame_id=0xFF)),
    ("N3", dict(n3_continuation_count_status=Code.SEND_LENGTH_DIFFERS)),
    ("N4", dict(n4_write_per_frame=False)),
    ("N5", dict(n5_len_over_1024_status=Code.LEN_ILLEGAL)),
    ("N6", dict(n6_db0_status=Code.INVALID_FB_PARAMETERS)),
    ("N7", dict(n7_pipelined_command_aborts=False)),
]

FUZZ_KIT = FuzzKit(RkGenerator, RK512_READINGS, tuple(ALTERNATIVE_READINGS), check_reports=True)

__all__ = ["FUZZ_KIT", "RkCoSim", "RkGenerator", "RkExample", "ALTERNATIVE_READINGS"]
