"""The transition table, exercised for every (state, input) pair.

For each state we drive a fresh station into it by a path through the protocol, then feed
each of the table's inputs and check that the station ran the row's action and ended in a
state the row allows. Rows marked impossible must be refused with ModelError."""

import pytest

from ptpcert.model.errors import ModelError
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import DLE, ETX, NAK, STX
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964

P = Params3964(cdt_ms=20, adt_ms=20)
CHAR = {T.STX: STX, T.DLE: DLE, T.ETX: ETX, T.NAK: NAK, T.OTHER: 0x41}


def drive(state: str, p: Params3964 = P) -> Station3964:
    s = Station3964(p, name="s", trace=True)
    t = 0.0
    if state == T.START_UP:
        return s
    s.power_on(t)
    paths = {
        T.IDLE: [],
        T.IDLE_JUNK: [("rx", 0x41)],
        T.WAIT_SETUP_ACK: [("req", b"ABCDEFGH")],
        T.SEND_DATA: [("req", b"ABCDEFGH"), ("rx", DLE)],
        T.ABORT_QUIET: [("req", b"ABCDEFGH"), ("rx", DLE), ("rx", 0x41)],
        T.WAIT_RELEASE_ACK: [("req", b"AB"), ("rx", DLE), ("until", T.WAIT_RELEASE_ACK)],
        T.WAIT_BUFFER: [("full",), ("rx", STX)],
        T.RECEIVE: [("rx", STX)],
        T.WAIT_ETX: [("rx", STX), ("rx", 0x31), ("rx", DLE)],
        T.WAIT_BCC: [("rx", STX), ("rx", 0x31), ("rx", DLE), ("rx", ETX)],
        T.WAIT_REPETITION: [("rx", STX), ("rx", 0x31), ("rx", DLE), ("rx", ETX), ("rx", 0x99)],
    }
    for step in paths[state]:
        t += 0.001
        if step[0] == "rx":
            s.receive(t, step[1])
        elif step[0] == "req":
            s.request_send(t, step[1])
        elif step[0] == "full":
            s.set_buffer_free(t, False)
        elif step[0] == "until":
            while s.state != step[1]:
                t = max(s.now, s.next_deadline())
                s.handle_timer(t)
                s.pop_output(t)
    s.pop_output()
    s.pop_events()
    assert s.state == state, (state, s.state)
    return s


def reachable(target: str, current: str) -> set[str]:
    if target == T.SAME:
        return {current, T.WAIT_SETUP_ACK}
    out, todo = set(), [target]
    while todo:
        x = todo.pop()
        if x in T.DECISION_TARGETS:
            todo.extend(T.DECISION_TARGETS[x])
        else:
            out.add(x)
    if T.IDLE in out:
        out.add(T.WAIT_SETUP_ACK)  # a pending job starts as soon as the station is idle
    return out


def feed(s: Station3964, inp: str) -> None:
    t = s.now + 0.0005
    if inp in CHAR:
        s.receive(t, CHAR[inp])
    elif inp == T.INVALID:
        s.receive_invalid(t, 0x41)
    elif inp == T.BREAK:
        s.line_break(t)
    elif inp == T.POWER_ON:
        s.power_on(t)
    elif inp == T.SEND_REQUEST:
        s.request_send(t, b"XYZ")
    elif inp == T.BUFFER_FREE:
        s.set_buffer_free(t, True)
    elif inp == T.TX_DONE:
        if s.block_done_at is None:
            s._input(T.TX_DONE)  # no block is being sent: the station must refuse it
        s.handle_timer(s.block_done_at)
    else:  # a timer
        if s.timer is None or s.timer[0] != inp:
            s._input(inp)  # not armed here: the station must refuse it
        s.handle_timer(s.timer[1])


@pytest.mark.parametrize("state,inp", [(s, i) for s in T.STATES for i in T.INPUTS])
def test_every_state_input_pair(state, inp):
    s = drive(state)
    row = T.TABLE[state][inp]
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            feed(s, inp)
        return
    if inp == T.BUFFER_FREE and state != T.WAIT_BUFFER:
        feed(s, inp)  # only a state waiting for a buffer reacts
        assert s.state == state
        return
    n = len(s.trace)
    feed(s, inp)
    steps = [x for x in s.trace[n:] if x[1] != "timer"]
    assert steps, "the input reached the table"
    first = steps[0]
    assert first[1:4] == (state, inp, row.action)
    assert first[4] in reachable(row.target, state), (first, row)


