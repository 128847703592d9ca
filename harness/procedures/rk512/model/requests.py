"""Requests of the active side (P_SND_RK, §6.3.2) and the request-script format.

A request script is text, one item per line; ``#`` starts a comment::

    send DB10:DW0:LEN=200            # SEND 200 bytes to the partner's DB 10 from DW 0
    fetch E:0:LEN=10                 # FETCH 10 input bytes from byte 0
    send DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004
    wait 500                         # ms before the next request

SPEC is ``AREA:ADDRESS:LEN=n[:CF=B.b][:CPU=n|none][:DATA=hex][:SEED=n]``: AREA one of DBn,
DXn, M, E, A, T, Z; ADDRESS ``DWn`` or ``OFF=n`` (an S7 byte offset, rounded down to even)
for DB/DX, the byte or cell number otherwise; LEN in bytes as on the FB. A SEND without
DATA carries byte i = (SEED + 7 i) & FFh, SEED 10h by default (so its first byte is a DLE).
A request's label is ``send:SPEC`` or ``fetch:SPEC`` with SPEC as written.

The parser checks the syntax only. Values the FB or the CP refuse (LEN 0 or over 1024, DB
0, a flag bit over 7, CPU 5, a SEND to a byte area...) parse, and the station refuses them
locally with their STATUS, so that a script can test that they never reach the wire.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

from ptpcert.model.codes import Code

from .codec import MAX_REQUEST_BYTES, Area, Header, command_header
from .readings import RK512_READINGS, Rk512Readings

DEFAULT_SEED = 0x10


@lru_cache(maxsize=256)
def _period(seed: int) -> bytes:
    return bytes((seed + 7 * i) & 0xFF for i in range(256))


def default_data(length: int, seed: int = DEFAULT_SEED) -> bytes:
    """The SEND data of a script request without DATA: byte i = (seed + 7 i) & FFh (the
    pattern repeats every 256 bytes)."""
    period = _period(seed & 0xFF)
    return (period * (length // 256 + 1))[:length]


@dataclass(frozen=True)
class Request:
    """One SEND or FETCH, in the request's own terms (the FB's parameters).

    ``number`` is the DB/DX number (0 for the other areas), ``address`` the S7 byte offset
    for DB/DX (as written: rounding happens in the header) and the byte or cell number
    otherwise; ``length`` is LEN in bytes; ``cf`` the coordination flag (byte, bit) or
    None; ``cpu`` the CPU number or None ("none"); ``data`` the SEND data as given (None:
    the default pattern from ``seed``). ``spec`` is the text of the SPEC, for the label.
    """

    op: str
    area: Area
    number: int
    address: int
    length: int
    cf: tuple[int, int] | None = None
    cpu: int | None = 1
    data: bytes | None = None
    seed: int = DEFAULT_SEED
    spec: str = ""
    line: int = 0

    @property
    def label(self) -> str:
        return f"{self.op}:{self.spec or self.canonical_spec()}"

    @property
    def payload(self) -> bytes:
        """The SEND data (LEN bytes, before any padding)."""
        if self.data is not None:
            return self.data
        return default_data(self.length, self.seed)

    def canonical_spec(self) -> str:
        a = self.area
        if a.block:
            where = f"{a.name}{self.number}:" + (f"DW{self.address // 2}" if self.address % 2 == 0 else f"OFF={self.address}")
        else:
            where = f"{a.name}:{self.address}"
        out = f"{where}:LEN={self.length}"
        if self.cf is not None:
            out += f":CF={self.cf[0]}.{self.cf[1]}"
        if self.cpu != 1:
            out += ":CPU=" + ("none" if self.cpu is None else str(self.cpu))
        if self.data is not None:
            out += ":DATA=" + self.data.hex().upper()
        elif self.seed != DEFAULT_SEED and self.op == "send":
            out += f":SEED={self.seed}"
        return out


@dataclass(frozen=True)
class Wait:
    """``wait N``: N milliseconds before the next request."""

    ms: int
    line: int = 0


class ScriptError(ValueError):
    """A request script (or one SPEC) that does not parse: ``line`` (1-based, 0 for a SPEC
    given alone) and what is wrong."""

    def __init__(self, line: int, message: str):
        self.line, self.message = line, message
        super().__init__(f"line {line}: {message}" if line else message)


_AREA = re.compile(r"^(DB|DX)(\d+)$|^(M|E|A|T|Z)$", re.IGNORECASE)
_NUM = re.compile(r"^\d+$")


def _number(text: str, what: str, line: int) -> int:
    if not _NUM.match(text):
        raise ScriptError(line, f"{what} {text!r} is not a decimal number")
    return int(text)


def parse_request(op: str, spec: str, line: int = 0) -> Request:
    """One request from its op ("send"/"fetch") and SPEC."""
    op = op.lower()
    if op not in ("send", "fetch"):
        raise ScriptError(line, f"{op!r} is not a request: send or fetch")
    spec = spec.strip()
    if not spec:
        raise ScriptError(line, f"{op} needs AREA:ADDRESS:LEN=n")
    parts = spec.split(":")
    m = _AREA.match(parts[0])
    if not m:
        raise ScriptError(line, f"area {parts[0]!r}: DBn, DXn, M, E, A, T or Z")
    if m.group(1):
        area = Area.DB if m.group(1).upper() == "DB" else Area.DX
        number = int(m.group(2))
    else:
        area, number = Area[m.group(3).upper()], 0
    if len(parts) < 2 or not parts[1]:
        raise ScriptError(line, f"{parts[0]} needs an address after the area")
    addr = parts[1]
    if area.block:
        up = addr.upper()
        if up.startswith("DW"):
            address = 2 * _number(addr[2:], "data word", line)
        elif up.startswith("OFF="):
            address = _number(addr[4:], "byte offset", line)
        else:
            raise ScriptError(line, f"address {addr!r} of {parts[0]}: DWn or OFF=n")
    else:
        address = _number(addr, f"{area.name} address", line)
    opts: dict[str, str] = {}
    for part in parts[2:]:
        key, eq, value = part.partition("=")
        key = key.strip().upper()
        if not eq:
            raise ScriptError(line, f"{part!r} is not KEY=value (LEN, CF, CPU, DATA, SEED)")
        if key not in ("LEN", "CF", "CPU", "DATA", "SEED"):
            raise ScriptError(line, f"unknown option {key!r}: LEN, CF, CPU, DATA or SEED")
        if key in opts:
            raise ScriptError(line, f"{key} is given twice")
        opts[key] = value.strip()
    if "LEN" not in opts:
        raise ScriptError(line, "LEN=n is missing")
    length = _number(opts["LEN"], "LEN", line)
    cf = None
    if "CF" in opts:
        m = re.match(r"^(\d+)\.(\d+)$", opts["CF"])
        if not m:
            raise ScriptError(line, f"CF={opts['CF']}: byte.bit, e.g. CF=12.3")
        cf = (int(m.group(1)), int(m.group(2)))
    cpu: int | None = 1
    if "CPU" in opts:
        cpu = None if opts["CPU"].lower() == "none" else _number(opts["CPU"], "CPU", line)
    data = None
    if "DATA" in opts:
        if op != "send":
            raise ScriptError(line, "DATA is for send only")
        text = opts["DATA"]
        if len(text) % 2 or not re.match(r"^[0-9A-Fa-f]*$", text):
            raise ScriptError(line, f"DATA={text}: an even number of hex digits")
        data = bytes.fromhex(text)
        if len(data) != length:
            raise ScriptError(line, f"DATA has {len(data)} bytes, LEN={length}")
    seed = DEFAULT_SEED
    if "SEED" in opts:
        if op != "send":
            raise ScriptError(line, "SEED is for send only")
        if data is not None:
            raise ScriptError(line, "SEED and DATA exclude each other")
        text = opts["SEED"]
        try:
            seed = int(text, 16) if text.lower().startswith("0x") else _number(text, "SEED", line)
        except ValueError:
            raise ScriptError(line, f"SEED={text}: a number 0..255 (decimal or 0x..)") from None
        if not 0 <= seed <= 255:
            raise ScriptError(line, f"SEED={text}: a number 0..255")
    return Request(op, area, number, address, length, cf, cpu, data, seed, spec, line)


def parse_line(text: str, line: int = 0) -> Request | Wait | None:
    """One script line: a Request, a Wait, or None for a blank or comment line."""
    body = text.split("#", 1)[0].strip()
    if not body:
        return None
    word, _, rest = body.partition(" ")
    word = word.lower()
    rest = rest.strip()
    if word == "wait":
        if not rest:
            raise ScriptError(line, "wait needs a number of milliseconds")
        return Wait(_number(rest, "wait time (ms)", line), line)
    if word in ("send", "fetch"):
        if " " in rest or "\t" in rest:
            raise ScriptError(line, f"one SPEC per line; {rest!r} has spaces in it")
        return parse_request(word, rest, line)
    raise ScriptError(line, f"{word!r} is not send, fetch or wait")


def parse_script(text: str) -> list[Request | Wait]:
    """Every item of a request script, in order; ScriptError names the first bad line."""
    out = []
    for i, raw in enumerate(text.splitlines(), 1):
        item = parse_line(raw, i)
        if item is not None:
            out.append(item)
    return out


# -- the active side's local checks and the request's frames ---------------------------------
def local_check(req: Request, readings: Rk512Readings = RK512_READINGS) -> Code | None:
    """The STATUS with which the FB or the CP refuses a request before anything is sent
    (§6.3.2, Table 6-4; Table 8-1 classes 03, 05; Table 8-2), None when it may go out:

    * a SEND to anything but a DB or DX: 16#0301 (invalid FB parameters);
    * LEN 0: 16#1E41; LEN over 1024: 16#0517 (reading n5);
    * DB/DX number 0 (reading n6) or above 255, a data word above 255 (offset above 511),
      an address above 255 for the other areas: 16#0514;
    * flag bit above 7: 16#0515; flag byte above 255: 16#0301 (255: "no flag");
    * CPU number above 4: 16#0516.
    """
    if req.op == "send" and not req.area.block:
        return Code.INVALID_FB_PARAMETERS
    if req.length <= 0:
        return Code.LEN_ILLEGAL
    if req.length > MAX_REQUEST_BYTES:
        return Code(readings.n5_len_over_1024_status)
    if req.area.block:
        if req.number == 0:
            return Code(readings.n6_db0_status)
        if req.number > 255 or req.address // 2 > 255:
            return Code.ADDRESS_OUT_OF_RANGE
    elif req.address > 255:
        return Code.ADDRESS_OUT_OF_RANGE
    if req.cf is not None:
        byte, bit = req.cf
        if bit > 7:
            return Code.INVALID_FLAG_BIT
        if byte > 255:
            return Code.INVALID_FB_PARAMETERS
    if req.cpu is not None and req.cpu > 4:
        return Code.CPU_NUMBER_TOO_HIGH
    return None


def request_header(req: Request, readings: Rk512Readings = RK512_READINGS) -> Header:
    """The first command header of a request that passed :func:`local_check`."""
    cf = req.cf if req.cf is not None and req.cf[0] != 255 else None
    return command_header(req.op, req.area, req.number, req.address, req.length, cf=cf, cpu=req.cpu,
                          counter_letter=readings.amb01_counter_letter,
                          send_dx_letter=readings.amb03_send_dx_letter,
                          cpu0_nibble=readings.amb22_cpu0_nibble_without_flag,
                          pad_byte_areas=readings.amb34_pad_byte_areas)


def send_payload(req: Request, header: Header) -> bytes:
    """The data a SEND puts on the wire: LEN bytes, padded with 00h to the header's length
    (an odd LEN to a DB/DX: §6.3.2 "Important notes")."""
    data = req.payload
    return data + bytes(header.nbytes - len(data))
