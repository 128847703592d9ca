"""RK 512, the computer link (manual §2.2.3, §6.3.2, §8.3/8.4; Figs. 2-13 to 2-19): the
second procedure of the core. Every RK 512 frame is the user data of one 3964(R) block, so
the line below is the 3964(R) link; the tester plays the partner CPU/CP, in the passive role
(it sends SEND/FETCH, the IUT answers) and in the active role (the IUT issues the requests
of a request script, the tester answers them).

The interface to an RK 512 IUT:

* the profile: the ``[iut]`` keys of 3964R (priority, timers, attempts, line) and the
  ``[rk512]`` table (link, response_time_ms, roles, requests, memory, db_range, dx_range,
  db_bytes, byte_area_bytes, cell_area_cells, cell_fetch_limit_bytes, serves_dx_fetch);
  ``send_trigger = "none"``;
* ``{requests}`` in the exec:/pty: command is replaced by the path of the case's request
  script (one request per line, empty where the IUT has nothing to request);
* set-ups ``cpu_stop`` and ``flag_set`` (words appended to the command);
* stderr: ``STATUS 16#xxxx`` lines, and one ``RESULT <label> OK`` or ``RESULT <label>
  STATUS 16#xxxx`` per request, in order, a FETCH that succeeded preceded by ``FETCHED
  <label> <hex>``.

A vector's ``extra`` table carries ``requests`` (the script's lines), ``results`` (the
RESULT/FETCHED lines expected, in order; alternatives separated by `` || ``, a FETCHED line
ending in `` *`` accepts any data) and ``needs`` (what the IUT's memory must offer: ``db``,
``dx`` numbers, ``db_bytes``, ``byte_area_bytes``, ``cell_area_cells`` at least, ``pattern``
for the pattern start contents; ``setup_attempts`` at least; ``expressible``: the invalid
request the case hands the IUT, which its interface must be able to express;
``cell_fetch_bytes``: the bytes of timers/counters a partner's FETCH must be served;
``silent``: [rk512] keys the profile must leave out, as the vector accepts either reading of
them).
"""

from __future__ import annotations

import hashlib
import os
import shlex
from dataclasses import fields
from typing import Any, Mapping

from ptpcert.model.errors import ParameterError
from ptpcert.procedure import MacroStep, Mutant, Procedure, ProcedureError
from ptpcert.procedures.p3964.link import LINK_KEYS, PRIME, block_end, link_values, prime_steps
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.params import T_BLOCK, T_NAKTIM, Params3964
from ptpcert.procedures.rk512.frames import decode_blocks, describe_frame
from ptpcert.procedures.rk512.iut import iut_host, line_matches, script_lines, setup_host_args

# The RK 512 model is imported where it is used, so that a 3964 IUT process (ptpcert iut)
# does not load it at its start.

#: the case groups, in the manual's order: the link below (§2.2.2 as RK 512 uses it), the
#: passive side (Fig. 2-19: SEND, FETCH, header checks, sequence, monitoring time, the CPU's
#: state), the active side (Fig. 2-18: commands, responses, monitoring time), both at once
#: (Fig. 2-17)
GROUPS = ("link", "passive-send", "passive-fetch", "passive-header", "passive-sequence",
          "passive-timing", "passive-cpu", "active-command", "active-response", "active-timing",
          "quasi-full-duplex", "regression")

#: the open points of our list of the manual's ambiguities (AMB-01..37) and those found
#: while building the model (N1..N7): the names of Rk512Readings' fields
READING_NAMES = tuple(f"AMB-{i:02d}" for i in range(1, 38)) + tuple(f"N{i}" for i in range(1, 8))

_LINE_FIELDS = tuple(f.name for f in fields(Params3964) if f.init and f.name != "procedure")
_RK_FIELDS = ("link", "response_time_ms", "roles", "requests", "memory", "db_range", "dx_range", "db_bytes",
              "byte_area_bytes", "cell_area_cells", "inexpressible_requests", "cell_fetch_limit_bytes",
              "serves_dx_fetch")
_EMPTY_SCRIPT = "requests-none.txt"
RECEIVE = MacroStep(keys=frozenset({"after", "within", "optional", "absent_grade", "or", "or_grade", "or_end", "since",
                                    "note"}),
                    max_data=codec.MAX_BLOCK, defaults={"within": "ADT"})


