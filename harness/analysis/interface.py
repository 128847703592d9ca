"""The interface between line analysis and a procedure, and the words they share.

Line analysis (:mod:`ptpcert.analysis`) knows no protocol: what a procedure brings is a
:class:`ProcedureAnalyzer` (``Procedure.analyzer(params_a, params_b)``) - its stations at rest
and powered on, when a station is at rest, which local events the seat's bytes reveal, why
the model sends each byte (rule, reference, STATUS code, timing window: a :class:`Cause`),
what a byte the model does not send breaks, the alternatives to try before a difference
stands (:class:`Variant`), and how an exchange is labelled. This module holds that interface
and the values both sides pass: the seats (:data:`SEATS`, :data:`OTHER`), one thing a seat put
on its line (:class:`Item`), a local event a byte reveals (:class:`Explanation`, or
:data:`WAIT`), and a rule a seat broke (:class:`Finding`); and the few helpers the procedures
share: :func:`resolution_variants` (the alternatives a coarse capture allows), :func:`clipped`
and :func:`strip_section` (texts for reports).

It sits at the bottom of the analysis: the seat run (:mod:`~ptpcert.analysis.seat`), the seat
judge (:mod:`~ptpcert.analysis.judge`), the line (:mod:`~ptpcert.analysis.line`) and each
procedure's analyzer (``ptpcert.procedures.*.analysis``) import it; it imports none of them.
The annotations that name ``SeatRun`` and ``LineAnalysis`` are the classes of those modules,
imported for type checkers only (``TYPE_CHECKING``), so that nothing here depends on them when
it runs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, NamedTuple

from ptpcert import results as R

if TYPE_CHECKING:
    from ptpcert.analysis.line import LineAnalysis
    from ptpcert.analysis.seat import SeatRun

SEATS = ("a", "b")
OTHER = {"a": "b", "b": "a"}
#: how far apart two instants may be and still count as one (seconds)
EPS = 1e-9
#: The capture formats hold whole microseconds, so instants that were equal may differ by one:
#: a byte the model begins within a microsecond of the other seat's character counts as begun
#: before it arrived (a sender stops only what it has not begun), and a local event a seat's
#: byte reveals may have happened a microsecond before that byte's estimated start.
QUANTUM = 1e-6


# ------------------------------------------------------------------ what the procedure brings


@dataclass(frozen=True)
class Cause:
    """Why the model sends a byte, and the timing it allows.

    ``early``/``late``: how much earlier/later than the model the byte may be complete and still
    conform (seconds, before the capture's resolution is added). ``kind``: "reply" (to the
    partner), "timer" (one of the station's own timers ran out), "local" (a local event)."""

    kind: str
    rule: str
    reference: str
    early: float
    late: float
    code: int | None = None
    what: str = ""           # the character's name for people, e.g. "DLE" or "the block"
    rules: tuple[str, ...] = ()   # ids of the rules in the procedure's catalogue (ptpcert rules)


@dataclass(frozen=True)
class Explanation:
    """A local event that a seat's byte reveals: ``apply(run, t)`` gives it to the model at
    ``t`` (e.g. a send request). ``note`` is worth telling people (None: routine)."""

    apply: Callable[["SeatRun", float], None]
    note: str | None = None


#: :meth:`ProcedureAnalyzer.explain` needs to see more of the line before it can tell
WAIT = object()


@dataclass(frozen=True)
class Variant:
    """An alternative to try before a difference stands: other readings of the manual's open
    points (``readings``, named ``name``, e.g. "A11"), or the other seat's bytes moved by
    ``shift`` seconds (within the capture's resolution)."""

    name: str
    description: str
    readings: Any = None
    shift: float = 0.0
    #: the local events the seat's bytes reveal (a send job, a free buffer) happened up to
    #: this much earlier than the bytes' timestamps say (within the capture's resolution)
    lead: float = 0.0
    #: what the finding an adopted alternative leaves is called ("reading" or "resolution"
    #: by default; e.g. "buffer": a local condition of the station the line does not show)
    kind: str = ""
    #: the shift moves only the other seat's characters stamped after the seat's last
    #: character that the run followed before the difference (the order of characters stamped
    #: within the resolution of each other is not known; those before are in their place)
    local: bool = False


class ProcedureAnalyzer:
    """The procedure's part of line analysis (see the module docstring). ``params`` maps a
    seat to its station's parameters; ``apps`` a seat to its application ("echo": it sends
    back every block it receives, and may send its own; "echo-only": it sends back every block
    it receives and nothing else, as the suite's IUT interface does; "none": what it sends is
    its own business)."""

    procedure: Any = None
    #: where the manual describes the procedure (the reference of an exchange without findings)
    reference: str = ""
    #: the longest label of an exchange (a longer one is cut short, ending "...")
    label_width = 160
    #: how late a reaction of a station's may come in a real-time capture (``--tolerance-ms``)
    late_abs = 0.0

    def __init__(self, procedure: Any, params: dict[str, Any], apps: dict[str, str] | None = None):
        self.procedure = procedure
        self.params = dict(params)
        self.apps = {s: "none" for s in SEATS} | dict(apps or {})
        self._char: dict[str, float] = {}

    # -- timing ---------------------------------------------------------------------------
    def char(self, seat: str) -> float:
        c = self._char.get(seat)
        if c is None:
            c = self._char[seat] = self.procedure.char_time(self.params[seat])
        return c

    def rest_gap(self) -> float:
        """How long the line must be quiet before every conforming station is at rest."""
        raise NotImplementedError

    def early_wait(self, host: Any) -> float:
        """How long after a byte the model does not send the analysis waits for the model to
        send it after all (a timer of the station's own that a conforming station may let run
        out that much sooner), before the byte stands as one the model does not send."""
        raise NotImplementedError

    def late_max(self, seat: str) -> float:
        """The largest ``Cause.late`` of the seat's bytes (the lag of live analysis)."""
        raise NotImplementedError

    # -- stations -------------------------------------------------------------------------
    def fresh(self, seat: str, t: float, readings: Any = None) -> Any:
        """A host (station and application) of ``seat`` that is running and at rest at ``t``."""
        raise NotImplementedError

    def powered(self, seat: str, t: float) -> Any:
        """A host of ``seat`` switched on at ``t`` (what it sends at start-up still to come)."""
        raise NotImplementedError

    def at_rest(self, host: Any) -> bool:
        raise NotImplementedError

    # -- reading the seat's bytes ---------------------------------------------------------
    def explain(self, run: "SeatRun", item: "Item", index: int) -> Explanation | None | object:
        """A local event that the seat's ``item`` (``run.judge.obs[index]``) reveals, the model
        not sending it on its own: an :class:`Explanation`, None, or :data:`WAIT` when more of
        the line must be seen first."""
        return None

    def interjects(self, run: "SeatRun", item: "Item") -> bool:
        """May the seat's ``item`` reveal a local event even where the model is about to send
        a byte of its own (e.g. a flow-control character a station puts between two
        characters of its frame)? Then :meth:`explain` is asked first."""
        return False

    def before(self, item: "Item", inputs: list["Item"]) -> bool:
        """The seat's ``item`` began at the instant (within a microsecond) the other seat's
        ``inputs`` were complete: did what it reveals happen before the station took them in
        (True, e.g. two STXs crossing), or after (False: the station answered them)?"""
        return False

    def event(self, run: "SeatRun", event: Any) -> None:
        """Every event the model raises (STATUS, deliveries, job results), for the
        procedure's own bookkeeping in ``run.memo``."""

    def begins(self, byte: int) -> bool:
        """Does a station's ``byte``, sent for a local event, begin an exchange (e.g. STX)?"""
        return False

    def begins_in(self, host: Any, byte: int) -> bool:
        """Does ``byte``, sent for a local event by the station of ``host`` (as it is when it
        sends the byte), begin an exchange? By default :meth:`begins`; a procedure with a
        layer above its blocks may say no while that layer has an exchange open (e.g. the
        RK 512 response to a command)."""
        return self.begins(byte)

    def resync_at(self, line: "LineAnalysis", k: int) -> int | None:
        """Where the line never goes quiet: does an exchange with both stations at rest begin
        in chunk ``k``, as its bytes and those before it show (a seat that is not followed
        any more is followed again from there)? The index of its first item in the chunk, or
        None."""
        return None

    def startup(self, run: "SeatRun", item: "Item", index: int) -> Explanation | None:
        """The seat was switched on (a case of a restarting IUT began): its first ``item`` is
        its start-up output, or None when it is not."""
        return None

    def startup_rule(self, seat: str) -> tuple[str, str, int | None]:
        """(rule, reference, code) of what a station sends at start-up."""
        return ("a station announces its start-up", "", None)

    def announces_startup(self, seat: str) -> bool:
        """Does the station in ``seat`` send something when it is switched on? (When it does
        not, a power-on only starts its model afresh: there is no start-up output to expect.)"""
        return True

    def startup_name(self, seat: str) -> str:
        """What a station sends at start-up, for people (e.g. "NAK")."""
        return "announcement"

    def entry_start(self, entry: Any) -> float:
        """When the transmission ``entry`` of a station's explanation log (``tx_log``) began."""
        return entry[0]

    def continues(self, prev: Any, entry: Any) -> bool:
        """Is ``entry`` of the explanation log the rest of the transmission ``prev`` (a log
        that records a transmission in parts, e.g. once its schedule was delayed)? Its bytes
        then keep ``prev``'s cause and count on from it."""
        return False

    def cause(self, run: "SeatRun", entry: Any, k: int, byte: int) -> Cause:
        """Why the model (``run.host``) sends ``byte``, the ``k``-th of the transmission
        ``entry`` of its explanation log (``station.tx_log``: [start, end, input, actions]).
        One cause serves every byte of a transmission."""
        raise NotImplementedError

    def unexpected(self, run: "SeatRun", host: Any, item: "Item",
                   later: tuple[float, int, Cause] | None) -> Cause:
        """The rule broken by sending ``item`` where the model ``host`` (as it was when the
        byte began) sends nothing; ``later`` is what the model sends next without further
        input, if anything: (completion, byte, cause)."""
        raise NotImplementedError

    def wrong(self, run: "SeatRun", item: "Item", byte: int, cause: Cause) -> Cause:
        """The rule broken by sending ``item`` where the model sends ``byte`` for ``cause``:
        ``cause`` itself unless the item breaks a rule of its own (e.g. a value no character
        of the seat's frame carries)."""
        return cause

    def name(self, byte: int) -> str:
        return f"{byte:02X}"

    def what(self, host: Any, entry: Any, k: int, byte: int) -> str:
        """The ``k``-th byte of the transmission ``entry`` in words (e.g. "the BCC 10"), or ""."""
        return ""

    def variants(self, seat: str, resolution: float) -> list[Variant]:
        """The alternatives to try before a difference stands."""
        return []

    def label(self, items: list[tuple[str, "Item"]]) -> str:
        """An exchange in a few words, from its bytes ((seat, item) in time order): each run of
        one seat's consecutive items as :meth:`describe` tells it, after the seat's name,
        joined by commas and cut to :attr:`label_width`."""
        runs: list[tuple[str, list[Item]]] = []
        for seat, it in items:
            if runs and runs[-1][0] == seat:
                runs[-1][1].append(it)
            else:
                runs.append((seat, [it]))
        return clipped(", ".join(f"{seat} {self.describe(seat, its)}" for seat, its in runs), self.label_width)

    def describe(self, seat: str, items: list["Item"]) -> str:
        """Consecutive ``items`` of ``seat`` in a few words, for :meth:`label` (the procedure's
        characters by name, its frames by their data)."""
        raise NotImplementedError


def resolution_variants(resolution: float, revealed: str) -> list[Variant]:
    """The alternatives a capture's timing ``resolution`` (seconds) allows: the other seat's
    characters that much earlier, that much later, and the local events the seat's characters
    reveal (``revealed``, in words, e.g. "send jobs") up to that much before they show them.
    None without a resolution."""
    if resolution <= 0:
        return []
    ms = f"{1000 * resolution:.3f} ms"
    return [
        Variant("resolution", f"with the other seat's characters {ms} earlier (within the timing resolution)",
                shift=-resolution),
        Variant("resolution", f"with the other seat's characters {ms} later (within the timing resolution)",
                shift=resolution),
        Variant("resolution", f"with the seat's own {revealed} up to {ms} before its characters show them "
                              "(within the timing resolution)", lead=resolution),
        Variant("resolution", f"with the other seat's characters since the seat's last one before the difference "
                              f"taken after the seat's bytes of its transmission stamped up to {ms} after them (the "
                              "order of characters stamped within the timing resolution of each other is not known)",
                shift=resolution, local=True),
    ]


def clipped(text: str, width: int) -> str:
    """``text``, cut to ``width`` characters ending "..." when it is longer."""
    return text if len(text) <= width else text[:width - 3] + "..."


# ------------------------------------------------------------------ findings


@dataclass
class Finding:
    """A rule a seat broke, or (grade informational) a point the analysis could not settle."""

    seat: str
    t: float                          # capture time of the byte concerned (or where it was due)
    grade: str                        # results.FAIL or results.INFORMATIONAL
    kind: str                         # wrong, missing, early, late, unexpected, start-up, timing, reading, resolution,
    #                                   buffer (a local condition the line does not show)
    rule: str
    reference: str
    message: str
    expected: str = ""
    observed: str = ""
    window: tuple[float, float] | None = None
    codes: tuple[int, ...] = ()
    readings: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)
    rules: tuple[str, ...] = ()       # ids of the rules broken, from the procedure's catalogue
    #: the difference does not depend on the order in which the model took the two seats'
    #: characters: a wrong byte inside a transmission the partner kept silent through, up to
    #: and including the read that returned the byte (a monitor reads every port that has
    #: characters waiting, so a partner's character stamped later came later)
    order_free: bool = False

    def text(self, seats: dict[str, str] | None = None) -> str:
        who = f"seat {self.seat}" + (f" ({seats[self.seat]})" if seats and seats.get(self.seat) not in (None, self.seat) else "")
        ids = f" [rule {', '.join(self.rules)}]" if self.rules else ""
        return f"{who}: {self.message}{ids}"