def test_table_is_complete_and_targets_are_known():
    assert len(list(T.rows())) == len(T.STATES) * len(T.INPUTS)
    for d, targets in T.DECISION_TARGETS.items():
        assert d in T.DECISIONS
        for x in targets:
            assert x in T.STATES or x in T.DECISIONS
    # every action named in the table exists on the station
    for _, _, row in T.rows():
        if row.action != T.IMPOSSIBLE:
            assert hasattr(Station3964, "_a_" + row.action), row.action
    for d in T.DECISIONS:
        assert hasattr(Station3964, "_d_" + d.lower()), d


def test_every_state_reachable_and_every_action_used():
    used = {row.action for _, _, row in T.rows()}
    defined = {n[3:] for n in dir(Station3964) if n.startswith("_a_")}
    assert used - {T.IMPOSSIBLE} == defined


# ---------------------------------------------------------------------------------------------
# The table as data: references, STATUS codes, targets
# ---------------------------------------------------------------------------------------------
import ast
import dataclasses
import inspect
import io
import xml.etree.ElementTree as ET
from contextlib import redirect_stdout
from pathlib import Path

import ptpcert
from ptpcert.cli import main as cli_main
from ptpcert.model.codes import Code
from ptpcert.model.events import Status
from ptpcert.procedures.p3964 import chart as statechart
from ptpcert.procedures.p3964 import mutants as p3964_mutants
from ptpcert.procedures.p3964.model import station as station_module
from ptpcert.procedures.p3964.model.readings import READINGS, Readings

P1 = Params3964(cdt_ms=20, adt_ms=20, setup_attempts=1, transmission_attempts=1)
ELEMENTS = [r for _, _, r in T.rows()] + [b for _, b in T.branches()]


def test_states_inputs_actions_decisions_are_enums_named_as_before():
    assert all(isinstance(s, T.State) and s == s.value == s.name for s in T.STATES)
    assert all(isinstance(i, T.Input) and i == i.name for i in T.INPUTS)
    assert all(isinstance(d, T.Decision) and d == d.name for d in T.DECISIONS)
    assert all(isinstance(r.action, T.Action) for _, _, r in T.rows())
    assert f"{T.WAIT_SETUP_ACK}" == "WAIT_SETUP_ACK" and str(T.Action.STORE) == "store"


def test_every_row_and_outcome_has_a_manual_reference():
    for state, inp, row in T.rows():
        if row.action != T.IMPOSSIBLE:
            assert row.ref.strip(), (state, inp)
    for d, b in T.branches():
        assert b.ref.strip() and b.when.strip(), d
    for e in ELEMENTS:
        # the manual's sections, figures and tables, or an open point; never our notes
        assert ".md" not in e.ref and ".md" not in e.rule
        if e.ref:
            assert any(k in e.ref for k in ("§2.2.2", "Fig. 2-", "Table 2-", "Table 8-1")), e.ref


def test_rows_and_outcomes_cite_rules_of_the_catalogue():
    from ptpcert.rules import for_procedure
    catalogue = for_procedure("p3964")
    quiet = (T.IMPOSSIBLE, T.Action.IGNORE, T.Action.QUEUE_JOB)
    for state, inp, row in T.rows():
        assert not catalogue.unknown(row.rules), (state, inp, row.rules)
        if row.action not in quiet:
            assert row.rules, (state, inp)
    for d, b in T.branches():
        assert b.rules and not catalogue.unknown(b.rules), (d, b.when)
    # every element that sends names its rule with an id, not with our notes' numbering
    for e in ELEMENTS:
        if e.rule:
            assert T.rule_text(e).startswith("3964.") and "item" not in e.rule and "§" not in e.rule


