"""Parameters of a CP 341 ASCII driver (§2.3.3: Tables 2-7, 2-8, 2-9, 2-10; Table A-7).

:class:`AsciiParams` is frozen and validated on construction. An invalid setting raises
:class:`~ptpcert.model.errors.ParameterError` naming the parameter, the value and the rule
it breaks, in one line. A parameter that the configuration does not use (end characters
without the end-character criterion, XON/XOFF codes without XON/XOFF flow control...) is
ignored, as the parameter tool greys it out (Table 2-7 footnotes 1 and 3, Table 2-9
footnotes 1, 3 and 4); it is not checked.

The field names are the keys of an ASCII IUT profile (``[iut]`` and ``[ascii]``), except the
character delay time, which the profile calls ``character_delay_ms`` (:data:`PROFILE_KEYS`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any, Mapping

from ptpcert.model.errors import ParameterError
from ptpcert.model.line import BAUD_RATES, PARITIES

END_CRITERIA = ("cdt", "end_chars", "fixed_length")
SEND_VARIANTS = ("up_to_end", "len_with_end", "len_append_end")
FLOW_CONTROLS = ("none", "xon_xoff", "rts_cts", "auto_v24")
INTERFACES = ("rs232c", "tty", "rs422", "rs485")

#: The receive buffer of the CP 341 (§2.2.4 "receive buffer"; Table 2-10).
BUFFER_BYTES = 1024
MAX_BUFFER_FRAMES = 250
#: Longest frame and longest send job (Table 6-2 LEN 1..1024; Table A-7).
MAX_FRAME = 1024
#: XOFF / RTS OFF once only this many characters are left in the buffer (§2.2.4
#: "data flow control").
XOFF_MARGIN = 50

#: Smallest character delay time per baud rate (Table 2-7).
MIN_CDT_MS = {300: 130, 600: 65, 1200: 32, 2400: 16, 4800: 8, 9600: 4,
              19200: 2, 38400: 2, 57600: 2, 76800: 2}
#: Default CDT (Table 2-7). Below the minimum at 300..4800 bit/s: see DEFAULT_CDT below.
DEFAULT_CDT_MS = 4
#: Longest CDT. Table 2-7 says 655350 ms (steps of 10 ms), Table A-7 65535 ms (steps of
#: 1 ms); Table 2-7's own minima (2, 4, 8, 16, 32, 65, 130 ms) and its default (4 ms) are
#: not multiples of 10. Reading Q1: any whole number of milliseconds from the baud rate's
#: minimum up to the larger bound, so that no setting either table allows is refused.
MAX_CDT_MS = 655_350
#: Wait time for XON / CTS = ON (Table 2-9: 20..655350 ms in steps of 10 ms; Table A-7
#: ends at 65535 ms). Reading Q2: the larger range.
XON_WAIT_RANGE_MS = (20, 655_350)
#: Time to RTS OFF and data output waiting time (Table 2-9: 0..655350 ms, steps of 10 ms).
V24_TIME_RANGE_MS = (0, 655_350)
TIME_STEP_MS = 10
#: The 20 mA TTY interface runs at most 19200 bit/s (Table 2-8 note; Table 1-2).
TTY_MAX_BAUD = 19200

#: profile key -> field, where they differ
PROFILE_KEYS = {"character_delay_ms": "cdt_ms"}


def default_cdt_ms(baud_rate: int) -> int:
    """The CDT used when none is given (reading Q3): the default of Table 2-7, 4 ms, raised
    to the baud rate's minimum where it lies below it (300..4800 bit/s)."""
    return max(DEFAULT_CDT_MS, MIN_CDT_MS[baud_rate])


def _is_int(v: Any) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


