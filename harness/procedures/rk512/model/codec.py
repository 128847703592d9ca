"""Pure codec of the RK 512 frames (CP 341 manual §2.2.3, Tables 2-1 and 2-2; §6.3.2,
Tables 6-4 to 6-8; §8.4, Table 8-3).

An RK 512 frame is the user data of one 3964(R) block; the 3964(R) framing (STX, DLE
doubling, DLE ETX, BCC) is the link's business (:mod:`ptpcert.procedures.p3964.model.codec`). Every function
here is a function of its arguments: no state, no time, no I/O. Decoders accept any byte
values (the fuzzer feeds them garbage); only encoders check ranges.

Frame kinds (§2.2.3): byte 1 is 00h in a first frame and FFh in a continuation frame,
byte 2 is 00h, byte 3 is the command letter in a command and 00h in a response (the only
field that can tell the two apart), byte 4 the data type of a command or the error number
(REATEL) of a response.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from ptpcert.model.codes import Code

# -- constants of the frame formats (Tables 2-1, 2-2) -----------------------------------
FIRST = 0x00            # byte 1 of a first (command or response) frame
CONTINUATION = 0xFF     # byte 1 of a continuation frame
SEND_DB = 0x41          # byte 3 'A': SEND, destination a data block
SEND_DX = 0x4F          # byte 3 'O': SEND, destination an extended data block (S5)
FETCH = 0x45            # byte 3 'E': FETCH
COMMAND_LETTERS = frozenset((SEND_DB, SEND_DX, FETCH))
NO_FLAG = 0xFF          # byte 9 when no coordination flag is given
HEADER_LEN = 10         # a first command frame's header (Table 2-1)
SHORT_HEADER_LEN = 4    # continuation command header and every response (Tables 2-1, 2-2)
CHUNK = 128             # data bytes in every frame but the last (§2.2.3, Figs. 2-14/2-16)
MAX_REQUEST_BYTES = 1024  # one request at most (Table 6-4: LEN 1..1024; App. A.1)
MAX_FRAME = HEADER_LEN + CHUNK  # the largest RK 512 frame: 138 bytes


class Area(StrEnum):
    """The data types of byte 4, as the letter on the wire (Table 2-1). The counter letter
    is Z (5Ah): Table 2-1 prints "'C' (5AH)", C being the FB's English mnemonic."""

    DB = "D"   # data block, words
    DX = "X"   # extended data block (S5), words
    E = "E"    # input bytes
    A = "A"    # output bytes
    M = "M"    # flag (memory marker) bytes
    T = "T"    # timer cells, one word each
    Z = "Z"    # counter cells, one word each

    @property
    def code(self) -> int:
        return ord(self.value)

    @property
    def words(self) -> bool:
        """Length and address count words (DB, DX) or cells of one word (T, Z)."""
        return self in _WORD_AREAS

    @property
    def block(self) -> bool:
        """Addressed by a block number (byte 5) and a data word (byte 6)."""
        return self is Area.DB or self is Area.DX


_WORD_AREAS = frozenset((Area.DB, Area.DX, Area.T, Area.Z))
AREA_BY_CODE = {a.code: a for a in Area}
WORD_CODES = frozenset(a.code for a in _WORD_AREAS)

#: P_SND_RK's R_TYP (and P_RCV_RK's L_TYP) mnemonics -> data type (Tables 6-4, 6-6, 6-7,
#: 6-10): the English letters C (counters), I (inputs), Q/O (outputs), F (flags) stand for
#: the German wire letters Z, E, A, M.
R_TYP_AREAS = {
    "D": Area.DB, "X": Area.DX,
    "M": Area.M, "F": Area.M,
    "I": Area.E, "E": Area.E,
    "Q": Area.A, "O": Area.A, "A": Area.A,
    "C": Area.Z, "Z": Area.Z,
    "T": Area.T,
}


class FrameError(ValueError):
    """A frame is too short or malformed for the decoder asked for it."""


