"""3964 / 3964R (manual §2.2; Figs. 2-5 to 2-12): the first procedure of the core."""

from __future__ import annotations

from dataclasses import fields
from typing import Any, Mapping

from ptpcert.model.app import Host
from ptpcert.model.errors import ParameterError
from ptpcert.model.hexbytes import hexstr, parse_hex
from ptpcert.procedure import Mutant, Procedure, ProcedureError
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.params import T_BLOCK, T_NAKTIM, Params3964
from ptpcert.procedures.p3964.model.station import Station3964

from .link import KEY_OF, LINK_KEYS, PRIME, block_end, link_values, prime_steps

def reference_profile(**overrides: Any):
    """The profile of ``ptpcert iut`` (3964R, low priority, CDT and ADT 20 ms, 6 attempts,
    echo, PARMRK, STATUS on stderr) with these [iut] keys changed: for tests, the kill
    matrix, benchmarks and the traceability matrix."""
    from ptpcert.profile import profile_from_dict

    base = dict(procedure="3964R", priority="low", character_delay_ms=20,
                acknowledgement_delay_ms=20, setup_attempts=6, transmission_attempts=6,
                send_trigger="echo", line_conditions="parmrk", status_from_stderr=True)
    base.update(overrides)
    xf = base.pop("expected_failures", {})
    return profile_from_dict({"iut": base, "expected_failures": xf})


GROUPS = ("start-up", "character-frame", "idle", "receive", "send", "release", "repetition", "conflict",
          "break", "character-error", "timing", "regression")


