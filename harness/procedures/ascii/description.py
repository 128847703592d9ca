"""The ASCII driver (manual §2.2.4; Figs. 2-20 to 2-24; Tables 2-7 to 2-10): the third
procedure of the core.

An ASCII IUT is described by a profile with ``procedure = "ASCII"`` in ``[iut]`` (the CDT
and the character frame there) and its driver settings in ``[ascii]``::

    [iut]
    procedure = "ASCII"
    character_delay_ms = 20        # CDT: receive criterion/watchdog and the send pause
    baud_rate = 9600               # data_bits 7|8, parity, stop_bits as for 3964R
    send_trigger = "echo"          # "echo" | "none"
    line_conditions = "parmrk"
    status_from_stderr = true

    [ascii]
    end_criterion = "end_chars"    # "cdt" | "end_chars" | "fixed_length"
    end_chars = [0x03]             # one or two codes (end_chars criterion)
    fixed_length = 240             # fixed_length criterion
    send_variant = "up_to_end"     # "up_to_end" | "len_with_end" | "len_append_end" (§2.2.4)
    send_pause = true              # CDT pause between sent frames (cdt and fixed_length)
    flow_control = "xon_xoff"      # "none" | "xon_xoff" | "rts_cts" | "auto_v24"
    xon = 0x11
    xoff = 0x13
    xon_wait_ms = 2000
    buffer_frames = 250
    prevent_overwrite = true

    [iut.setups]
    slow_reader = "--echo-delay-ms 5000"

The echo application: every complete frame in the receive buffer is read, oldest first,
while no send job of the IUT's own runs, and handed back as one send job with LEN = the
frame's length, end character(s) included; the send side applies its variant, pause and
flow control.
"""

from __future__ import annotations

from dataclasses import fields
from typing import TYPE_CHECKING, Any, Mapping

from ptpcert.model.errors import ParameterError
from ptpcert.model.line import BAUD_RATES, LineSettings
from ptpcert.procedure import Mutant, Procedure, ProcedureError
from ptpcert.procedures.ascii.model.codec import char_name, send_bytes, split_frames
from ptpcert.procedures.ascii.model.params import (
    END_CRITERIA,
    FLOW_CONTROLS,
    INTERFACES,
    MAX_CDT_MS,
    MIN_CDT_MS,
    PROFILE_KEYS,
    SEND_VARIANTS,
    AsciiParams,
)
from ptpcert.procedures.ascii.model.readings import READINGS, TESTER_READINGS, frame_reaches_xoff
from ptpcert.procedures.ascii.settings import RuleSettings

if TYPE_CHECKING:   # the station and its host are imported where one is built (start-up)
    from ptpcert.procedures.ascii.model.app import AsciiHost
    from ptpcert.procedures.ascii.model.station import AsciiStation

#: [iut] keys of an ASCII profile besides the common ones (procedure, send_trigger...)
IUT_KEYS = ("character_delay_ms", "baud_rate", "data_bits", "parity", "stop_bits")
#: [ascii] keys
ASCII_KEYS = ("end_criterion", "end_chars", "fixed_length", "send_variant", "send_pause",
              "flow_control", "xon", "xoff", "xon_wait_ms", "buffer_frames", "prevent_overwrite",
              "interface", "rts_off_delay_ms", "data_output_wait_ms")
_FIELD_KEY = {v: k for k, v in PROFILE_KEYS.items()}

GROUPS = ("start-up", "end-criterion", "send", "flow-control", "buffer", "line-conditions", "regression")

#: a read delay of the slow reader in sim: when the setup does not name one (the issue's
#: example profile reads after 5 s)
SLOW_READER_MS = 5000
#: the transport capability RTS/CTS and automatic V.24 cases need (no transport has it yet)
MODEM_LINES = "modem_lines"


def _show(key: str, value: Any) -> str:
    """A refused value as the profile wrote it (character codes in hex)."""
    if key in ("xon", "xoff") and isinstance(value, int) and not isinstance(value, bool):
        return f"0x{value:02X}"
    if key == "end_chars" and isinstance(value, (tuple, list)):
        return "[" + ", ".join(f"0x{v:02X}" if isinstance(v, int) else repr(v) for v in value) + "]"
    return repr(value)