def test_codes_are_data_from_the_one_list():
    assert any(e.code for e in ELEMENTS)
    for e in ELEMENTS:
        assert e.code is None or isinstance(e.code, Code), e
        assert not e.noted or e.code is not None, e
        if e.code is not None and "Table 8-1" in e.ref:
            assert e.code.text in e.ref or "16#" in e.ref


def _claims(s: Station3964, steps) -> tuple[list[int], int | None]:
    """The STATUS codes the table says the station raises for the rows and outcomes in
    ``steps`` (in order), and a code still noted but not yet raised."""
    out: list[int] = []
    noted = None
    for _, state, inp, _action, _new, decided in steps:
        elements = [(None, T.TABLE[state][inp])] + [(d, T.branch(d, o)) for d, o in decided]
        for d, e in elements:
            if d == T.NAK_CHECK:
                # the NAK raises the error noted first, 16#0801 at the first NAK of a block, and
                # the first error again when the receiver gives up
                assert s.w_r == 1
                out += [noted, Code.EXPECT_REPETITION] + ([noted] if e.target == T.IDLE else [])
                noted = None
            if e.code is not None:
                if e.noted:
                    noted = noted or e.code
                else:
                    out.append(e.code)
    return out, noted


WALK = [(p, s, i) for p in (P, P1) for s in T.STATES for i in T.INPUTS
        if T.TABLE[s][i].action != T.IMPOSSIBLE and not (p is P1 and s == T.WAIT_REPETITION)]


@pytest.mark.parametrize("p,state,inp", WALK, ids=[f"{'P1' if p is P1 else 'P'}-{s}-{i}" for p, s, i in WALK])
def test_walk_the_table_codes_raised_are_the_rows_codes(p, state, inp):
    """Fire every row (with 6 attempts, and with 1, which takes the give-up outcomes): the
    STATUS events raised are exactly those the row and the outcomes taken say, in order; a
    noted code is raised when the NAK goes out."""
    _fire_and_check(drive(state, p), inp)


def _fire_and_check(s: Station3964, inp: str) -> list:
    n = len(s.trace)
    feed(s, inp)
    steps = [x for x in s.trace[n:] if x[1] != "timer"]
    raised = [e.code for e in s.pop_events() if isinstance(e, Status)]
    claims, pending = _claims(s, steps)
    assert raised == claims, (steps, raised, claims)
    for _, _, _, _, _, decided in steps:
        for d, outcome in decided:
            assert outcome in T.DECISION_TARGETS[d]
    if pending is not None:
        # the reception goes on; the noted error comes with the NAK (here at the CDT timeout)
        for _ in range(5):
            if raised:
                break
            s.handle_timer(s.next_deadline())
            raised = [e.code for e in s.pop_events() if isinstance(e, Status)]
        assert raised[:1] == [pending]
    return steps


def _late_dle() -> Station3964:
    """SEND_DATA with the partner's DLE arriving while the BCC is on its way (A10)."""
    s = drive(T.SEND_DATA)
    s.handle_timer(s.block_done_at - 1.5 * P.char_time - 0.0005)
    return s


def test_every_code_in_the_table_is_raised_by_the_walk():
    """The walk above reaches every row and outcome that carries a code, except those of the
    alternative readings (checked in test_readings_flip_the_wire)."""
    reached = set()
    for s, inp in [(drive(state, p), inp) for p, state, inp in WALK] + [(_late_dle(), T.DLE)]:
        for _, st, i, _a, _n, decided in _fire_and_check(s, inp):
            reached.add(("row", st, i))
            reached.update(("branch", d, o) for d, o in decided)
    missing = [(state, inp) for state, inp, r in T.rows() if r.code and ("row", state, inp) not in reached]
    assert missing == []
    missing = [(d, b.target) for d, b in T.branches() if b.code and ("branch", d, b.target) not in reached]
    # keeping the buffer wait after garbage is the alternative of A16
    assert missing == [(T.ABANDON_SETUP, T.WAIT_BUFFER)]


def _methods(prefix: str):
    tree = ast.parse(inspect.getsource(station_module))
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Station3964")
    return cls, {f.name[len(prefix):]: f for f in cls.body if isinstance(f, ast.FunctionDef) and f.name.startswith(prefix)}