# -- command headers (Table 2-1) ----------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Header:
    """The ten bytes of a first command frame, as wire fields.

    ``number`` and ``address`` are bytes 5 and 6 (DB/DX number and data word; for the byte
    and cell areas the two bytes of the address), ``length`` bytes 7/8 (words for D, X, T, Z;
    bytes for E, A, M), ``cf_byte`` byte 9 and ``b10`` byte 10 (CPU number in the high
    nibble, coordination-flag bit in the low one). ``frame_id`` and ``byte2`` are bytes 1
    and 2, kept so that a decoded header re-encodes to the same bytes.
    """

    command: int
    dtype: int
    number: int
    address: int
    length: int
    cf_byte: int = NO_FLAG
    b10: int = 0xFF
    frame_id: int = FIRST
    byte2: int = 0x00

    def encode(self) -> bytes:
        for name in ("command", "dtype", "number", "address", "cf_byte", "b10", "frame_id", "byte2"):
            v = getattr(self, name)
            if not 0 <= v <= 0xFF:
                raise ValueError(f"header byte {name} = {v} is not a byte value (0..255)")
        if not 0 <= self.length <= 0xFFFF:
            raise ValueError(f"header length {self.length} does not fit bytes 7/8 (0..65535)")
        return bytes((self.frame_id, self.byte2, self.command, self.dtype, self.number,
                      self.address, self.length >> 8, self.length & 0xFF, self.cf_byte, self.b10))

    # -- derived views ------------------------------------------------------------------
    @property
    def is_send(self) -> bool:
        return self.command == SEND_DB or self.command == SEND_DX

    @property
    def is_fetch(self) -> bool:
        return self.command == FETCH

    @property
    def area(self) -> Area | None:
        """The data type of byte 4 (None for a letter that is not one)."""
        return AREA_BY_CODE.get(self.dtype)

    @property
    def nbytes(self) -> int:
        """User-data bytes of the whole request on the wire: 2 x length for word types,
        length for byte types (Table 2-1; §6.3.2 "Notes on timers and counters")."""
        return 2 * self.length if self.dtype in WORD_CODES else self.length

    @property
    def cpu(self) -> int:
        """High nibble of byte 10: the CPU number (0h: not given, with a flag; Fh: neither)."""
        return self.b10 >> 4

    @property
    def cf_bit(self) -> int:
        """Low nibble of byte 10: the flag bit (Fh: no flag)."""
        return self.b10 & 0x0F

    @property
    def flag(self) -> tuple[int, int] | None:
        """(byte, bit) of the coordination flag, None when byte 9 is FFh."""
        return None if self.cf_byte == NO_FLAG else (self.cf_byte, self.b10 & 0x0F)

    @property
    def continuation(self) -> bytes:
        """The 4-byte header of this request's continuation frames (§2.2.3)."""
        return bytes((CONTINUATION, 0x00, self.command, self.dtype))


def decode_header(frame: bytes) -> Header:
    """The header of a first command frame (its first ten bytes). Raises FrameError for a
    frame of fewer than ten bytes; the values are taken as they are, valid or not."""
    if len(frame) < HEADER_LEN:
        raise FrameError(f"a command header has {HEADER_LEN} bytes, the frame has {len(frame)}")
    f = frame
    return Header(f[2], f[3], f[4], f[5], (f[6] << 8) | f[7], f[8], f[9], f[0], f[1])


def flag_cpu_bytes(cf: tuple[int, int] | None, cpu: int | None, cpu0_nibble: int = 0x0) -> tuple[int, int]:
    """Bytes 9 and 10 per Table 2-1 and Fig. 2-13 (the CPU/flag matrix):

    ===========  ======  =======  ==========================
    CPU given    flag    byte 9   byte 10
    ===========  ======  =======  ==========================
    n (1..4)     no      FFh      n*16 + Fh ("only CPU 1": 1Fh)
    n            B.b     B        n*16 + b
    no           B.b     B        00h + b
    no           no      FFh      FFh
    ===========  ======  =======  ==========================

    ``cpu0_nibble`` is the high nibble sent for CPU number 0 without a flag (an open point:
    0h, the number as given, or Fh, "not given")."""
    if cf is None:
        b9, bit = NO_FLAG, 0x0F
    else:
        b9, bit = cf
    if cpu is None:
        hi = 0x0 if cf is not None else 0x0F
    elif cpu == 0 and cf is None:
        hi = cpu0_nibble
    else:
        hi = cpu
    return b9, (hi << 4) | bit