class P3964Procedure(Procedure):
    id = "p3964"
    rank = 10
    title = "3964/3964R"
    names = ("3964R", "3964")
    groups = GROUPS
    time_names = ("CDT", "ADT", "NAKTIM", "BLOCK", "JOB")
    #: JOB is no timer of the IUT's but a bound derived from its attempts (:meth:`timer_env`)
    iut_timers = ("CDT", "ADT", "NAKTIM", "BLOCK")
    #: a receiver's character delay time: the gap it still waits for a further character
    max_gap = "CDT"
    byte_names = {name: byte for byte, name in codec.CONTROL_NAMES.items()}
    readings = tuple(f"A{i}" for i in range(1, 28))
    #: the grade of the other reading of each open point the model can take either way
    #: (docs/readings.md gives the manual's text, both readings and why): A4 (is the setup
    #: counter reset per transmission attempt, Fig. 2-10), A13 (NAK after a character error
    #: in idle, Table 8-1 16#080C), A19 (the receiver waiting for a repetition, Fig. 2-12)
    #: and A21 (the deferred job after a failed conflict reception, Fig. 2-8) are
    #: informational; A17 (block length: before or after doubling, too long, empty; Table
    #: A-5, 16#0816) is non-strict; A6, A7, A10, A11, A12 and A23 are as good (pass).
    #: A14 (the buffer wait, 400 ms) is not listed: the other reading fails.
    reading_grades = {"A4": "informational", "A6": "pass", "A7": "pass", "A10": "pass", "A11": "pass",
                      "A12": "pass", "A13": "informational", "A17": "non-strict", "A19": "informational",
                      "A21": "informational", "A23": "pass"}
    requirements = ("echo",)
    #: no_buffer: the IUT's application never frees its receive buffer (Fig. 2-11), so an STX
    #: is answered with NAK after T_NAKTIM (16#080A); ``ptpcert iut --buffer full``
    setups = ("no_buffer",)
    reference_setups = {"no_buffer": "--buffer full"}
    #: prime: the tester delivers the payload as a conforming sender (STX, DLE, block, DLE)
    macro_steps = {"prime": PRIME}
    suite = "ptpcert.conformance.p3964"

    # -- profiles and parameters ----------------------------------------------------------
    def profile_schema(self):
        from .link import LINK_SCHEMA
        return LINK_SCHEMA

    def profile_keys(self) -> tuple[str, ...]:
        return tuple(LINK_KEYS)

    def params_from_profile(self, iut: dict[str, Any], tables: dict[str, dict[str, Any]]) -> Params3964:
        values = link_values(iut)
        try:
            return Params3964(procedure=values["procedure"], **{LINK_KEYS[k]: values[k] for k in LINK_KEYS})
        except ParameterError as exc:
            key = KEY_OF.get(exc.name, exc.name)
            raise ProcedureError(f"iut.{key}", str(exc).replace(exc.name, key, 1)) from None

    def reference_profile(self, **settings: Any):
        return reference_profile(**settings)

    def profile_dict(self, params: Params3964) -> dict[str, Any]:
        return {"procedure": params.procedure, **{k: getattr(params, p) for k, p in LINK_KEYS.items()}}

    def params_from_table(self, raw: dict[str, Any]) -> Params3964:
        try:
            return Params3964.from_dict(raw)
        except ParameterError as exc:
            raise ProcedureError(exc.name, str(exc)) from None
        except TypeError as exc:
            raise ProcedureError("", str(exc)) from None

    def params_table(self, params: Params3964) -> dict[str, Any]:
        d = params.to_dict()
        if d["baud_rate"] is None:
            d.pop("baud_rate")
        return d

    def params_with(self, params, **changes: Any):
        return params.with_(**changes)   # re-validated, with the model's own rules for a change

    def param_names(self) -> frozenset[str]:
        return frozenset(f.name for f in fields(Params3964) if f.init)

    def timer_env(self, params: Params3964) -> dict[str, float]:
        """The timers, and JOB: the longest one send job of the IUT can take with its attempts
        (Table 2-4), each transmission attempt with every setup attempt timing out, a block of
        1024 data DLEs (doubled) and ADT for the acknowledgement - for a window that must hold
        every attempt the profile allows."""
        char = params.char_time
        attempt = params.setup_attempts * (params.adt + 2 * char) + 2060 * char + params.adt + params.cdt
        return {"CDT": params.cdt, "ADT": params.adt, "CHAR": char,
                "NAKTIM": T_NAKTIM, "BLOCK": T_BLOCK, "JOB": params.transmission_attempts * attempt}

    def edge_timers(self, params: Params3964) -> tuple[float, ...]:
        return (params.cdt, params.adt)

    def startup_bytes(self, params: Params3964) -> bytes:
        return bytes((codec.NAK,))   # §6: one NAK at start-up

    def tester_params(self, params: Params3964, declared: Params3964 | None = None) -> Params3964:
        """A conforming partner: the other priority (§9), unless the vector declares the
        tester's parameters (then with the IUT's timers)."""
        if declared is not None:
            return declared.with_(cdt_ms=params.cdt_ms, adt_ms=params.adt_ms)
        return params.with_(priority="high" if params.priority == "low" else "low")

    # -- ptpcert iut -----------------------------------------------------------------------
    def add_iut_arguments(self, group) -> None:
        group.add_argument("--priority", choices=["low", "high"], default="low")
        group.add_argument("--adt-ms", type=int, default=None,
                           help="acknowledgement delay time (default 2000; 550 for 3964)")
        group.add_argument("--setup-attempts", type=int, default=6)
        group.add_argument("--transmission-attempts", type=int, default=6)
        group.add_argument("--buffer", choices=["free", "full"], default="free",
                           help="full: the application never frees the receive buffer, so every STX gets "
                                "NAK after 400 ms (the no_buffer setup)")

    def params_from_iut(self, args) -> Params3964:
        try:
            return Params3964(
                procedure=args.procedure, priority=args.priority,
                cdt_ms=220 if args.cdt_ms is None else args.cdt_ms, adt_ms=args.adt_ms,
                setup_attempts=args.setup_attempts, transmission_attempts=args.transmission_attempts,
                baud_rate=None if args.baud == 0 else args.baud, data_bits=args.data_bits,
                parity=args.parity, stop_bits=args.stop_bits)
        except ParameterError as exc:
            raise ProcedureError("", str(exc)) from None

    # -- steps ----------------------------------------------------------------------------
    def expand(self, step, params: Params3964) -> list:
        """``prime``: the tester delivers the payload as a conforming sender (STX, DLE,
        block, DLE)."""
        proc = params.procedure
        return prime_steps(step, proc, f"the tester delivers {hexstr(step.data)} as a conforming sender",
                           f"block: data, {block_end(proc)}")

    # -- models ---------------------------------------------------------------------------
    def station(self, params: Params3964, *, name: str = "iut", mutant: str | None = None,
                readings=None, explain: bool = False) -> Station3964:
        if mutant:
            m = self.mutants().get(mutant)
            if m is None:
                raise ProcedureError("mutant", f"unknown broken variant {mutant!r}; known: {', '.join(self.mutants())}")
            return m.make(params, name=name)
        if readings is None:
            return Station3964(params, name=name, explain=explain)
        return Station3964(params, readings, name=name, explain=explain)

    def host(self, station: Station3964, *, app: str = "echo", vector=None) -> Host:
        return Host(station, app)

    def sim_option_names(self) -> tuple[str, ...]:
        return self.SIM_OPTIONS + ("priority",)

    def sim_options(self, options: dict[str, str]):
        caps, options = super().sim_options(options)
        if options.get("priority", "low") not in ("low", "high"):
            raise ValueError("priority must be low or high")
        return caps, options

    def sim_params(self, params: Params3964, options: dict[str, str]) -> Params3964:
        if "priority" in options:
            return params.with_(priority=options["priority"])
        return params

    def sim_host(self, params: Params3964, vector, options: dict[str, str], readings=None) -> Host:
        host = super().sim_host(params, vector, options, readings)
        if vector is not None and vector.setup is not None and vector.setup[0] == "no_buffer":
            host.station.buffer_free = False
        return host

    def iut_host(self, params: Params3964, args) -> Host:
        host = super().iut_host(params, args)
        if args.buffer == "full":
            host.station.buffer_free = False
        for text in getattr(args, "send", ()):
            try:
                payload = parse_hex(text)
            except ValueError:
                raise ProcedureError("send", f"{text!r} is not hex bytes") from None
            # handed over before the switch-on: the job waits, and starts once the station is idle
            if not host.station.request_send(0.0, payload):
                raise ProcedureError("send", f"a block carries 1 to 1024 bytes, not {len(payload)}")
        return host

    def unsupported_reason(self, vector, profile, capabilities, factory) -> str | None:
        """A suite case that could not be built for the profile says why in
        ``extra.unsupported``; a vector whose steps need at least so many attempts (a
        repetition) names them in ``[extra.needs]`` (e.g. ``transmission_attempts = 2``)."""
        why = vector.extra.get("unsupported")
        if why:
            return why
        if profile is None:
            return None
        for key, least in vector.extra.get("needs", {}).items():
            have = getattr(profile.params, key)
            if have < least:
                return f"needs {key} >= {least} (its steps repeat); the profile has {have}"
        return None

    def partner_done(self, host: Host) -> bool:
        # waiting for a repetition looks like idle on the line (§8.5 item 7)
        st = host.station
        return (st.state in ("IDLE", "WAIT_REPETITION") and st.pending_jobs == 0
                and not st.transmitting)

    def echo_time_limit(self, params: Params3964, payloads: list[bytes]) -> float:
        blk = max(len(self.frame(e, params)) for e in payloads) * params.char_time
        return len(payloads) * (params.setup_attempts * (params.adt + blk) + 1.0) + 2.0

    def frame(self, payload: bytes, params: Params3964) -> bytes:
        return codec.frame(payload, params.procedure)

    def cross_check(self, v) -> tuple[str, str] | None:
        """Where both sides send and their STXs cross (``iut_role = "both"``: Fig. 2-8), the
        tester's script is itself checked: two model stations wired together - the IUT with
        the job the vector primes and its echo application, the tester (the other priority)
        with the block it sends, its STX crossing the IUT's - must put exactly the vector's
        bytes on the line, in its order, and deliver what it says. Returns (verdict, message)
        with verdict "pass", "fail" or "error"; None where that does not apply (one sender, a
        vector without a primed job of the IUT - e.g. a fuzz finding, where the IUT sends only
        by echo - or an STX the script sends well after the IUT's, which is a stimulus)."""
        from ptpcert.model.events import Delivered
        from ptpcert.model.link import Link
        from ptpcert.scenario import expand, timer_env

        primes = [s for s in v.steps if s.kind == "prime"]
        if v.iut_role != "both" or not primes:
            return None  # the IUT sends only what its echo application answers: no crossing of own jobs
        steps = [s for s in expand(v) if s.kind in ("send", "expect")][4 * len(primes):]
        try:
            own = primes[0].data
            first = next(i for i, s in enumerate(steps) if s.kind == "send")
            stx_at = steps[first].at.eval(timer_env(v))
            theirs = codec.parse_body(next(s.data for s in steps[first:] if s.kind == "send" and len(s.data) > 2),
                                      v.params.procedure)
        except (StopIteration, IndexError, codec.FrameError) as exc:
            return "error", f"both sides: no crossing setup to replay in the script ({exc})"
        if stx_at > 0:
            return None  # an STX sent after the IUT's has arrived is a stimulus, not a crossing
        tester_params = v.tester_params or v.params.with_(priority="high" if v.params.priority == "low" else "low")
        iut, tester = Station3964(v.params, name="iut"), Station3964(tester_params, name="tester")
        link = Link(iut, tester, echo={"iut"})
        link.power_on(0.0)
        link.run_until_quiet(1.0)
        t0 = link.now
        link.request(iut, own, at=t0)
        # the STXs cross: the tester's starts just before the IUT's has reached it, when the
        # script sends it (at once after receiving the IUT's, one character later on the line)
        link.request(tester, theirs, at=t0 + v.params.char_time * (1 - 1e-6))
        link.run_until_quiet(t0 + 600.0)
        got = [(w.src, w.byte) for w in link.wire if w.start >= t0 - 1e-9]
        want = [("tester" if s.kind == "send" else "iut", b) for s in steps for b in s.data]
        if got[:len(want)] != want:
            i = next((k for k, (a, b) in enumerate(zip(got, want)) if a != b), min(len(got), len(want)))
            show = lambda x: f"{x[0]} {x[1]:02X}" if x else "nothing"  # noqa: E731
            return "fail", (f"both sides: byte {i + 1} of the exchange is {show(want[i] if i < len(want) else None)} "
                            f"in the script, {show(got[i] if i < len(got) else None)} between two model stations")
        delivered = [own] + [e.payload for e in link.events_of(iut, Delivered)]
        echoed = [e.payload for e in link.events_of(tester, Delivered)]
        if delivered != list(v.expected.delivered) or echoed[1:] != list(v.expected.echo_after):
            return "fail", ("both sides: the model stations deliver " + ", ".join(hexstr(x) for x in delivered)
                            + " / echo " + ", ".join(hexstr(x) for x in echoed[1:]))
        return "pass", ""

    # -- line analysis --------------------------------------------------------------------
    def analyzer(self, params_a: Params3964, params_b: Params3964, *, apps=None, late_ms: float = 50.0):
        from ptpcert.procedures.p3964.analysis import P3964Analyzer
        return P3964Analyzer(self, {"a": params_a, "b": params_b}, dict(apps or {}), late_ms)
    # -- the traceability matrix --------------------------------------------------------
    def rule_settings(self) -> list[tuple[str, dict[str, Any], Any]]:
        """Both variants in both priorities with the default 8-bit frame, and 3964R with a
        7-bit frame, each at the bundled reference's timers."""
        out = []
        for proc, prio, bits in (("3964R", "low", 8), ("3964R", "high", 8), ("3964", "low", 8),
                                 ("3964", "high", 8), ("3964R", "low", 7)):
            values = {"procedure": proc, "priority": prio, "data_bits": bits}
            label = f"{proc} {prio}" + ("" if bits == 8 else f" {bits} data bits")
            out.append((label, values, reference_profile(**values)))
        return out

    def setting_values(self, params: Params3964) -> dict[str, Any]:
        return {"procedure": params.procedure, "priority": params.priority, "data_bits": params.data_bits}

    def chart(self):
        """The transition table of Figs. 2-9 to 2-12, as text and drawn (:mod:`.chart`)."""
        from . import chart
        return chart

    # -- broken variants and fuzzing ------------------------------------------------------
    def mutants(self) -> Mapping[str, Mutant]:
        from ptpcert.procedures.p3964 import mutants
        return mutants.MUTANTS

    def fuzz_kit(self):
        from .fuzz import FUZZ_KIT
        return FUZZ_KIT

    # -- the reports' view ------------------------------------------------------------------
    def report_view(self):
        """The control characters named by each case's procedure (3964 or 3964R)."""
        from .tokens import report_view
        return report_view(self.groups)