class Rk512Procedure(Procedure):
    id = "rk512"
    rank = 20
    title = "RK 512"
    names = ("RK512",)
    tables = ("rk512",)
    groups = GROUPS
    #: TRES: the IUT's response monitoring time (the profile's, else 10 s); TRES_MIN: the
    #: shortest it may be (the profile's, else the figures' 5 s / 7 s / 10 s by baud rate,
    #: open point AMB-02): a response the tester holds back stays under TRES_MIN, a pause
    #: meant to outlast T_RES passes TRES
    time_names = ("CDT", "ADT", "NAKTIM", "BLOCK", "TRES", "TRES_MIN")
    #: a receiver's character delay time: the gap it still waits for a further character
    max_gap = "CDT"
    byte_names = {name: byte for byte, name in codec.CONTROL_NAMES.items()}
    readings = READING_NAMES
    #: cpu_stop: the partner CPU is in STOP (every command gets REATEL 2Ah, §7.3; Table 8-1
    #: 16#060D); flag_set: coordination flag {flag} (B.b) is set at the start and cleared by
    #: the application {reset_ms} ms after it was set (§6.3.2 "Using interprocessor
    #: communication flags")
    setups = ("cpu_stop", "flag_set")
    reference_setups = {"cpu_stop": "--cpu-stop", "flag_set": "--cf-set {flag}@{reset_ms}"}
    #: prime: the tester delivers a frame as a conforming 3964(R) sender; receive: the IUT
    #: sends one (or one of ``or``) and the tester receives it as a conforming receiver (the
    #: IUT's STX in [after, within], within ADT unless the vector says otherwise)
    macro_steps = {"prime": PRIME, "receive": RECEIVE}
    suite = "ptpcert.conformance.rk512"
    #: RK 512 IUTs are made to send by requests, not by echo
    send_triggers = ("none",)

    # -- profiles and parameters ----------------------------------------------------------
    def profile_schema(self):
        from .profile_keys import SCHEMA
        return SCHEMA

    def reference_profile(self, **settings: Any):
        """The profile of ``ptpcert iut --procedure RK512 --cdt-ms 20 --adt-ms 20 --parmrk
        --requests {requests}`` with its setups: the 3964R link at low priority, 6 attempts,
        T_RES 500 ms, the default memory; ``settings``: [iut] and [rk512] keys changed."""
        from ptpcert.profile import profile_from_dict
        iut: dict[str, Any] = dict(procedure="RK512", priority="low", character_delay_ms=20,
                                   acknowledgement_delay_ms=20, setup_attempts=6, transmission_attempts=6,
                                   send_trigger="none", line_conditions="parmrk", status_from_stderr=True,
                                   setups=dict(self.reference_setups))
        table: dict[str, Any] = {"response_time_ms": 500}
        iut_keys = set(self.profile_keys()) | {"send_trigger", "line_conditions", "status_from_stderr", "setups"}
        for key, value in settings.items():
            (iut if key in iut_keys else table)[key] = value
        return profile_from_dict({"iut": iut, "rk512": table})

    def profile_keys(self) -> tuple[str, ...]:
        return tuple(LINK_KEYS)

    def params_from_profile(self, iut: dict[str, Any], tables: dict[str, dict[str, Any]]):
        from ptpcert.procedures.rk512.model import Rk512Params
        values = link_values(iut)
        table = dict(tables.get("rk512", {}))
        link = table.get("link", "3964R")
        if link not in ("3964R", "3964"):
            raise ProcedureError("rk512.link", f"{link!r} is not allowed; allowed values: \"3964R\", \"3964\"")
        key_of = {v: k for k, v in LINK_KEYS.items()}
        try:
            line = Params3964(procedure=link, **{LINK_KEYS[k]: values[k] for k in LINK_KEYS})
        except ParameterError as exc:
            key = key_of.get(exc.name, exc.name)
            raise ProcedureError(f"iut.{key}", str(exc).replace(exc.name, key, 1)) from None
        try:
            return Rk512Params.from_dict(table, line)
        except ParameterError as exc:
            raise ProcedureError(f"rk512.{exc.name}", str(exc)) from None
        except TypeError as exc:
            raise ProcedureError("rk512", str(exc)) from None

    def profile_dict(self, params: Any) -> dict[str, Any]:
        line = params.line
        return {"procedure": self.names[0], **{k: getattr(line, p) for k, p in LINK_KEYS.items()},
                "rk512": params.to_dict()}

    def params_from_table(self, raw: dict[str, Any]):
        """A vector's [params]: the link's parameters (priority, cdt_ms, adt_ms, attempts,
        baud_rate and character frame) and the [rk512] keys, in one table."""
        from ptpcert.procedures.rk512.model import Rk512Params
        raw = dict(raw)
        if "procedure" in raw:
            raise ProcedureError("procedure", "RK 512 vectors name the link as link = \"3964R\" or \"3964\"")
        line_keys = {k: raw.pop(k) for k in list(raw) if k in _LINE_FIELDS}
        link = raw.get("link", "3964R")
        if link not in ("3964R", "3964"):   # the link names the procedure below: said as the key written
            raise ProcedureError("link", f"link = {link!r} is not allowed: one of \"3964R\", \"3964\"")
        try:
            line = Params3964(procedure=link, **line_keys)
            return Rk512Params.from_dict(raw, line)
        except ParameterError as exc:
            raise ProcedureError(exc.name, str(exc)) from None
        except TypeError as exc:
            raise ProcedureError("", str(exc)) from None

    def params_table(self, params: Any) -> dict[str, Any]:
        d = {"link": params.link}
        line = params.line.to_dict()
        line.pop("procedure")
        if line["baud_rate"] is None:
            line.pop("baud_rate")
        d.update(line)
        rk = params.to_dict()
        rk.pop("link")
        d.update(rk)
        return d

    def params_with(self, params, **changes: Any):
        return params.with_(**changes)   # re-validated, with the model's own rules for a change

    def param_names(self) -> frozenset[str]:
        return frozenset(_LINE_FIELDS) | frozenset(_RK_FIELDS) | {"procedure"}

    def line(self, params: Any):
        return params.line.line

    def timer_env(self, params: Any) -> dict[str, float]:
        return {"CDT": params.cdt, "ADT": params.adt, "CHAR": params.char_time,
                "NAKTIM": T_NAKTIM, "BLOCK": T_BLOCK, "TRES": params.t_res,
                "TRES_MIN": params.t_res_min}

    def edge_timers(self, params: Any) -> tuple[float, ...]:
        return (params.cdt, params.adt)

    def startup_bytes(self, params: Any) -> bytes:
        return bytes((codec.NAK,))   # the link's NAK at start-up (§2.2.2)

    def tester_params(self, params: Any, declared: Any | None = None) -> Any:
        """A conforming partner: the other priority (§2.2.2 "Initialization conflict"), with
        the IUT's timers, unless the vector declares the tester's parameters."""
        if declared is not None:
            return declared.with_(cdt_ms=params.line.cdt_ms, adt_ms=params.line.adt_ms)
        return params.with_(priority="high" if params.priority == "low" else "low")

    # -- steps ----------------------------------------------------------------------------
    def expand(self, step, params: Any) -> list:
        """``prime``: the tester delivers the frame as a conforming 3964(R) sender (STX,
        DLE, block, DLE). ``receive``: the IUT sends the frame and the tester receives it as
        a conforming receiver: the IUT's STX in the step's window, the tester's DLE at once,
        the block (its first character within CDT, §2.2.2 "Receiving data"), the tester's
        DLE. A receive's ``or_end`` counts the steps after its DLE."""
        from ptpcert.scenario import Expr, Step

        proc = params.procedure
        end = block_end(proc)
        if step.kind == "prime":
            return prime_steps(step, proc, f"the tester sends {describe_frame(step.data)}",
                               f"block: {describe_frame(step.data)}; {end}")
        note = step.note or f"the IUT sends {describe_frame(step.data)}"
        alts = tuple(codec.body(a, proc) for a in step.alternatives)
        return [
            Step("expect", bytes([codec.STX]), after=step.after, within=step.within, since=step.since,
                 optional=step.optional, absent_grade=step.absent_grade, skip=3 if step.optional else 0,
                 note=f"STX ({note})"),
            Step("send", bytes([codec.DLE]), note="DLE: the tester is ready to receive"),
            Step("expect", codec.body(step.data, proc), within=Expr("CDT"), alternatives=alts,
                 alt_grade=step.alt_grade, or_end=None if step.or_end is None else step.or_end + 1,
                 note=(f"{step.note}; " if step.note else "") + f"block: {describe_frame(step.data)}"
                      + (" (or " + " or ".join(describe_frame(a) for a in step.alternatives) + ")"
                         if step.alternatives else "") + f"; {end}"),
            Step("send", bytes([codec.DLE]), note="DLE: the tester accepts the block"),
        ]

    # -- models ---------------------------------------------------------------------------
    def station(self, params, *, name: str = "iut", mutant: str | None = None, readings=None,
                explain: bool = False):
        from ptpcert.procedures.rk512.model import RK512_READINGS, Rk512Station
        if mutant:
            m = self.mutants().get(mutant)
            if m is None:
                raise ProcedureError("mutant", f"unknown broken variant {mutant!r}; known: {', '.join(self.mutants())}")
            return m.make(params, name=name)
        return Rk512Station(params, readings or RK512_READINGS, name=name, explain=explain)

    def host(self, station, *, app: str = "script", vector=None):
        """The station with its application: the vector's request script (none without a
        vector: the tester's partner) and its set-up."""
        script = "\n".join(script_lines(vector))
        return iut_host(station, script, **setup_host_args(vector))

    def apps(self) -> tuple[str, ...]:
        return ("script",)

    def sim_option_names(self) -> tuple[str, ...]:
        # response_time_ms: the simulated IUT's own T_RES where the profile leaves it open
        # (e.g. the figures' 5 s under a profile that declares none, AMB-02)
        return self.SIM_OPTIONS + ("priority", "response_time_ms")

    def sim_options(self, options: dict[str, str]):
        options = dict(options)
        options.setdefault("app", "script")
        caps, options = super().sim_options(options)
        if options.get("priority", "low") not in ("low", "high"):
            raise ValueError("priority must be low or high")
        if not options.get("response_time_ms", "10").isdigit():
            raise ValueError("response_time_ms must be a whole number of milliseconds")
        return caps, options

    def sim_params(self, params: Any, options: dict[str, str]) -> Any:
        if "priority" in options:
            params = params.with_(priority=options["priority"])
        if "response_time_ms" in options:
            params = params.with_(response_time_ms=int(options["response_time_ms"]))
        return params

    def sim_host(self, params, vector, options: dict[str, str], readings=None):
        station = self.station(params, mutant=options.get("mutant") or None, readings=readings)
        return self.host(station, vector=vector)

    def partner_done(self, host) -> bool:
        return host.station.idle and host.done

    def echo_time_limit(self, params: Any, payloads: list[bytes]) -> float:
        blk = max(len(self.frame(e, params)) for e in payloads) * params.char_time
        return len(payloads) * (params.line.setup_attempts * (params.adt + blk) + 1.0) + 2.0

    def frame(self, payload: bytes, params: Any) -> bytes:
        return codec.frame(payload, params.procedure)

    # -- IUT processes --------------------------------------------------------------------
    def add_iut_arguments(self, group) -> None:
        group.add_argument("--link", choices=["3964R", "3964"], default="3964R",
                           help="RK 512: the link procedure below (default 3964R)")
        group.add_argument("--response-time-ms", type=int, default=None, metavar="MS",
                           help="RK 512: T_RES, the response monitoring time of both sides (default 10000, "
                                "the CP 341's value at every baud rate)")
        group.add_argument("--requests", metavar="FILE",
                           help="RK 512: the request script (one send/fetch/wait per line) the IUT runs from its start")
        group.add_argument("--cpu-stop", action="store_true",
                           help="RK 512: the CPU is in STOP: every partner command gets REATEL 2Ah")
        group.add_argument("--cf-set", action="append", default=[], metavar="B.b@MS",
                           help="RK 512: coordination flag B.b is set at the start and cleared MS ms after it "
                                "was set (repeatable)")
        group.add_argument("--db-range", default="1-199", metavar="FIRST-LAST",
                           help="RK 512: the DB numbers that exist (default 1-199)")
        group.add_argument("--dx-range", default="1-199", metavar="FIRST-LAST",
                           help="RK 512: the DX numbers that exist (default 1-199; 'none': no DX)")
        group.add_argument("--db-bytes", type=int, default=512, help="RK 512: the size of every DB/DX (default 512)")
        group.add_argument("--byte-area-bytes", type=int, default=256,
                           help="RK 512: the size of the flag, input and output areas (default 256)")
        group.add_argument("--cell-area-cells", type=int, default=256,
                           help="RK 512: the number of timers and of counters (default 256)")

    @staticmethod
    def _range(text: str, name: str) -> tuple[int, ...]:
        if text.strip().lower() == "none":
            return ()
        try:
            lo, hi = (int(x) for x in text.split("-"))
        except ValueError:
            raise ProcedureError(name, f"{text!r}: FIRST-LAST, e.g. 1-199") from None
        return (lo, hi)

    def params_from_iut(self, args):
        from ptpcert.procedures.rk512.model import Rk512Params
        try:
            adt = getattr(args, "adt_ms", None)
            line = Params3964(
                procedure=args.link, priority=getattr(args, "priority", "low"),
                cdt_ms=220 if args.cdt_ms is None else args.cdt_ms, adt_ms=adt,
                setup_attempts=getattr(args, "setup_attempts", 6),
                transmission_attempts=getattr(args, "transmission_attempts", 6),
                baud_rate=None if args.baud == 0 else args.baud, data_bits=args.data_bits,
                parity=args.parity, stop_bits=args.stop_bits)
            return Rk512Params(link=args.link, line=line, response_time_ms=args.response_time_ms,
                               db_range=self._range(args.db_range, "--db-range"),
                               dx_range=self._range(args.dx_range, "--dx-range"),
                               db_bytes=args.db_bytes, byte_area_bytes=args.byte_area_bytes,
                               cell_area_cells=args.cell_area_cells)
        except ParameterError as exc:
            raise ProcedureError("", str(exc)) from None

    def iut_host(self, params, args):
        from ptpcert.procedures.rk512.model import ScriptError, parse_cf_set, parse_script
        script = ""
        if args.requests:
            try:
                with open(args.requests, encoding="utf-8") as f:
                    script = f.read()
            except OSError as exc:
                raise ProcedureError("--requests", f"{args.requests}: {exc.strerror}") from None
            try:
                parse_script(script)
            except ScriptError as exc:
                raise ProcedureError("--requests", f"{args.requests}: {exc}") from None
        try:
            cf = [parse_cf_set(x) for x in args.cf_set]
        except ValueError as exc:
            raise ProcedureError("--cf-set", str(exc)) from None
        station = self.station(params, mutant=args.mutant)
        try:
            return iut_host(station, script, cpu_stop=args.cpu_stop, cf_set=cf)
        except ValueError as exc:
            raise ProcedureError("--cf-set", str(exc)) from None

    def command(self, template: str, vector, setups: Mapping[str, str], workdir: str) -> str | None:
        """The case's request script written into ``workdir`` (an empty one where the IUT
        requests nothing) and its path put for ``{requests}``; the set-up's words appended."""
        if "{requests}" in template:
            lines = script_lines(vector)
            if lines:
                text = "\n".join(lines) + "\n"
                name = f"requests-{hashlib.sha256(text.encode()).hexdigest()[:16]}.txt"
            else:
                text, name = "", _EMPTY_SCRIPT
            path = os.path.join(workdir, name)
            if not os.path.exists(path):
                with open(path, "w", encoding="utf-8") as f:
                    f.write(text)
            template = template.replace("{requests}", shlex.quote(path))
        return super().command(template, vector, setups, workdir)

    def start_ahead(self, vector) -> bool:
        """An IUT with requests starts them at its start, and a flag set-up runs its reset
        time from there: such a case's IUT starts with the case."""
        if vector is None:
            return True
        return not script_lines(vector) and not (vector.setup and vector.setup[0] == "flag_set")

    def unsupported_reason(self, vector, profile, capabilities, factory) -> str | None:
        from .applies import unsupported_reason
        return unsupported_reason(self, vector, profile, capabilities, factory)

    def judge_reports(self, vector, lines: list[str]) -> list[str]:
        """The RESULT and FETCHED lines the IUT printed against the vector's ``results``, in
        order; other lines are not judged here."""
        want = [str(x) for x in vector.extra.get("results", [])]
        got = [x.strip() for line in lines for x in line.split("\n")
               if x.strip().startswith(("RESULT ", "FETCHED "))]
        for i, w in enumerate(want):
            if i >= len(got):
                return [f"expected the line {w!r}; the IUT reported "
                        + (f"only {len(got)} RESULT/FETCHED line(s)" if got else "no RESULT/FETCHED line")]
            if not line_matches(w, got[i]):
                return [f"expected {w!r}; the IUT reported {got[i]!r}"]
        if len(got) > len(want):
            return [f"the IUT reported more than expected: {got[len(want)]!r}"]
        return []

    # -- reports --------------------------------------------------------------------------
    def describe_frames(self, transcript: list[dict[str, Any]], params: Any) -> list[dict[str, Any]]:
        return decode_blocks(transcript, params.procedure == "3964R")

    # -- line analysis --------------------------------------------------------------------
    def analyzer(self, params_a: Any, params_b: Any, *, apps=None, late_ms: float = 50.0):
        """Both stations judged as the 3964(R) stations that carry the RK 512 frames (blocks,
        acknowledgements, retries, timers, §2.2.2; a frame a station sends is a send job the
        line reveals) and as RK 512 stations: what the frames say (command headers, Table 2-1;
        continuation frames; responses and their REATEL, Table 2-2, Table 8-3; T_RES; nesting
        depth 1, §2.2.3 'Quasi-full-duplex'), judged by the model's own RK 512 layer
        (:mod:`ptpcert.procedures.rk512.analysis`). The memory behind a station is not on the
        line: data values are not judged."""
        from ptpcert.procedures.rk512.analysis import Rk512Analyzer
        from ptpcert.registry import by_id
        return Rk512Analyzer(by_id("p3964"), {"a": params_a, "b": params_b}, late_ms)

    # -- the traceability matrix ------------------------------------------------------------
    #: the areas of the settings the matrix is computed for: large enough for every case (a
    #: 1024-byte request of every type), as the profile of a CP 341-sized partner would be
    _RULE_AREAS = {"db_bytes": 2048, "byte_area_bytes": 2048, "cell_area_cells": 1024}

    def rule_settings(self) -> list[tuple[str, dict[str, Any], Any]]:
        """Both links in both priorities with both roles and DX blocks; then, over 3964R at
        low priority, an IUT that is only passive, one that is only active, and one without
        DX blocks - each at the bundled reference's timers, with every set-up."""
        out = []
        for label, settings in (
                ("3964R low", {"link": "3964R", "priority": "low"}),
                ("3964R high", {"link": "3964R", "priority": "high"}),
                ("3964 low", {"link": "3964", "priority": "low"}),
                ("3964 high", {"link": "3964", "priority": "high"}),
                ("3964R low passive-only", {"link": "3964R", "priority": "low", "roles": ["passive"]}),
                ("3964R low active-only", {"link": "3964R", "priority": "low", "roles": ["active"]}),
                ("3964R low no-DX", {"link": "3964R", "priority": "low", "dx_range": []})):
            profile = self.reference_profile(**self._RULE_AREAS, **settings)
            out.append((label, self.setting_values(profile.params), profile))
        return out

    def setting_values(self, params: Any) -> dict[str, Any]:
        return {"link": params.link, "priority": params.priority, "roles": tuple(params.roles),
                "dx": "present" if params.dx_range else "absent"}

    def setting_from_profile(self, profile: Mapping[str, Any], dimensions) -> dict[str, Any]:
        values = super().setting_from_profile(profile, dimensions)
        table = profile.get("rk512", {})
        if "roles" in values:
            values["roles"] = tuple(values["roles"])
        if "dx_range" in table:
            values["dx"] = "present" if table["dx_range"] else "absent"
        return values

    # -- broken variants and fuzzing ------------------------------------------------------
    # -- ptpcert status -------------------------------------------------------------------
    def add_status_arguments(self, group) -> None:
        from .status import add_arguments
        add_arguments(group)

    def status_command(self, args) -> int | None:
        from .status import command
        return command(args)

    def status_notes(self, code: int) -> list[str]:
        """The error number a responder's class-06 event answers with, or the numbers that
        raise a requester's class-09 event (Table 8-3)."""
        from ptpcert.status import lookup

        from .status import reatel_of
        if "RK 512" not in lookup(code).protocols:
            return []
        line = reatel_of(code)
        return [line] if line else []

    def mutants(self) -> Mapping[str, Mutant]:
        from ptpcert.procedures.rk512.mutants import MUTANTS
        return MUTANTS

    def fuzz_kit(self):
        from .fuzz import FUZZ_KIT
        return FUZZ_KIT

    # -- the reports' view ------------------------------------------------------------------
    def report_view(self):
        """The link's bytes named as 3964R names them."""
        from ptpcert.procedures.p3964.tokens import report_view
        return report_view(self.groups, link="3964R")