def parse_codes(text: str) -> tuple[int, ...]:
    """``"03"`` or ``"0D,0A"`` (hex) -> the codes."""
    out = []
    for part in str(text).replace(" ", ",").split(","):
        if part:
            out.append(int(part, 16))
    return tuple(out)


def parse_jobs(text: str) -> list[bytes]:
    """Send jobs for the ``send_job`` setup: hex payloads separated by commas, ``-`` for
    a job of LEN 0 (``"4142034445,-"``)."""
    jobs = []
    for part in str(text).split(","):
        part = part.strip()
        if part == "-":
            jobs.append(b"")
        elif part:
            jobs.append(bytes.fromhex(part))
    return jobs


def echo_frames(frames: list[bytes], params: AsciiParams) -> list[bytes]:
    """What a conforming partner (the tester) receives when an echo IUT sends ``frames``
    back: each job's characters (its send variant applied), split by the partner's end
    criterion; a job is a frame of its own with the CDT criterion (the pause separates
    them)."""
    out: list[bytes] = []
    for f in frames:
        wire = send_bytes(f, params)
        if wire is None:
            continue
        out += [p.data for p in split_frames(wire, params) if p.kind in ("frame", "fragment")]
    return out


#: the [iut.setups] of the bundled reference implementation (ptpcert iut --procedure ASCII)
REFERENCE_SETUPS = {"slow_reader": "--echo-delay-ms {ms}", "send_job": "--send={jobs}"}


def reference_profile(**settings: Any):
    """The profile of ``ptpcert iut --procedure ASCII`` with these settings (profile keys of
    [iut] and [ascii], e.g. ``end_criterion="end_chars"``; defaults: CDT 20 ms, 9600 8E1,
    echo, PARMRK, STATUS on stderr, both setups) - for tests, the kill matrix, benchmarks."""
    from ptpcert.profile import profile_from_dict

    iut: dict[str, Any] = dict(procedure="ASCII", character_delay_ms=20, send_trigger="echo",
                               line_conditions="parmrk", status_from_stderr=True, setups=dict(REFERENCE_SETUPS))
    table: dict[str, Any] = {}
    for key, value in settings.items():
        if key in IUT_KEYS or key in ("send_trigger", "line_conditions", "status_from_stderr", "setups"):
            iut[key] = value
        else:
            table[key] = value
    return profile_from_dict({"iut": iut, "ascii": table})


def iut_command(params: AsciiParams, *, mutant: str | None = None, python: str | None = None,
                parmrk: bool = True) -> str:
    """The ``ptpcert iut`` command line that runs the reference implementation (or a broken
    variant) with these parameters."""
    import shlex
    import sys

    words = [python or sys.executable, "-m", "ptpcert.cli", "iut", "--procedure", "ASCII",
             "--cdt-ms", str(params.cdt_ms), "--baud", str(params.baud_rate), "--data-bits", str(params.data_bits),
             "--parity", params.parity, "--stop-bits", str(params.stop_bits),
             "--end-criterion", params.end_criterion, "--end-chars", ",".join(f"{c:02X}" for c in params.end_chars),
             "--fixed-length", str(params.fixed_length), "--send-variant", params.send_variant,
             "--flow-control", params.flow_control, "--xon", f"{params.xon:02X}", "--xoff", f"{params.xoff:02X}",
             "--xon-wait-ms", str(params.xon_wait_ms), "--buffer-frames", str(params.buffer_frames),
             "--interface", params.interface]
    if not params.send_pause:
        words.append("--no-send-pause")
    if not params.prevent_overwrite:
        words.append("--overwrite")
    if parmrk:
        words.append("--parmrk")
    if mutant:
        words += ["--mutant", mutant]
    return " ".join(shlex.quote(w) for w in words)