@dataclass(frozen=True)
class AsciiParams:
    """One ASCII driver's parameter set. Defaults are the manual's (Tables 2-7 to 2-10)
    where it gives one."""

    # -- character frame (Table 2-8)
    baud_rate: int = 9600
    data_bits: int = 8
    parity: str = "even"
    stop_bits: int = 1
    # -- protocol (Table 2-7)
    cdt_ms: int | None = None          # None: default_cdt_ms(baud_rate) (reading Q3)
    end_criterion: str = "cdt"         # "indicator for end of receive message frame"
    end_chars: tuple[int, ...] = (0x03,)  # one or two codes (Table A-7 "1 or 2")
    fixed_length: int = 240
    #: end-character criterion: what a send job puts on the line (§2.2.4; no parameter
    #: name or default in the tables, reading Q6)
    send_variant: str = "up_to_end"
    #: the CDT pause between sent frames; only the fixed-length pause can be switched off
    #: (§2.2.4; Preface; reading Q8)
    send_pause: bool = True
    # -- data flow control (Table 2-9)
    flow_control: str = "none"
    xon: int = 0x11
    xoff: int = 0x13
    xon_wait_ms: int = 20_000
    rts_off_delay_ms: int = 10         # "time to RTS OFF"
    data_output_wait_ms: int = 10      # "data output waiting time"
    # -- receive buffer (Table 2-10)
    buffer_frames: int = MAX_BUFFER_FRAMES
    prevent_overwrite: bool = True
    # -- interface variant (Table 1-2; Table 2-11)
    interface: str = "rs232c"
    # Derived, filled in by __post_init__.
    char_time: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        # -- character frame
        if self.interface not in INTERFACES:
            raise ParameterError("interface", self.interface, "one of " + ", ".join(INTERFACES))
        if self.baud_rate not in BAUD_RATES or isinstance(self.baud_rate, bool):
            raise ParameterError("baud_rate", self.baud_rate,
                                 "one of " + ", ".join(map(str, BAUD_RATES)) + " (Table 2-8)")
        if self.interface == "tty" and self.baud_rate > TTY_MAX_BAUD:
            raise ParameterError("baud_rate", self.baud_rate,
                                 f"the 20 mA TTY interface runs at most {TTY_MAX_BAUD} bit/s (Table 2-8)")
        if self.data_bits not in (7, 8) or isinstance(self.data_bits, bool):
            raise ParameterError("data_bits", self.data_bits, "7 or 8 (Table 2-8)")
        if self.parity not in PARITIES:
            raise ParameterError("parity", self.parity, "one of none, odd, even (Table 2-8)")
        if self.stop_bits not in (1, 2) or isinstance(self.stop_bits, bool):
            raise ParameterError("stop_bits", self.stop_bits, "1 or 2 (Table 2-8)")
        code_max = 0x7F if self.data_bits == 7 else 0xFF
        code_rule = (f"a code 00..{code_max:02X}h with {self.data_bits} data bits "
                     "(Tables 2-7/2-9 footnote 2)")
        # -- protocol
        if self.cdt_ms is None:
            set_(self, "cdt_ms", default_cdt_ms(self.baud_rate))
        low = MIN_CDT_MS[self.baud_rate]
        if not _is_int(self.cdt_ms) or not low <= self.cdt_ms <= MAX_CDT_MS:
            raise ParameterError("cdt_ms", self.cdt_ms,
                                 f"{low}..{MAX_CDT_MS} ms; the minimum at {self.baud_rate} bit/s "
                                 f"is {low} ms (Table 2-7)")
        if self.end_criterion not in END_CRITERIA:
            raise ParameterError("end_criterion", self.end_criterion,
                                 "one of " + ", ".join(END_CRITERIA) + " (Table 2-7)")
        chars = self.end_chars
        if isinstance(chars, (list, bytes, bytearray)):
            chars = tuple(chars)
        elif _is_int(chars):
            chars = (chars,)
        set_(self, "end_chars", chars)
        if self.end_criterion == "end_chars":
            if not isinstance(chars, tuple) or len(chars) not in (1, 2):
                raise ParameterError("end_chars", self.end_chars,
                                     "one or two end characters (Table 2-7; Table A-7)")
            for c in chars:
                if not _is_int(c) or not 0 <= c <= code_max:
                    raise ParameterError("end_chars", self.end_chars, "each end character " + code_rule)
        if self.end_criterion == "fixed_length":
            if not _is_int(self.fixed_length) or not 1 <= self.fixed_length <= MAX_FRAME:
                raise ParameterError("fixed_length", self.fixed_length,
                                     f"1..{MAX_FRAME} bytes (Table 2-7)")
        if self.end_criterion == "end_chars" and self.send_variant not in SEND_VARIANTS:
            raise ParameterError("send_variant", self.send_variant,
                                 "one of " + ", ".join(SEND_VARIANTS) + " (§2.2.4)")
        if not isinstance(self.send_pause, bool):
            raise ParameterError("send_pause", self.send_pause, "true or false")
        if self.end_criterion == "cdt" and not self.send_pause:
            raise ParameterError("send_pause", self.send_pause,
                                 "with the CDT criterion the pause between sent frames is always "
                                 "inserted; only the fixed-length pause can be switched off (§2.2.4)")
        # -- data flow control
        if self.flow_control not in FLOW_CONTROLS:
            raise ParameterError("flow_control", self.flow_control,
                                 "one of " + ", ".join(FLOW_CONTROLS) + " (Table 2-9)")
        if self.flow_control != "none" and self.interface == "rs485":
            raise ParameterError("flow_control", self.flow_control,
                                 "no data flow control with RS 485 (Table 2-9; Table 1-2)")
        if self.flow_control in ("rts_cts", "auto_v24") and self.interface != "rs232c":
            raise ParameterError("flow_control", self.flow_control,
                                 "RTS/CTS and automatic use of V.24 signals only with RS 232C "
                                 "(Table 2-9; Table 1-2)")
        if self.flow_control == "xon_xoff":
            for name in ("xon", "xoff"):
                v = getattr(self, name)
                if not _is_int(v) or not 0 <= v <= code_max:
                    raise ParameterError(name, v, "the " + name.upper() + " character must be " + code_rule)
            if self.xon == self.xoff:
                raise ParameterError("xoff", self.xoff, "XON and XOFF must be different characters (Table 2-9)")
            if self.end_criterion == "end_chars":
                for c in chars:
                    if c in (self.xon, self.xoff):
                        raise ParameterError(
                            "end_chars", self.end_chars,
                            "an end character cannot be the XON or XOFF code: both must stay out "
                            "of the user data (§2.2.4)")
        if self.flow_control in ("xon_xoff", "rts_cts"):
            self._check_time("xon_wait_ms", XON_WAIT_RANGE_MS)
        if self.flow_control == "auto_v24":
            self._check_time("rts_off_delay_ms", V24_TIME_RANGE_MS)
            self._check_time("data_output_wait_ms", V24_TIME_RANGE_MS)
        # -- receive buffer
        if not _is_int(self.buffer_frames) or not 1 <= self.buffer_frames <= MAX_BUFFER_FRAMES:
            raise ParameterError("buffer_frames", self.buffer_frames,
                                 f"1..{MAX_BUFFER_FRAMES} buffered receive frames (Table 2-10)")
        if not isinstance(self.prevent_overwrite, bool):
            raise ParameterError("prevent_overwrite", self.prevent_overwrite, "true or false")
        if not self.prevent_overwrite and self.buffer_frames != 1:
            raise ParameterError("prevent_overwrite", self.prevent_overwrite,
                                 "prevent overwrite = no only with buffer_frames = 1 (Table 2-10)")
        set_(self, "char_time", self.bits_per_char / self.baud_rate)

    def _check_time(self, name: str, bounds: tuple[int, int]) -> None:
        v = getattr(self, name)
        lo, hi = bounds
        if not _is_int(v) or not lo <= v <= hi or v % TIME_STEP_MS:
            raise ParameterError(name, v, f"{lo}..{hi} ms in steps of {TIME_STEP_MS} ms (Table 2-9)")

    # -- derived values -------------------------------------------------------------
    @property
    def bits_per_char(self) -> int:
        """Start bit + data bits + parity bit (if any) + stop bits (Table 2-8)."""
        return 1 + self.data_bits + (0 if self.parity == "none" else 1) + self.stop_bits

    @property
    def cdt(self) -> float:
        return self.cdt_ms / 1000.0

    @property
    def xon_wait(self) -> float:
        return self.xon_wait_ms / 1000.0

    @property
    def rts_off_delay(self) -> float:
        return self.rts_off_delay_ms / 1000.0

    @property
    def data_output_wait(self) -> float:
        return self.data_output_wait_ms / 1000.0

    @property
    def end_sequence(self) -> bytes:
        """The configured end character(s), in order (end-character criterion)."""
        return bytes(self.end_chars)

    @property
    def pauses_between_frames(self) -> bool:
        """Whether the driver holds a pause between two frames it sends (§2.2.4): always
        with the CDT criterion, with the fixed-length criterion unless switched off, never
        with the end-character criterion."""
        if self.end_criterion == "cdt":
            return True
        return self.end_criterion == "fixed_length" and self.send_pause

    @property
    def code_max(self) -> int:
        return 0x7F if self.data_bits == 7 else 0xFF

    def with_(self, **changes: Any) -> "AsciiParams":
        """A copy with some fields changed (re-validated). A CDT left at its default follows
        a new baud rate (reading Q3)."""
        if "baud_rate" in changes and "cdt_ms" not in changes and self.cdt_ms == default_cdt_ms(self.baud_rate):
            changes["cdt_ms"] = None
        return replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("char_time", None)
        d["end_chars"] = list(self.end_chars)
        return d

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "AsciiParams":
        known = {f.name for f in fields(cls) if f.init}
        unknown = sorted(set(data) - known)
        if unknown:
            raise ParameterError(unknown[0], data[unknown[0]],
                                 "not a parameter; known: " + ", ".join(sorted(known)))
        return cls(**data)

    @classmethod
    def from_profile(cls, iut: Mapping[str, Any], ascii: Mapping[str, Any]) -> "AsciiParams":
        """From the two tables of an IUT profile. Keys of ``[iut]`` that are not ASCII
        driver parameters (procedure, send_trigger...) are left to the profile; every key of
        ``[ascii]`` must be a parameter. An error names the profile key."""
        values: dict[str, Any] = {}
        back: dict[str, str] = {}
        known = {f.name for f in fields(cls) if f.init}
        for key, value in iut.items():
            name = PROFILE_KEYS.get(key, key)
            if name in known:
                values[name], back[name] = value, key
        for key, value in ascii.items():
            name = PROFILE_KEYS.get(key, key)
            if name not in known:
                raise ParameterError(f"ascii.{key}", value, "not an ASCII driver parameter")
            values[name], back[name] = value, key
        try:
            return cls(**values)
        except ParameterError as e:
            key = back.get(e.name, e.name)
            raise ParameterError(key, e.value, e.allowed) from None