def test_no_action_sets_a_target_outside_the_table():
    cls, decisions = _methods("_d_")
    _, actions = _methods("_a_")
    # only the dispatcher (and the constructor) moves the station between states
    setters = {f.name for f in cls.body if isinstance(f, ast.FunctionDef)
               for n in ast.walk(f) if isinstance(n, ast.Attribute) and n.attr == "state"
               and isinstance(n.ctx, ast.Store)}
    assert setters == {"__init__", "_input"}
    assert "_override" not in inspect.getsource(station_module)
    # actions return nothing: the row's target decides
    for name, f in actions.items():
        assert not [r for r in ast.walk(f) if isinstance(r, ast.Return) and r.value is not None], name
    # a decision returns one of its outcomes in the table, and every outcome is returned somewhere
    assert set(decisions) == {d.lower() for d in T.DECISIONS}
    for d in T.DECISIONS:
        returned = {getattr(T, n.attr) for r in ast.walk(decisions[d.lower()]) if isinstance(r, ast.Return)
                    for n in ast.walk(r.value) if isinstance(n, ast.Attribute) and getattr(n.value, "id", "") == "T"}
        assert returned == set(T.DECISION_TARGETS[d]), d


def test_the_station_and_the_mutants_keep_to_the_public_surface():
    """Nothing outside the station reads its private fields; broken variants override
    protected hooks (methods) and patch table rows, and touch no private field either."""
    s = Station3964(P, name="s")
    private = {k for k in vars(s) if k.startswith("_")}
    station_file = Path(inspect.getfile(station_module))
    root = Path(inspect.getfile(ptpcert)).parent
    # every module of the package of broken variants
    mutants_files = sorted(Path(inspect.getfile(p3964_mutants)).parent.rglob("*.py"))
    assert len(mutants_files) > 1
    for path in sorted(root.rglob("*.py")):
        if path == station_file:
            continue
        rel = path.relative_to(root).as_posix()
        tree = ast.parse(path.read_text("utf-8"))
        for n in ast.walk(tree):
            if isinstance(n, ast.Attribute) and n.attr in private:
                own = isinstance(n.value, ast.Name) and n.value.id == "self" and path not in mutants_files
                assert own, f"{rel}:{n.lineno} reads {n.attr}"
    for mutants_file in mutants_files:
        mutants_src = ast.parse(mutants_file.read_text("utf-8"))
        for n in ast.walk(mutants_src):
            if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == "self" \
                    and n.attr.startswith("_"):
                assert callable(getattr(Station3964, n.attr, None)), \
                    f"{mutants_file.name}:{n.lineno} uses self.{n.attr}"


def test_the_public_surface_of_the_station():
    s = Station3964(P, name="s")
    assert not s.transmitting and s.timer is None and s.block_done_at is None and not s.has_events
    s.power_on(0.0)
    assert s.transmitting and s.busy_until == pytest.approx(P.char_time)
    assert s.pop_output(0.0) and not s.transmitting and s.popped_until == pytest.approx(P.char_time)
    s.request_send(0.01, b"AB\x10")
    name, at = s.timer
    assert name == T.T_ADT and at == pytest.approx(0.01 + P.char_time + P.adt + P.char_time)
    s.receive(0.02, 0x10)
    body = s.block_body(b"AB\x10")
    assert body[:5] == b"AB\x10\x10\x10" and s.timer is None
    assert s.block_done_at == pytest.approx(0.02 + len(body) * P.char_time)
    s.handle_timer(s.block_done_at)
    assert s.block_done_at is None and s.timer[0] == T.T_ADT
    s.receive(s.now + 0.001, 0x10)
    assert s.has_events
    assert [type(e).__name__ for e in s.pop_events()] == ["SendDone"] and not s.has_events