def command_header(op: str, area: Area | str, number: int, address: int, length: int, *,
                   cf: tuple[int, int] | None = None, cpu: int | None = 1,
                   counter_letter: int = 0x5A, send_dx_letter: int = SEND_DX,
                   cpu0_nibble: int = 0x0, pad_byte_areas: bool = False) -> Header:
    """The header for one request, from the request's own terms (the P_SND_RK parameters,
    §3.5 of our notes; §6.3.2, Tables 6-4 to 6-8):

    * ``op``: "send" or "fetch"; ``area``: an :class:`Area` (or its letter);
    * ``number``: the DB/DX number (ignored for the other areas);
    * ``address``: for DB/DX the S7 byte offset (R_OFFSET; rounded down to even, DW =
      offset / 2); otherwise the byte, timer or counter number, sent as a 16-bit value in
      bytes 5/6;
    * ``length``: LEN in bytes as on the FB. Word areas carry ceil(LEN / 2) words (an odd
      SEND is padded with one 00h, an odd FETCH asks for one byte more); byte areas LEN
      bytes (``pad_byte_areas`` rounds them up to even as well);
    * ``cf``: the coordination flag (R_CF_BYT, R_CF_BIT) or None; ``cpu``: R_CPU_NO or None.

    No range checks beyond what the bytes can hold: the local checks of the active side are
    :func:`ptpcert.procedures.rk512.model.requests.local_check`.
    """
    area = Area(area)
    if op == "send":
        command = SEND_DB if area is Area.DB else send_dx_letter if area is Area.DX else SEND_DB
    elif op == "fetch":
        command = FETCH
    else:
        raise ValueError(f"op {op!r}: send or fetch")
    dtype = counter_letter if area is Area.Z else area.code
    if op == "send" and area is Area.DX:
        dtype = Area.DB.code  # Table 2-1: byte 4 is only 'D' when sending
    if area.block:
        hi, lo = number, address // 2
    else:
        hi, lo = address >> 8, address & 0xFF
    if area.words:
        wire_len = (length + 1) // 2
    else:
        wire_len = length + (length & 1 if pad_byte_areas else 0)
    b9, b10 = flag_cpu_bytes(cf, cpu, cpu0_nibble)
    return Header(command, dtype, hi, lo, wire_len, b9, b10)


def psnd_header(SF: str, R_TYP: str, R_NO: int, R_OFFSET: int, LEN: int, *,
                R_CF_BYT: int = 255, R_CF_BIT: int = 0, R_CPU_NO: int | None = 1) -> Header:
    """The header P_SND_RK sends for its parameters (§6.3.2, Tables 6-4 to 6-8): SF 'S'
    (SEND) or 'F' (FETCH), R_TYP in any of the manual's mnemonics (:data:`R_TYP_AREAS`),
    R_CF_BYT 255 meaning "no coordination flag"."""
    op = {"S": "send", "F": "fetch"}.get(SF)
    if op is None:
        raise ValueError(f"SF {SF!r}: 'S' or 'F' (Table 6-4)")
    if R_TYP not in R_TYP_NAMES:
        raise ValueError(f"R_TYP {R_TYP!r}: one of {', '.join(sorted(R_TYP_NAMES))}")
    cf = None if R_CF_BYT == 255 else (R_CF_BYT, R_CF_BIT)
    return command_header(op, R_TYP_AREAS[R_TYP], R_NO, R_OFFSET, LEN, cf=cf, cpu=R_CPU_NO)


R_TYP_NAMES = frozenset(R_TYP_AREAS)


# -- frames ---------------------------------------------------------------------------------
def chunk_sizes(n: int) -> list[int]:
    """Data bytes per frame for a request of ``n`` bytes: 128 in every frame but the last,
    the rest in the last (§2.2.3: the first continuation starts with byte 129)."""
    if n <= 0:
        return [0]
    full, rest = divmod(n, CHUNK)
    return [CHUNK] * full + ([rest] if rest else [])


def send_frames(header: Header, data: bytes) -> list[bytes]:
    """The frames of a SEND: the header with data bytes 1..128, then continuation frames
    ``FF 00 b3 b4`` with the next 128 bytes each (§2.2.3, Figs. 2-13/2-14)."""
    data = bytes(data)
    first = header.encode() + data[:CHUNK]
    out = [first]
    cont = header.continuation
    for i in range(CHUNK, len(data), CHUNK):
        out.append(cont + data[i:i + CHUNK])
    return out


def fetch_frames(header: Header) -> list[bytes]:
    """The command frames of a FETCH: the 10-byte header, then one 4-byte continuation
    command per further 128 bytes of data (§2.2.3, Figs. 2-15/2-16)."""
    n = len(chunk_sizes(header.nbytes))
    return [header.encode()] + [header.continuation] * (n - 1)


def response(first: bool, reatel: int = 0, data: bytes = b"") -> bytes:
    """A (continuation) response frame: ``00|FF 00 00 REATEL`` + the FETCH data (Table 2-2)."""
    return bytes((FIRST if first else CONTINUATION, 0, 0, reatel)) + bytes(data)