class Item(NamedTuple):
    """One thing a seat put on its line: a byte, a character with an error ("invalid") or a
    BREAK. ``t``: when it was complete; ``start``: when it began (both estimated from the
    chunk's time); ``chunk``: its chunk's index."""

    t: float
    kind: str
    value: Any
    chunk: int
    start: float


def strip_section(rule: str) -> str:
    """A rule sentence without a leading section number of our own notes (e.g. "§2.2.2 items
    1-3: ")."""
    return re.sub(r"^§[\d.\-]+(?: items? [\d\-]+)?:\s*", "", rule)


def at_ms(t: float) -> str:
    """A time on the capture's clock, for people: ``"12.500 ms"``."""
    return f"{t * 1000:.3f} ms"


def show_item(kit: "ProcedureAnalyzer", o: Item | None) -> str:
    """What a seat sent, for people: a byte by the procedure's name for it, a BREAK, a
    character with a parity or framing error."""
    if o is None:
        return "nothing"
    if o.kind == "break":
        return "a BREAK"
    if o.kind == "invalid":
        return f"{kit.name(o.value)} with a parity/framing error"
    return kit.name(o.value)


def resolution_finding(seat: str, cause: Cause, name: str, due: float, at: float, d: float, resolution: float,
                       window: tuple[float, float]) -> Finding:
    """A byte in its window only because of the capture's timing resolution: informational.
    (A byte that answers the other seat cannot be too early: it came after what it answers,
    only the timestamps say otherwise.)"""
    side = "early" if d < 0 else "late"
    return Finding(
        seat, at, R.INFORMATIONAL, "timing", cause.rule, cause.reference,
        f"{name} {1000 * abs(d):.3f} ms {side}, within the capture's timing resolution "
        f"({1000 * resolution:.3f} ms) of its window: {cause.rule} ({cause.reference})",
        expected=f"{name} at {at_ms(due)}", observed=f"{name} at {at_ms(at)}", window=window, rules=cause.rules)