# ---------------------------------------------------------------------------------------------
# Rules for transcripts, derived from the rows
# ---------------------------------------------------------------------------------------------
def test_rules_come_from_the_rows_that_send():
    from ptpcert.procedures.p3964.fuzz import BLOCK_RULE, rule_for, rule_of_note

    for state, inp, row in T.rows():
        for name in row.sends:
            byte = 0x41 if name == T.BLOCK else T.SENDABLE[name]
            assert T.rule_for([row.action], byte) is row or T.rule_for([row.action], byte).rule == row.rule
    for d, b in T.branches():
        for name in b.sends:
            # (both outcomes of NAK_CHECK send the NAK under one rule)
            assert T.rule_for([d], T.SENDABLE[name]).rule == b.rule
    assert rule_for(["setup_acknowledged"], 0x99) == BLOCK_RULE
    assert rule_for(["start_job", "START_CHECK"], 0x02) == T.rule_text(T.branch(T.START_CHECK, T.WAIT_SETUP_ACK))
    # the outermost step is the more specific rule: a low-priority station's DLE after a conflict
    assert "3964.CONFLICT.LOW-DEFERS" in rule_for(["initialization_conflict", "PRIORITY", "RECEIVE_ENTRY"], 0x10)
    assert rule_for(["ignore"], 0x15) == "the reference model's behaviour"
    text = T.rule_text(T.TABLE[T.IDLE_JUNK][T.T_CDT])
    assert rule_of_note(text + " [STATUS 16#0802]") == (text, "16#0802")
    assert rule_of_note("the IUT stops sending its block") == ("the IUT stops sending its block", "")


# ---------------------------------------------------------------------------------------------
# The drawing and the text
# ---------------------------------------------------------------------------------------------
def test_svg_is_well_formed_and_names_every_state_and_decision(tmp_path):
    out = tmp_path / "model.svg"
    with redirect_stdout(io.StringIO()):
        assert cli_main(["model", "--svg", str(out)]) == 0
    root = ET.parse(out).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    assert root.tag == ns + "svg"
    texts = {"".join(t.itertext()) for t in root.iter(ns + "text")}
    groups = {g.get("class"): set() for g in root.iter(ns + "g")}
    for g in root.iter(ns + "g"):
        groups[g.get("class")].add(g.get("id"))
    assert groups["state"] == set(T.STATES) and groups["decision"] == set(T.DECISIONS)
    assert set(T.STATES) <= texts and set(T.DECISIONS) <= texts
    labels = " ".join(texts)
    for e in ELEMENTS:   # every STATUS code of the table is on an arrow
        if e.code is not None:
            assert e.code.text in labels, e
    assert len(list(root.iter(ns + "path"))) > len(T.STATES) + len(T.DECISIONS)
    assert "href" not in out.read_text("utf-8")   # self-contained


def test_model_command_prints_the_table():
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert cli_main(["model"]) == 0
    text = buf.getvalue()
    lines = text.splitlines()
    for state, inp, row in T.rows():
        if row.action != T.IMPOSSIBLE:
            assert any(l.split()[:4] == [state, inp, row.action, row.target] and row.ref in l for l in lines), \
                (state, inp)
    for d, b in T.branches():
        assert any(l.startswith(d) and b.when in l and b.ref in l for l in lines)


def test_statechart_imports_only_the_model():
    tree = ast.parse(inspect.getsource(statechart))
    for n in ast.walk(tree):
        if isinstance(n, ast.ImportFrom) and n.level:
            assert (n.module or "").split(".")[0] == "model", n.module
        elif isinstance(n, (ast.Import, ast.ImportFrom)):
            names = [a.name for a in n.names] if isinstance(n, ast.Import) else [n.module]
            for name in names:
                assert name.split(".")[0] in {"__future__", "math", "collections", "dataclasses", "xml"}, name


# ---------------------------------------------------------------------------------------------
# Every reading switches something
# ---------------------------------------------------------------------------------------------
P0 = Params3964(cdt_ms=20, adt_ms=20, baud_rate=None)   # characters take no time
BLOCK_A = b"A\x10\x03" + bytes([0x41 ^ 0x10 ^ 0x03])     # "A", DLE ETX, BCC (3964R)
BAD_A = b"A\x10\x03\x99"                                 # the same with a wrong BCC