_RESPONSE_HEADS = {(True, r): bytes((FIRST, 0, 0, r)) for r in range(256)}
_RESPONSE_HEADS.update({(False, r): bytes((CONTINUATION, 0, 0, r)) for r in range(256)})


def response_head(first: bool, reatel: int) -> bytes:
    """The 4 bytes of a response header (cached; the fast path of the stations)."""
    return _RESPONSE_HEADS[(first, reatel)]


@dataclass(frozen=True, slots=True)
class Response:
    frame_id: int   # byte 1: 00h first, FFh continuation (anything else is a structure error)
    reatel: int     # byte 4
    data: bytes     # bytes 5.. (FETCH data)

    @property
    def first(self) -> bool:
        return self.frame_id == FIRST


def decode_response(frame: bytes) -> Response:
    """A response frame's fields; FrameError for fewer than four bytes."""
    if len(frame) < SHORT_HEADER_LEN:
        raise FrameError(f"a response has at least {SHORT_HEADER_LEN} bytes, the frame has {len(frame)}")
    return Response(frame[0], frame[3], bytes(frame[4:]))


class Kind(StrEnum):
    """What a frame is, from bytes 1 and 3 (§2.2.3, Tables 2-1, 2-2)."""

    COMMAND = "command"                            # byte 1 00h, byte 3 not 00h
    CONTINUATION = "continuation"                  # byte 1 FFh, byte 3 not 00h
    RESPONSE = "response"                          # byte 1 00h, byte 3 00h
    CONTINUATION_RESPONSE = "continuation response"  # byte 1 FFh, byte 3 00h
    BAD_COMMAND = "command with a bad byte 1"      # byte 3 not 00h, byte 1 neither 00h nor FFh
    BAD_RESPONSE = "response with a bad byte 1"    # byte 3 00h, byte 1 neither 00h nor FFh
    SHORT = "short"                                # fewer than 3 bytes: cannot be told


def classify(frame: bytes) -> Kind:
    """The kind of a frame. Byte 3 separates commands (a command letter) from responses
    (00h): nothing else in the header can (§2.2.3); byte 1 separates first frames from
    continuations. Lengths are not judged here."""
    if len(frame) < 3:
        return Kind.SHORT
    b1, b3 = frame[0], frame[2]
    if b3:
        return Kind.COMMAND if b1 == FIRST else Kind.CONTINUATION if b1 == CONTINUATION else Kind.BAD_COMMAND
    return Kind.RESPONSE if b1 == FIRST else Kind.CONTINUATION_RESPONSE if b1 == CONTINUATION else Kind.BAD_RESPONSE


# -- REATEL <-> STATUS (§8.4, Table 8-3) -----------------------------------------------------
#: The error number in a response -> the event the requester reports (Table 8-3, class 09).
REATEL_STATUS: dict[int, Code] = {
    0x0A: Code.PARTNER_TYPE_OR_PLC_FAULT,       # 16#0905
    0x0C: Code.PARTNER_MEMORY_ACCESS,           # 16#0902
    0x10: Code.PARTNER_HEADER_BYTE1_4,          # 16#090B
    0x12: Code.PARTNER_REQUEST_NOT_PERMITTED,   # 16#0904
    0x14: Code.PARTNER_DB_ACCESS,               # 16#0903
    0x16: Code.PARTNER_HEADER_BYTE3,            # 16#090A
    0x2A: Code.PARTNER_NO_RESTART,              # 16#090D
    0x32: Code.PARTNER_DB_LOCKED,               # 16#0909
    0x34: Code.PARTNER_FRAME_LENGTH,            # 16#090C
    0x36: Code.PARTNER_SEQUENCE,                # 16#0908
}

