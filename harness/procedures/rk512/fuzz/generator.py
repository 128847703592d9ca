"""The RK 512 fuzz kit's generator (:class:`RkGenerator`): what the campaign calls to draw
one example. It draws the IUT's request script (where the profile's IUT runs one) and a
set-up, starts the co-simulation (:class:`~.cosim.RkCoSim`) and lets the tester's side of
the example (:class:`~.example.RkExample`) act a drawn number of times and finish.

It also draws what the tester may address: valid commands that fit the IUT's memory as the
profile declares it (:meth:`RkGenerator.valid_command`), which both sides of the example use.
"""

from __future__ import annotations

from hypothesis import strategies as st

from ptpcert.procedures.rk512.model.readings import RK512_READINGS

from .cosim import RkCoSim
from .example import RkExample
from .requests import CHUNK, OpenRequest, command_header


def _fill(kind: str, seed: int, n: int) -> bytes:
    """SEND data: all DLEs, control characters mixed in (DLE, STX, ETX, NAK, 00, FF), or a ramp."""
    if kind == "dle":
        return bytes([0x10]) * n
    if kind == "mixed":
        alphabet = (0x10, 0x00, 0xFF, 0x02, 0x41, 0x03, 0x15)
        return bytes(alphabet[(seed + 3 * i + (i * i) % 7) % len(alphabet)] for i in range(n))
    return bytes((seed + 7 * i) & 0xFF for i in range(n))


#: the data lengths a drawn command asks for: around one frame's chunk and beyond it
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
    def block_number(self, data, dx: bool = False) -> int:
        """A DB (``dx``: DX) number the profile says exists, among its first 21."""
        lo, hi = self.p.dx_range if dx else self.p.db_range
        return data.draw(st.integers(lo, min(hi, lo + 20)), label="block number")

    def valid_command(self, data, single: bool = False) -> OpenRequest:
        """A command the IUT can serve: a SEND (DB, DX) or, with the pattern memory, a FETCH
        (also of the flag, input, output, timer and counter areas), of a drawn length and
        start that fit the area, naming a coordination flag the example knows at times;
        ``single``: it fits one frame."""
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
            b5, b6 = self.block_number(data, typ == "X"), start // 2
        else:
            addr = start // 2 if typ in "TZ" else start
            b5, b6 = addr >> 8, addr & 0xFF
        length = n // 2 if words else n
        cmd = 0x45 if fetch else (0x4F if typ == "X" else 0x41)
        b9, b10 = 0xFF, 0x1F
        if self.flags and data.draw(st.booleans(), label="name a flag"):
            b9, b10 = data.draw(st.sampled_from(self.flags), label="flag")
        hdr = command_header(cmd, ord("D") if not fetch and typ == "X" else ord(typ), b5, b6, length, b9, b10)
        payload = b"" if fetch else _fill(data.draw(st.sampled_from(["dle", "mixed", "ramp"]), label="data"),
                                            data.draw(st.integers(0, 255), label="data seed"), n)
        return OpenRequest(hdr, fetch, payload if not fetch else bytes(n))

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
    def __call__(self, data) -> RkExample:
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