def _wire(readings: Readings, p: Params3964, script, until: float = 10.0):
    """Run a station through ``script`` [(time, kind, value)]; return its wire (time, byte)
    and the STATUS codes it raised."""
    s = Station3964(p, readings, name="s")
    s.power_on(0.0)
    wire = []

    def run(until, inclusive):
        # the station's deadlines include the start of each byte it transmits: take them out
        while (d := s.next_deadline()) is not None and (d <= until if inclusive else d < until):
            s.handle_timer(d)
            wire.extend(s.pop_output(d))

    for t, kind, value in script:
        run(t, False)
        if kind == "rx":
            s.receive(t, value)
        elif kind == "bad":
            s.receive_invalid(t, value)
        elif kind == "break":
            s.line_break(t)
        elif kind == "req":
            s.request_send(t, value)
        elif kind == "full":
            s.set_buffer_free(t, False)
        wire.extend(s.pop_output(t))
    run(until, True)
    wire.extend(s.pop_output())
    return [(round(t, 7), b) for t, b in wire], [e.code for e in s.pop_events() if isinstance(e, Status)]


_CT = P.char_time
SCENARIOS = {
    # a job handed over after a CDT timeout waits for T_BLOCK, or starts at once
    "a2_cdt_timeout_awaits_repetition": (P0, [(0.01, "rx", 0x02), (0.05, "req", b"A")]),
    # refused setup, accepted, release refused; the next setup is refused: X = 2 of 2, or 3
    "a4_reset_setup_counter_per_attempt": (
        P0.with_(setup_attempts=2, transmission_attempts=2),
        [(0.001, "req", b"A"), (0.002, "rx", 0x15), (0.003, "rx", 0x10), (0.004, "rx", 0x15),
         (0.005, "rx", 0x15)]),
    # another character during the only attempt: NAK after the quiet wait, and maybe a second
    "a6_second_final_nak": (P.with_(transmission_attempts=1),
                            [(0.001, "req", bytes(range(0x20, 0x60))), (0.005, "rx", 0x10), (0.02, "rx", 0x41)]),
    # two stray characters 15 ms apart: the quiet wait restarts, or not
    "a7_quiet_wait_retriggered": (P0, [(0.01, "rx", 0x41), (0.025, "rx", 0x41)]),
    # a refused setup: 16#0702 raised at once, or only noted
    "a9_report_each_error": (P0, [(0.001, "req", b"A"), (0.002, "rx", 0x15), (0.003, "rx", 0x10),
                                  (0.004, "rx", 0x10)]),
    # a DLE while the BCC is on its way: DLE too early (new STX at once), or other character
    "a10_dle_in_end_sequence_too_early": (P, [(0.001, "req", b"ABCDEFGH"), (0.004, "rx", 0x10),
                                              (0.004 + 9.5 * _CT, "rx", 0x10)]),
    # DLE followed by another character: NAK at the end, or at once
    "a11_deferred_nak_after_dle_other": (P0, [(0.01, "rx", 0x02), (0.011, "rx", b"A\x10B")]),
    # no answer to the block: T_ADT from the BCC, or from DLE ETX (one character earlier)
    "a12_release_adt_after_last_byte": (P, [(0.001, "req", b"ABCDEFGH"), (0.004, "rx", 0x10)]),
    # a character error in idle: NAK after CDT, or none
    "a13_nak_after_invalid_char_in_idle": (P0, [(0.01, "bad", 0x41)]),
    # BREAK while waiting for the setup DLE: 16#080D or 16#1E0D
    "a15_break_status_on_send": (P0, [(0.001, "req", b"A"), (0.002, "break", 0)]),
    # a character while the receiver waits for a buffer: NAK after CDT, or at T_NAKTIM
    "a16_garbage_during_buffer_wait_quiet_nak": (P0, [(0.005, "full", 0), (0.01, "rx", 0x02), (0.012, "rx", 0x41)]),
    # an empty block: DLE, or NAK
    "a17_accept_zero_length_block": (P0, [(0.01, "rx", 0x02), (0.012, "rx", b"\x10\x03\x13")]),
    # one transmission attempt: a refused block ends the reception (a new job starts at once),
    # or the figure's 6 keep it waiting for a repetition
    "a18_receiver_uses_own_attempt_limit": (P0.with_(transmission_attempts=1),
                                            [(0.01, "rx", 0x02), (0.012, "rx", BAD_A), (0.02, "req", b"A")]),
    # the partner's NAK while a repetition is expected: 16#0815, or another code
    "a19_wait_repetition_code": (P0, [(0.01, "rx", 0x02), (0.012, "rx", BAD_A), (0.02, "rx", 0x15)]),
    # a low-priority station with one setup attempt loses the conflict: NAK, or a new STX
    "a21_conflict_counts_collided_stx": (P0.with_(setup_attempts=1),
                                         [(0.001, "req", b"A"), (0.002, "rx", 0x02), (0.003, "rx", BLOCK_A)]),
    # a high-priority station sees the partner's STX 14 ms into its ADT: retry at 20 ms, or 34 ms
    "a23_restart_adt_on_conflict_stx": (P0.with_(priority="high"), [(0.001, "req", b"A"), (0.015, "rx", 0x02)]),
    # no answer to STX: the retry one character time later, or not
    "timer_grace_one_character": (P, [(0.001, "req", b"A")]),
}
STATUS_ONLY = {"a9_report_each_error", "a15_break_status_on_send", "a19_wait_repetition_code"}
OTHER_VALUE = {"a15_break_status_on_send": Code.ABORTED_BY_RESET, "a19_wait_repetition_code": Code.BCC_ERROR}


