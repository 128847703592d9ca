"""The procedure-neutral core: what the harness needs to know about one procedure.

A :class:`Procedure` describes one of the CP 341's procedures (3964/3964R, RK 512, the ASCII
driver) to the rest of ptpcert: the names it has in a profile and its own profile tables,
how its parameters are read and written, the timers its time expressions may name, its
sans-IO station and application (for ``sim:``, ``vectors --check`` and the tester's
conforming partner), how a per-case IUT command is made, how its frames are named in
transcripts and reports, its rules catalogue, its broken variants and its fuzz kit. The runner, the transports,
the driver, the reports and the CLI use only this description; each procedure is a package
(the built-in ones under :mod:`ptpcert.procedures`, others in distributions of their own)
that fills it in and registers it in the entry-point group ``ptpcert.procedures``
(:mod:`ptpcert.registry` finds it).

The case generator is named here (:attr:`Procedure.suite`) but not imported: the suite sits
above the harness, and only the command line (:mod:`ptpcert.suite`) loads it and hands its
cases to the runner.

This module is a leaf: it imports nothing of ptpcert at its top.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import sys
from importlib import resources
from typing import Any, Callable, Iterable, Mapping


class ProcedureError(ValueError):
    """A profile, vector or option that does not fit the procedure. ``key`` names what is
    wrong (e.g. ``iut.procedure`` or ``params.cdt_ms``)."""

    def __init__(self, key: str, message: str):
        self.key = key
        super().__init__(f"{key}: {message}" if key else message)


@dataclass(frozen=True)
class Mutant:
    """A deliberately broken variant of the reference implementation, breaking one rule."""

    name: str
    rule: str                  # the rule it breaks, with its manual reference
    make: Callable[..., Any]   # make(params, name=...) -> station
    #: profile settings under which the broken rule shows (e.g. the priority it concerns)
    profile: Mapping[str, Any] = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.profile is None:
            object.__setattr__(self, "profile", {})


@dataclass(frozen=True)
class MacroStep:
    """A step kind of a procedure's own that stands for the send and expect steps of a whole
    exchange (expanded by :meth:`Procedure.expand` before a run, e.g. the tester delivering a
    block as a conforming sender): the keys a vector may give it besides its kind, the
    longest payload (``data``, 1 to ``max_data`` bytes), and the time expressions of window
    keys it may leave out."""

    keys: frozenset[str]
    max_data: int
    defaults: Mapping[str, str] = field(default_factory=dict)


class Procedure:
    """The description of one procedure. Subclasses fill in every method that raises
    NotImplementedError; the others have defaults that fit a procedure without the feature."""

    #: stable id: the vectors folder, the JSON results, the ``procedure`` key of a vector
    id: str = ""
    #: for people: "3964/3964R", "RK 512", "ASCII driver"
    title: str = ""
    #: values of the profile's ``[iut] procedure`` key that select this procedure; the first
    #: is its usual name (``ptpcert iut`` without ``--procedure`` runs the first procedure's)
    names: tuple[str, ...] = ()
    #: the profile tables of its own (besides [iut], [iut.setups], [expected_failures])
    tables: tuple[str, ...] = ()
    #: case groups, in the manual's order (reports and the run order follow it)
    groups: tuple[str, ...] = ()
    #: names a time expression may use besides CHAR and STARTUP
    time_names: tuple[str, ...] = ()
    #: its characters by name (e.g. a control character), for the message that refuses a
    #: name where a vector wants bytes in hex
    byte_names: Mapping[str, int] = {}
    #: the longest gap between two characters of one transmission, as a time expression: an
    #: expect step waits this long for each further byte unless it says otherwise (``max_gap``)
    max_gap: str = "2*CHAR"
    #: the open points of the manual this procedure's model has readings for (e.g. A11)
    readings: tuple[str, ...] = ()
    #: how a case grades an IUT that takes the other reading of one of its tagged open
    #: points (a vector's ``readings``): open point -> "pass" (as good), "non-strict"
    #: (allowed, not as the manual prefers) or "informational" (reported, never a failure);
    #: an open point not listed is not graded down (a divergence fails)
    reading_grades: Mapping[str, str] = {}
    #: which of :attr:`time_names` are the IUT's own timers (None: all of them). A window
    #: whose lower bound names one waits for what that timer causes; the profile's
    #: ``timer_tolerance_ms`` widens its late side
    iut_timers: tuple[str, ...] | None = None
    #: the capabilities a vector may ``require`` (besides those every procedure knows)
    requirements: tuple[str, ...] = ()
    #: names of the ``[iut.setups]`` entries its cases may use
    setups: tuple[str, ...] = ()
    #: the words the bundled reference (``ptpcert iut``) takes for each setup
    reference_setups: Mapping[str, str] = {}
    #: step kinds of its own, expanded into send/expect steps before a run, by name
    macro_steps: Mapping[str, MacroStep] = {}
    #: the module of its conformance suite, with ``cases(profile) -> list[Vector]`` (every
    #: case for the IUT a profile describes); loaded by the command line only
    suite: str = ""
    #: the values its profiles allow for ``[iut] send_trigger``
    send_triggers: tuple[str, ...] = ("echo", "none")
    #: where it is listed among the procedures (command-line choices, help): lower first
    rank: int = 100

    # -- profiles and parameters ----------------------------------------------------------
    def params_from_profile(self, iut: dict[str, Any], tables: dict[str, dict[str, Any]]) -> Any:
        """The parameters from the profile's [iut] keys (the common ones removed) and its own
        tables. Raises :class:`ProcedureError` naming the key."""
        raise NotImplementedError

    def profile_keys(self) -> tuple[str, ...]:
        """The [iut] keys it reads (for the error that lists the allowed keys)."""
        raise NotImplementedError

    def profile_schema(self) -> tuple[Any, ...]:
        """Its keys in the profile (:class:`ptpcert.schema.Key`: in [iut] and its own
        tables), each with its kind, allowed values, default and the manual's table: the
        profile loader checks every key's value against it before :meth:`params_from_profile`
        checks them together; the property tests draw profiles from it."""
        return ()

    def profile_dict(self, params: Any) -> dict[str, Any]:
        """The parameters as profile keys, for reports."""
        raise NotImplementedError

    def params_from_table(self, raw: dict[str, Any]) -> Any:
        """A vector's [params] table. Raises :class:`ProcedureError` naming the key."""
        raise NotImplementedError

    def params_table(self, params: Any) -> dict[str, Any]:
        """Inverse of :meth:`params_from_table`."""
        raise NotImplementedError

    def params_with(self, params: Any, **changes: Any) -> Any:
        """``params`` with some values changed (a vector's bound parameters on a profile's);
        raises ValueError where they do not go together. By default for a frozen dataclass."""
        from dataclasses import replace
        return replace(params, **changes)

    def param_names(self) -> frozenset[str]:
        """Parameter names a vector may bind (``binds``)."""
        raise NotImplementedError

    def line(self, params: Any):
        """The serial line's settings (:class:`ptpcert.model.line.LineSettings`)."""
        return params.line

    def char_time(self, params: Any) -> float:
        return self.line(params).char_time

    def timer_env(self, params: Any) -> dict[str, float]:
        """Values of the names a time expression may use (seconds), CHAR included."""
        raise NotImplementedError

    def edge_timers(self, params: Any) -> tuple[float, ...]:
        """The IUT's timers that watch the tester's pace: a stimulus later than the
        shortest of them may be judged late; the line is quiet after the longest."""
        raise NotImplementedError

    def transmit_lead(self, params: Any) -> float:
        """How much later than its rules' moment the IUT may begin a transmission because its
        parameters make it prepare the line first (e.g. a modem handshake before each
        frame): the late side of every window for the IUT's bytes, and the quiet that shows
        it has nothing more to send, widen by it. Seconds; 0 for most procedures."""
        return 0.0

    def startup_bytes(self, params: Any) -> bytes:
        """What a freshly started station sends on its own (3964's NAK, ASCII's XON)."""
        return b""

    def tester_params(self, params: Any, declared: Any | None = None) -> Any:
        """The parameters of a conforming partner in the tester's seat."""
        return declared if declared is not None else params

    # -- steps ----------------------------------------------------------------------------
    def expand(self, step: Any, params: Any) -> list[Any]:
        """A step of one of :attr:`macro_steps` as the send/expect steps it stands for."""
        raise NotImplementedError

    # -- models ---------------------------------------------------------------------------
    def station(self, params: Any, *, name: str = "iut", mutant: str | None = None,
                readings: Any | None = None, explain: bool = False) -> Any:
        """A sans-IO station (the reference, or a broken variant)."""
        raise NotImplementedError

    def host(self, station: Any, *, app: str = "echo", vector: Any | None = None) -> Any:
        """The station with its application (``.station``, ``.drain(now)``): ``echo`` or
        ``none``, set up as ``vector`` needs (its setup, its requests...)."""
        raise NotImplementedError

    def apps(self) -> tuple[str, ...]:
        return ("echo", "none")

    def profile_app(self, profile: Any) -> str:
        """The application of the reference IUT a profile describes (``sim:`` and ``ptpcert
        iut --profile`` run it): ``none`` where nothing makes the IUT send (``send_trigger =
        "none"``) and the procedure has that application, else its first."""
        if profile.send_trigger == "none" and "none" in self.apps():
            return "none"
        return self.apps()[0]

    # -- sim: -----------------------------------------------------------------------------
    #: options of a ``sim:`` URL every procedure knows
    SIM_OPTIONS = ("app", "mutant")

    def sim_option_names(self) -> tuple[str, ...]:
        return self.SIM_OPTIONS

    def sim_options(self, options: dict[str, str]) -> tuple[frozenset[str], dict[str, str]]:
        """Check a ``sim:`` URL's options; return the capabilities they add and the options.
        Raises ValueError with a message naming what is allowed."""
        known = self.sim_option_names()
        unknown = sorted(set(options) - set(known))
        if unknown:
            raise ValueError(f"unknown option {unknown[0]!r} (known: {', '.join(known)})")
        app = options.get("app", self.apps()[0])
        if app not in self.apps():
            raise ValueError(f"app={app!r}: allowed values are {', '.join(self.apps())}")
        mutant = options.get("mutant")
        if mutant is not None and mutant not in self.mutants():
            raise ValueError(f"mutant={mutant!r} is not a broken variant of {self.title}; known: "
                             + ", ".join(self.mutants()))
        return frozenset(), options

    def sim_params(self, params: Any, options: dict[str, str]) -> Any:
        """The parameters of the model IUT, as the ``sim:`` options change them."""
        return params

    def sim_host(self, params: Any, vector: Any, options: dict[str, str], readings: Any = None) -> Any:
        """The model IUT of a ``sim:`` case, with its application."""
        station = self.station(params, mutant=options.get("mutant") or None, readings=readings)
        return self.host(station, app=options.get("app", self.apps()[0]), vector=vector)

    def partner_done(self, host: Any) -> bool:
        """The tester's partner is at rest: nothing to send, nothing in progress."""
        st = host.station
        return st.idle

    def echo_time_limit(self, params: Any, payloads: list[bytes]) -> float:
        """How long receiving ``payloads`` back from an echo IUT may take at most."""
        raise NotImplementedError

    def frame(self, payload: bytes, params: Any) -> bytes:
        """The bytes an IUT puts on the line to send ``payload`` (for time estimates)."""
        return bytes(payload)

    def cross_check(self, vector: Any) -> tuple[str, str] | None:
        """``vectors --check`` beyond the model as IUT: the tester's own script replayed by a
        model in the tester's seat, where that applies. (verdict, message) or None."""
        return None

    # -- IUT processes --------------------------------------------------------------------
    def add_iut_arguments(self, group) -> None:
        """``ptpcert iut`` options of its own (an argparse argument group)."""

    def params_from_iut(self, args) -> Any:
        """The parameters from ``ptpcert iut``'s options. Raises ProcedureError."""
        raise NotImplementedError

    def iut_host(self, params: Any, args) -> Any:
        """The station and application ``ptpcert iut`` runs in real time."""
        station = self.station(params, mutant=args.mutant)
        return self.host(station, app=args.app)

    def command(self, template: str, vector: Any, setups: Mapping[str, str], workdir: str) -> str | None:
        """The exec:/pty: command for ``vector``: the template with what the case needs
        (its setup's words appended, files it needs written into ``workdir``). None when
        the case needs a setup the profile does not have."""
        setup = getattr(vector, "setup", None) if vector is not None else None
        if not setup:
            return template
        name, args = setup
        if name not in setups:
            return None
        words = setups[name]
        for k, v in args.items():
            words = words.replace("{" + k + "}", str(v))
        return f"{template} {words}"

    def interleaved(self, params: Any) -> bytes:
        """Bytes an IUT may put on the line between any others at times the manual leaves
        open (ASCII: the XON of its flow control). An expect step passes over them where it
        does not expect them."""
        return b""

    def start_ahead(self, vector: Any) -> bool:
        """Whether the IUT process of ``vector``'s case may be started while the previous
        case runs. Not where the IUT acts on its own from its start (RK 512's request
        script, a coordination flag cleared a time after the start): it must start with its
        case."""
        return True

    def unsupported_reason(self, vector: Any, profile: Any, capabilities: frozenset[str],
                           factory: Any) -> str | None:
        """Why ``vector`` cannot run against the IUT ``profile`` describes (None: it can),
        beyond what the runner checks for every procedure: e.g. a role or a memory area the
        IUT does not have."""
        return None

    def judge_reports(self, vector: Any, lines: list[str]) -> list[str]:
        """Problems with what the IUT reported on stderr beyond STATUS (e.g. RK 512's RESULT
        lines); empty: acceptable."""
        return []

    # -- reports --------------------------------------------------------------------------
    def describe_frames(self, transcript: list[dict[str, Any]], params: Any) -> list[dict[str, Any]]:
        """Frames found in a transcript, for reports: dicts with ``dir``, ``t0``, ``t1``,
        ``label`` (e.g. "block 31 32 (2 bytes)")."""
        return []

    # -- line analysis (ptpcert analyze, ptpcert monitor) ----------------------------------
    def analyzer(self, params_a: Any, params_b: Any, *, apps: Mapping[str, str] | None = None,
                 late_ms: float = 50.0) -> Any:
        """The procedure's part of judging a recorded or live link between two stations
        (:class:`ptpcert.analysis.ProcedureAnalyzer`): ``params_a``/``params_b`` are the
        stations' parameters in seats a and b, ``apps`` their applications ("echo" or
        "none"), ``late_ms`` how late a station may act on its own timer. None while the
        procedure has none."""
        return None
    # -- the rules catalogue --------------------------------------------------------------
    def _package(self) -> str:
        """The package that holds the description's module."""
        module = sys.modules[type(self).__module__]
        return module.__spec__.parent if module.__spec__ is not None else type(self).__module__

    def rules_file(self) -> Any | None:
        """The procedure's rules catalogue as a file (an importlib.resources Traversable):
        ``rules.toml`` in the package that holds its description; None where it has none.
        :mod:`ptpcert.rules` reads it."""
        entry = resources.files(self._package()).joinpath("rules.toml")
        return entry if entry.is_file() else None

    def vectors_dir(self) -> Any | None:
        """A folder of golden vectors that ships with the procedure (an importlib.resources
        Traversable), loaded with ptpcert's own; None: its vectors are among ptpcert's
        bundled ones (``ptpcert.vectors``), as the built-in procedures' are."""
        return None

    def rule_settings(self) -> list[tuple[str, dict[str, Any], Any]]:
        """The IUT settings the traceability matrix is computed for, each as (label, the
        values of the catalogue's dimensions, the profile): a rule that applies to a setting
        needs a case in the suite generated for it. By default one setting, the reference
        IUT's profile (:meth:`reference_profile`)."""
        try:
            profile = self.reference_profile()
        except NotImplementedError:
            return []
        return [("the reference profile", self.setting_values(profile.params), profile)]

    def setting_values(self, params: Any) -> dict[str, Any]:
        """The values of the catalogue's dimensions for an IUT with ``params``."""
        return {}

    def setting_from_profile(self, profile: Mapping[str, Any], dimensions: Iterable[str]) -> dict[str, Any]:
        """The values of the catalogue's ``dimensions`` from a run's profile as the results
        keep it (:meth:`ptpcert.profile.Profile.to_dict`): by default each dimension's profile
        key, at the top or in one of the procedure's tables."""
        flat = dict(profile)
        for table in self.tables:
            if isinstance(profile.get(table), Mapping):
                flat.update(profile[table])
        return {k: flat[k] for k in dimensions if k in flat}

    # -- broken variants and fuzzing ------------------------------------------------------
    def mutants(self) -> Mapping[str, Mutant]:
        return {}

    def fuzz_kit(self) -> Any:
        """The fuzz strategies and oracle (:class:`ptpcert.fuzz.FuzzKit`), or None."""
        return None

    # -- the readings of the manual's open points -------------------------------------------
    def reading_grade(self, name: str) -> str | None:
        """The grade of a case's divergence that the other reading of open point ``name``
        explains (see :attr:`reading_grades`); None: not graded down."""
        return self.reading_grades.get(name)

    def other_reading(self, name: str) -> Any | None:
        """The model's readings (the object :meth:`station` takes) with the other reading of
        open point ``name``; None when the model has no other reading of it. By default the
        fuzz kit's alternatives (the same change the fuzzer tries on a divergence)."""
        kit = self.fuzz_kit()
        change = dict(kit.alternatives).get(name) if kit is not None else None
        if change is None:
            return None
        from dataclasses import replace
        return replace(kit.readings, **change)

    # -- the reference IUT's profile --------------------------------------------------------
    def reference_profile(self, **settings: Any) -> Any:
        """The profile (:class:`ptpcert.profile.Profile`) of the bundled reference IUT
        (``ptpcert iut --procedure NAME``) with these profile keys changed: for tests, the
        kill matrix, benchmarks and the traceability matrix."""
        raise NotImplementedError

    # -- the command line's explanations -----------------------------------------------------
    def chart(self) -> Any | None:
        """Its state machine for ``ptpcert model``: an object with ``table_text() -> str``
        (the transition table as text) and ``svg() -> str`` (drawn); None where it has none."""
        return None

    def add_status_arguments(self, group) -> None:
        """``ptpcert status`` options of its own (an argparse argument group)."""

    def status_command(self, args) -> int | None:
        """``ptpcert status`` with the options of :meth:`add_status_arguments`: print the
        explanation (a value it cannot read: one line on stderr) and return the exit status;
        None where none of its options was given."""
        return None

    def status_notes(self, code: int) -> list[str]:
        """Lines ``ptpcert status CODE`` adds to a STATUS event's description (e.g. the
        error number of a response frame that goes with it)."""
        return []

    def __repr__(self) -> str:
        return f"<procedure {self.id}>"

    # -- the reports' view ------------------------------------------------------------------
    def report_view(self) -> Any:
        """How the reports show this procedure's runs (a
        :class:`ptpcert.view.ReportView`): by default each byte in hex and the case
        groups in the order of :attr:`groups`."""
        from ptpcert.view import ReportView
        return ReportView(groups=self.groups)