#: The responder's class-06 (and 03) events -> the error number it sends (Table 8-3).
#: 16#0610 (frame too short) and 16#0612 (response not sent) have none (an open point).
STATUS_REATEL: dict[Code, int] = {
    Code.INVALID_FB_PARAMETERS: 0x0C,   # listed under 0Ch and 10h; the model never sends it
    Code.CMD_BYTE1_INVALID: 0x10,
    Code.CMD_BYTE3_INVALID: 0x16,
    Code.CMD_BYTE3_CHANGED: 0x16,
    Code.CMD_BYTE4_INVALID: 0x10,
    Code.CMD_BYTE4_CHANGED: 0x10,
    Code.DB_NUMBER_NOT_ALLOWED: 0x14,
    Code.START_ADDRESS_TOO_HIGH: 0x0C,
    Code.LENGTH_NOT_ALLOWED: 0x34,
    Code.FLAG_INVALID: 0x0C,
    Code.CPU_NUMBER_NOT_ALLOWED: 0x0C,
    Code.SEND_LENGTH_DIFFERS: 0x34,
    Code.FETCH_WITH_DATA: 0x34,
    Code.CP_NOT_READY: 0x2A,
    Code.PARTNER_SEQUENCE_ERROR: 0x36,
    Code.DB_LOCKED: 0x32,
    Code.FRAME_LENGTH_DIFFERS: 0x34,
}


def status_for_reatel(reatel: int) -> Code | None:
    """The requester's event for a REATEL: None for 00h (no error), the Table 8-3 event for
    a listed value, 16#090E ("unknown error number") for any other."""
    if reatel == 0:
        return None
    return REATEL_STATUS.get(reatel, Code.PARTNER_UNKNOWN_ERROR)


def reatels_for_status(code: int) -> list[int]:
    """Every REATEL a requester maps to ``code`` (class 09; 16#090E has no listed value)."""
    return sorted(r for r, c in REATEL_STATUS.items() if c == code)


# -- human labels ----------------------------------------------------------------------------
def _area_label(dtype: int, number: int, address: int, counter_letter: int = 0x5A) -> str:
    a = AREA_BY_CODE.get(dtype)
    if a is None:
        return f"type {dtype:02X}h"
    if a.block:
        return f"{a.name}{number} DW{address}"
    return f"{a.name} {(number << 8) | address}"


def describe(frame: bytes) -> str:
    """A short human label for a frame, for transcripts, diagrams and JUnit messages:
    "SEND DB10 DW0 100 bytes", "FETCH E 0 10 bytes", "continuation SEND 72 bytes",
    "response REATEL 00", "response REATEL 34h -> 16#090C". Never raises."""
    frame = bytes(frame)
    kind = classify(frame)
    n = len(frame)
    if kind is Kind.SHORT:
        return f"short frame ({n} byte{'s' if n != 1 else ''}: {frame.hex(' ').upper() or 'empty'})"
    if kind in (Kind.RESPONSE, Kind.CONTINUATION_RESPONSE, Kind.BAD_RESPONSE):
        prefix = {Kind.RESPONSE: "response", Kind.CONTINUATION_RESPONSE: "continuation response",
                  Kind.BAD_RESPONSE: f"response with byte 1 {frame[0]:02X}h"}[kind]
        if n < SHORT_HEADER_LEN:
            return f"{prefix}, too short ({n} bytes)"
        r = frame[3]
        text = f"{prefix} REATEL 00" if r == 0 else f"{prefix} REATEL {r:02X}h -> {status_for_reatel(r).text}"
        if n > SHORT_HEADER_LEN:
            text += f" + {n - SHORT_HEADER_LEN} data bytes"
        return text
    op = {SEND_DB: "SEND", SEND_DX: "SEND", FETCH: "FETCH"}.get(frame[2], f"command {frame[2]:02X}h")
    if kind is Kind.CONTINUATION:
        if n < SHORT_HEADER_LEN:
            return f"continuation {op}, too short ({n} bytes)"
        data = n - SHORT_HEADER_LEN
        return f"continuation {op}" + (f" {data} bytes" if data or op == "SEND" else "")
    prefix = "" if kind is Kind.COMMAND else f"byte 1 {frame[0]:02X}h: "
    if n < HEADER_LEN:
        return f"{prefix}{op}, too short ({n} bytes)"
    h = decode_header(frame)
    if h.command == SEND_DX and h.dtype == Area.DB.code:
        where = f"DX{h.number} DW{h.address}"
    else:
        where = _area_label(h.dtype, h.number, h.address)
    text = f"{prefix}{op} {where} {h.nbytes} bytes"
    data = n - HEADER_LEN
    if h.is_send and data != h.nbytes:
        text += f" ({data} in this frame)"
    elif not h.is_send and data:
        text += f" (+{data} data bytes)"
    flag = h.cf_byte != NO_FLAG
    if flag:
        text += f" CF {h.cf_byte}.{h.cf_bit}"
    cpu = h.cpu
    if (cpu == 0 and flag) or (h.b10 == 0xFF and not flag):
        text += " no CPU"
    elif cpu != 1:
        text += f" CPU {cpu}"
    return text