def test_every_reading_has_a_scenario():
    assert set(SCENARIOS) == {f.name for f in dataclasses.fields(Readings)}


@pytest.mark.parametrize("field", sorted(SCENARIOS))
def test_readings_flip_the_wire(field):
    """Each reading changes what the station does when flipped: the bytes on the wire or their
    timing, or (A9, A15, A19: readings of the STATUS reporting) the STATUS events."""
    p, script = SCENARIOS[field]
    default = getattr(READINGS, field)
    other = OTHER_VALUE.get(field, not default)
    wire_a, codes_a = _wire(READINGS, p, script)
    wire_b, codes_b = _wire(dataclasses.replace(READINGS, **{field: other}), p, script)
    if field in STATUS_ONLY:
        assert wire_a == wire_b and codes_a != codes_b
        assert (default in codes_a and other in codes_b) or field == "a9_report_each_error"
    else:
        assert wire_a != wire_b, (wire_a, wire_b)


def test_reading_differences_are_the_ones_described():
    """A few of the differences, spelled out."""
    # A2 / A18: the job waits for T_BLOCK (4 s) in the default reading
    wire, _ = _wire(READINGS, *SCENARIOS["a2_cdt_timeout_awaits_repetition"])
    stx = [t for t, b in wire if b == 0x02]
    assert stx and stx[0] == pytest.approx(0.01 + P0.cdt + 4.0)
    wire, _ = _wire(dataclasses.replace(READINGS, a2_cdt_timeout_awaits_repetition=False),
                    *SCENARIOS["a2_cdt_timeout_awaits_repetition"])
    assert [t for t, b in wire if b == 0x02][0] == pytest.approx(0.05)
    # A16: the NAK once the line has been quiet for CDT, or at T_NAKTIM (400 ms after STX)
    wire, codes = _wire(READINGS, *SCENARIOS["a16_garbage_during_buffer_wait_quiet_nak"])
    assert wire[1:] == [(pytest.approx(0.012 + P0.cdt), 0x15)] and codes == [Code.RX_SETUP_ERROR]
    wire, codes = _wire(dataclasses.replace(READINGS, a16_garbage_during_buffer_wait_quiet_nak=False),
                        *SCENARIOS["a16_garbage_during_buffer_wait_quiet_nak"])
    assert wire[1:] == [(pytest.approx(0.41), 0x15)]
    assert codes == [Code.RX_SETUP_ERROR, Code.NO_RECEIVE_BUFFER]
    # A18: with one attempt the receiver is idle at once; the figure's 6 keep it waiting
    wire, _ = _wire(READINGS, *SCENARIOS["a18_receiver_uses_own_attempt_limit"])
    assert (pytest.approx(0.02), 0x02) in wire
    wire, _ = _wire(dataclasses.replace(READINGS, a18_receiver_uses_own_attempt_limit=False),
                    *SCENARIOS["a18_receiver_uses_own_attempt_limit"])
    assert [t for t, b in wire if b == 0x02][0] == pytest.approx(0.012 + 4.0)