class AsciiProcedure(RuleSettings, Procedure):
    id = "ascii"
    rank = 30
    suite = "ptpcert.conformance.ascii"
    title = "ASCII driver"
    names = ("ASCII",)
    tables = ("ascii",)
    groups = GROUPS
    time_names = ("CDT", "XONWAIT")
    #: a receiver's character delay time: the gap it still waits for a further character
    max_gap = "CDT"
    readings = tuple(f"Q{i}" for i in range(1, 29)) + ("d_hold", "d_break", "d_start_up")
    requirements = ("echo", MODEM_LINES)
    #: slow_reader: the application reads a stored frame only after a while (ptpcert iut
    #: --echo-delay-ms), so the buffer can fill; send_job: the IUT hands these jobs to its
    #: driver at start-up (ptpcert iut --send HEX,...), for the send rules an echo cannot
    #: reach (data after the end character, LEN 0 or 1025)
    setups = ("slow_reader", "send_job")
    reference_setups = REFERENCE_SETUPS

    # -- profiles and parameters ----------------------------------------------------------
    def reference_profile(self, **settings: Any):
        return reference_profile(**settings)

    def profile_schema(self):
        from .profile_keys import SCHEMA
        return SCHEMA

    def profile_keys(self) -> tuple[str, ...]:
        return IUT_KEYS

    def params_from_profile(self, iut: dict[str, Any], tables: dict[str, dict[str, Any]]) -> AsciiParams:
        own = {k: v for k, v in iut.items() if k != "procedure"}
        table = dict(tables.get("ascii", {}))
        for key in table:
            if key not in ASCII_KEYS:
                raise ProcedureError(f"ascii.{key}", "unknown key (allowed: " + ", ".join(ASCII_KEYS) + ")")
        where = {**{k: f"iut.{k}" for k in own}, **{k: f"ascii.{k}" for k in table}}
        values: dict[str, Any] = {}
        for key, value in {**own, **table}.items():
            values[PROFILE_KEYS.get(key, key)] = value
        if isinstance(values.get("end_chars"), int) and not isinstance(values.get("end_chars"), bool):
            values["end_chars"] = (values["end_chars"],)
        try:
            return AsciiParams(**values)
        except ParameterError as exc:
            key = _FIELD_KEY.get(exc.name, exc.name)
            raise ProcedureError(where.get(key, f"ascii.{key}"),
                                 f"{_show(key, exc.value)} is not allowed: {exc.allowed}") from None
        except TypeError as exc:
            raise ProcedureError("ascii", str(exc)) from None

    def profile_dict(self, params: AsciiParams) -> dict[str, Any]:
        d = params.to_dict()
        out = {"procedure": "ASCII", "character_delay_ms": d.pop("cdt_ms")}
        for k in ("baud_rate", "data_bits", "parity", "stop_bits"):
            out[k] = d.pop(k)
        out["ascii"] = d
        return out

    def params_from_table(self, raw: dict[str, Any]) -> AsciiParams:
        try:
            return AsciiParams.from_dict(raw)
        except ParameterError as exc:
            raise ProcedureError(exc.name, str(exc)) from None
        except TypeError as exc:
            raise ProcedureError("", str(exc)) from None

    def params_table(self, params: AsciiParams) -> dict[str, Any]:
        return params.to_dict()

    def params_with(self, params, **changes: Any):
        return params.with_(**changes)   # re-validated, with the model's own rules for a change

    def param_names(self) -> frozenset[str]:
        return frozenset(f.name for f in fields(AsciiParams) if f.init)

    def line(self, params: AsciiParams) -> LineSettings:
        return LineSettings(params.baud_rate, params.data_bits, params.parity, params.stop_bits)

    def char_time(self, params: AsciiParams) -> float:
        return params.char_time

    def timer_env(self, params: AsciiParams) -> dict[str, float]:
        return {"CDT": params.cdt, "CHAR": params.char_time, "XONWAIT": params.xon_wait}

    def edge_timers(self, params: AsciiParams) -> tuple[float, ...]:
        return (params.cdt,)

    def transmit_lead(self, params: AsciiParams) -> float:
        # §2.2.4 'automatic use of the V.24 signals' (Fig. 2-24): each send job sets RTS ON and
        # starts sending only when the data output waiting time is over; the job before it
        # ended only once RTS went OFF the time to RTS OFF after its last character
        if params.flow_control != "auto_v24":
            return 0.0
        return params.data_output_wait + params.rts_off_delay

    def startup_bytes(self, params: AsciiParams) -> bytes:
        # §2.2.4 "data flow control": XON once parameterised for XON/XOFF
        return bytes((params.xon,)) if params.flow_control == "xon_xoff" else b""

    def tester_params(self, params: AsciiParams, declared: AsciiParams | None = None) -> AsciiParams:
        """A conforming partner with the IUT's settings, except its CDT. With the CDT
        criterion it delimits the IUT's frames by the pause: its CDT is 0.6 of the IUT's
        (not below the baud rate's minimum), between the pause of more than the CDT the IUT
        keeps between frames and the gaps inside them (none, plus what real time adds).
        With the other criteria frames are delimited by end characters or length, and the
        CDT is only a watchdog: three times the IUT's plus 100 ms, so that a real-time IUT
        scheduled a little late is not taken to have broken its frame."""
        base = declared if declared is not None else params
        if base.end_criterion == "cdt":
            cdt = min(params.cdt_ms, max(MIN_CDT_MS[base.baud_rate], int(0.6 * params.cdt_ms)))
        else:
            cdt = min(MAX_CDT_MS, 3 * params.cdt_ms + 100)
        return base.with_(cdt_ms=cdt)

    def interleaved(self, params: AsciiParams) -> bytes:
        # reading Q15: an XON may also follow every read, not only an XOFF; and where one
        # frame can reach the XOFF threshold (a fixed length near 1024 bytes), the IUT holds
        # the tester in the middle of it (reading Q14), wherever a case sends one
        if params.flow_control != "xon_xoff":
            return b""
        return bytes((params.xon, params.xoff)) if frame_reaches_xoff(params) else bytes((params.xon,))

    def unsupported_reason(self, vector, profile, capabilities: frozenset[str], factory) -> str | None:
        if MODEM_LINES in vector.needs and MODEM_LINES not in capabilities:
            return ("needs the RS 232C modem lines (RTS, CTS, DTR, DSR), which no transport of this "
                    "harness carries")
        params = getattr(profile, "params", None)
        if isinstance(params, AsciiParams) and params.flow_control == "xon_xoff" \
                and vector.params.flow_control != "xon_xoff":
            # a vector written without XON/XOFF whose data hold a code the profile makes XON
            # or XOFF: those bytes are flow control here, not data (§2.2.4 'code transparency')
            held = sorted({params.xon, params.xoff} & _data_codes(vector))
            if held:
                return (f"its data contain {', '.join(f'{c:02X}' for c in held)}, which the profile makes XON/XOFF "
                        f"(xon = 0x{params.xon:02X}, xoff = 0x{params.xoff:02X}): flow control, not data")
        return None

    # -- models ---------------------------------------------------------------------------
    def station(self, params: AsciiParams, *, name: str = "iut", mutant: str | None = None,
                readings=None, explain: bool = False) -> AsciiStation:
        if mutant:
            m = self.mutants().get(mutant)
            if m is None:
                raise ProcedureError("mutant", f"unknown broken variant {mutant!r}; known: {', '.join(self.mutants())}")
            return m.make(params, name=name)
        from ptpcert.procedures.ascii.model.station import AsciiStation
        if readings is None:
            readings = TESTER_READINGS if name == "tester" else READINGS
        return AsciiStation(params, readings, name=name, explain=explain)

    def host(self, station: AsciiStation, *, app: str = "echo", vector=None, read_delay: float = 0.0) -> AsciiHost:
        from ptpcert.procedures.ascii.model.app import AsciiHost  # loaded where a station runs, not at start-up
        return AsciiHost(station, app, read_delay=read_delay)

    def sim_host(self, params: AsciiParams, vector, options: dict[str, str], readings=None) -> AsciiHost:
        station = self.station(params, mutant=options.get("mutant") or None, readings=readings)
        read_delay = 0.0
        setup = vector.setup if vector is not None else None
        if setup is not None and setup[0] == "slow_reader":
            read_delay = float(setup[1].get("ms", SLOW_READER_MS)) / 1000.0
        host = self.host(station, app=options.get("app", "echo"), read_delay=read_delay)
        if setup is not None and setup[0] == "send_job":
            for job in parse_jobs(setup[1].get("jobs", "")):
                station.request_send(0.0, job)
        return host

    def partner_done(self, host: AsciiHost) -> bool:
        return host.station.idle

    def echo_time_limit(self, params: AsciiParams, payloads: list[bytes]) -> float:
        per = sum((len(self.frame(p, params)) + 4) * params.char_time + 3 * params.cdt + self.transmit_lead(params)
                  for p in payloads)
        return 5.0 + 2 * per

    def frame(self, payload: bytes, params: AsciiParams) -> bytes:
        wire = send_bytes(payload, params)
        return bytes(payload) if wire is None else wire

    # -- ptpcert iut -----------------------------------------------------------------------
    def add_iut_arguments(self, group) -> None:
        group.add_argument("--end-criterion", choices=END_CRITERIA, default="cdt",
                           help="ASCII: how a received frame ends (default cdt)")
        group.add_argument("--end-chars", default="03", metavar="HEX[,HEX]",
                           help="ASCII: one or two end characters in hex (default 03)")
        group.add_argument("--fixed-length", type=int, default=240, help="ASCII: fixed frame length (default 240)")
        group.add_argument("--send-variant", choices=SEND_VARIANTS, default="up_to_end",
                           help="ASCII, end-character criterion: what a send job puts on the line")
        group.add_argument("--no-send-pause", action="store_true",
                           help="ASCII, fixed-length criterion: no CDT pause between sent frames")
        group.add_argument("--flow-control", choices=FLOW_CONTROLS, default="none", help="ASCII (default none)")
        group.add_argument("--xon", default="11", metavar="HEX", help="ASCII: XON code (default 11)")
        group.add_argument("--xoff", default="13", metavar="HEX", help="ASCII: XOFF code (default 13)")
        group.add_argument("--xon-wait-ms", type=int, default=20000, help="ASCII: wait time for XON (default 20000)")
        group.add_argument("--buffer-frames", type=int, default=250, help="ASCII: buffered receive frames (default 250)")
        group.add_argument("--overwrite", action="store_true",
                           help="ASCII: prevent overwrite = no (needs --buffer-frames 1)")
        group.add_argument("--interface", choices=INTERFACES, default="rs232c", help="ASCII (default rs232c)")
        group.add_argument("--echo-delay-ms", type=int, default=0,
                           help="ASCII: the application reads a stored frame only after it has been in the "
                                "receive buffer this long (the slow_reader setup)")

    def params_from_iut(self, args) -> AsciiParams:
        if args.baud == 0:
            raise ProcedureError("--baud", "the ASCII driver needs a baud rate (its CDT and pauses depend on it)")
        try:
            return AsciiParams(
                baud_rate=args.baud, data_bits=args.data_bits, parity=args.parity, stop_bits=args.stop_bits,
                cdt_ms=args.cdt_ms, end_criterion=args.end_criterion, end_chars=parse_codes(args.end_chars),
                fixed_length=args.fixed_length, send_variant=args.send_variant, send_pause=not args.no_send_pause,
                flow_control=args.flow_control, xon=int(args.xon, 16), xoff=int(args.xoff, 16),
                xon_wait_ms=args.xon_wait_ms, buffer_frames=args.buffer_frames,
                prevent_overwrite=not args.overwrite, interface=args.interface)
        except ParameterError as exc:
            raise ProcedureError("", str(exc)) from None
        except ValueError as exc:
            raise ProcedureError("", f"not a hex code: {exc}") from None

    def iut_host(self, params: AsciiParams, args) -> AsciiHost:
        import time

        if args.echo_delay_ms < 0:
            raise ProcedureError("--echo-delay-ms", "must not be negative")
        station = self.station(params, mutant=args.mutant)
        host = self.host(station, app=args.app, read_delay=args.echo_delay_ms / 1000.0)
        try:
            jobs = parse_jobs(",".join(getattr(args, "send", ())))
        except ValueError as exc:
            raise ProcedureError("--send", f"hex payloads separated by commas: {exc}") from None
        now = time.monotonic()
        for job in jobs:   # handed over before power-on: they start once the driver runs
            station.request_send(now, job)
        return host

    # -- reports --------------------------------------------------------------------------
    def describe_frames(self, transcript: list[dict[str, Any]], params: AsciiParams) -> list[dict[str, Any]]:
        """The frames each side sent, as a receiver with the IUT's settings delimits them:
        end characters and XON/XOFF named, fragments marked, and for each frame the CDT
        window after its last character (the pause that ends it, or its watchdog).

        Each frame and fragment carries ``marks``: its end character(s) by name, or the
        character that completes a fixed-length frame ("fixed length"), at the time its
        last stop bit ends; and ``windows``: the CDT from its last character, the pause
        that ends a frame under the CDT criterion and the watchdog under the others
        (§2.2.4, the receive end criteria)."""
        char = params.char_time
        flow = (params.xon, params.xoff) if params.flow_control == "xon_xoff" else ()
        out: list[dict[str, Any]] = []
        for side in ("tester", "iut"):
            timed = [(e["t"] - char, e["byte"]) for e in transcript
                     if e.get("dir") == side and e.get("kind") in ("byte", "char_error")]
            # frames and fragments take the characters other than XON/XOFF in turn: where
            # each of their characters ends, for the marks
            ends = [t + char for t, b in timed if b not in flow]
            k = 0
            for p in split_frames(timed, params):
                marks: list[dict[str, Any]] = []
                if p.kind in ("frame", "fragment"):
                    mine = ends[k:k + len(p.data)]
                    k += len(p.data)
                    if p.end_len and len(mine) == len(p.data):
                        marks = [{"t": round(t, 6), "name": char_name(b)}
                                 for t, b in zip(mine[-p.end_len:], p.data[-p.end_len:])]
                    elif (p.kind == "frame" and params.end_criterion == "fixed_length"
                          and mine and len(p.data) == params.fixed_length):
                        marks = [{"t": round(mine[-1], 6), "name": "fixed length"}]
                if p.kind in ("xon", "xoff"):
                    label = f"{p.kind.upper()} ({p.data[0]:02X})"
                else:
                    body = p.data[:len(p.data) - p.end_len]
                    text = " ".join(f"{b:02X}" for b in body[:16]) + (" ..." if len(body) > 16 else "")
                    if p.end_len:
                        text = (text + " " if text else "") + " ".join(f"<{char_name(b)}>" for b in p.data[len(body):])
                    what = "frame" if p.kind == "frame" else "fragment (incomplete)"
                    label = f"{what} {text} ({len(p.data)} byte{'s' if len(p.data) != 1 else ''})"
                t0 = None if p.start is None else round(p.start, 6)
                t1 = None if p.end is None else round(p.end, 6)
                if t0 is None or t1 is None:
                    continue
                item = {"dir": side, "t0": t0, "t1": t1, "label": label}
                if p.kind in ("frame", "fragment"):
                    item["cdt_until"] = round(t1 + params.cdt, 6)
                    item["windows"] = [{"t0": t1, "t1": item["cdt_until"], "name": "CDT"}]
                    if marks:
                        item["marks"] = marks
                out.append(item)
        out.sort(key=lambda f: f["t0"])
        return out

    # -- line analysis --------------------------------------------------------------------
    def analyzer(self, params_a: AsciiParams, params_b: AsciiParams, *, apps=None, late_ms: float = 50.0):
        from ptpcert.procedures.ascii.analysis import AsciiAnalyzer
        return AsciiAnalyzer(self, {"a": params_a, "b": params_b}, dict(apps or {}), late_ms)

    # -- broken variants and fuzzing ------------------------------------------------------
    def mutants(self) -> Mapping[str, Mutant]:
        from ptpcert.procedures.ascii.mutants import MUTANTS
        return MUTANTS

    def fuzz_kit(self):
        from .fuzz import FUZZ_KIT
        return FUZZ_KIT

    # -- the reports' view ------------------------------------------------------------------
    def report_view(self):
        """XON/XOFF and the end characters named as each case's settings give them."""
        from ptpcert.procedures.ascii.tokens import report_view
        return report_view(self.groups)


def _data_codes(vector) -> set[int]:
    """Every byte a vector's tester sends or expects as data."""
    out: set[int] = set()
    for step in vector.steps:
        if step.kind in ("send", "send_error", "expect"):
            out.update(step.data)
            for alt in step.alternatives:
                out.update(alt)
    exp = vector.expected
    for block in exp.delivered + exp.sent + exp.echo_after:
        out.update(block)
    return out


__all__ = ["AsciiProcedure", "GROUPS", "echo_frames", "parse_codes", "parse_jobs", "BAUD_RATES"]
