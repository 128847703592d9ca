"""Initialization conflict (§2.2.2 Initialization conflict; Figs. 2-8, 2-10, 2-11). The cases
follow the IUT's own priority from its profile; the tester takes the other one."""

from dataclasses import replace

from ._build import (DLE, NAK, PLAIN, RETRY, STX, body, brk, case, expect, partner, prime, receive_block, send, silence)

ECHO = ["echo"]
OFFSETS = (("0", "AT-ONCE"), ("0.25*ADT", "QUARTER-ADT"), ("0.5*ADT", "HALF-ADT"), ("0.75*ADT", "THREE-QUARTERS-ADT"))
THEIRS = b"\x41\x42\x43"


def cases(p):
    own, theirs = PLAIN, THEIRS
    out = []
    if p.priority == "low":
        for at, name in OFFSETS:
            steps = [prime(own), expect(STX, within=RETRY, note="the IUT's STX"),
                     send(STX, at=at, note="the tester's STX (high priority) crosses it"),
                     expect(DLE, note="the IUT defers and acknowledges"),
                     send(body(theirs, p), note="the tester's block"), expect(DLE, note="received")]
            if p.setup_attempts >= 2:
                steps += [expect(STX, within=RETRY, note="the deferred job's next setup attempt"), send(DLE),
                          expect(body(own, p), within="CDT", note="the IUT's own block"), send(DLE)]
            else:
                # one setup attempt: whether the collided STX used it up is open (A21), so the
                # deferred job may go out or end with NAK; the tester answers either way
                steps.append(partner("ADT + BLOCK + 20*CHAR", "the deferred job: its STX, or its end (A21)"))
            out.append(case(
                p, f"CONFLICT.LOW-{name}", f"Conflict, IUT low: the tester's STX {name.lower().replace('-', ' ')} into the IUT's setup",
                "§2.2.2 Initialization conflict; Fig. 2-8; Fig. 2-10 'low priority'; Fig. 2-11 'initialization conflict, low priority'",
                "A low-priority station that receives STX while waiting for its setup DLE defers its job, answers DLE, receives the block, and then sets up its own connection again.",
                "conflict", "both", steps,
                iut=((), ["16#0709"] if p.setup_attempts < 2 else ()),
                delivered=[own, theirs], sent=[own] if p.setup_attempts >= 2 else [],
                echo_after=[theirs] if p.setup_attempts >= 2 else [],   # else the partner step takes it
                requires=ECHO, readings=["A8", "A21"], provenance="[S][F]",
                rules=["3964.CONFLICT.LOW-DEFERS"] + (["3964.CONFLICT.LOW-RESUMES"] if p.setup_attempts >= 2 else [])))
    if p.priority == "low" and p.setup_attempts >= 2:
        out.append(case(
            p, "CONFLICT.LOW-RECEPTION-BROKEN-BY-BREAK", "Conflict, IUT low: a BREAK ends the conflict reception at once, without NAK",
            "§2.2.2 Error handling; Fig. 2-11 legend 'immediate return to the initial state on BREAK'; §2.2.2 Initialization conflict",
            "A BREAK during the reception of a conflict ends it at once, without a NAK; whether the deferred job survives it is open (A21): it going out once the line is restored is our reading, its loss is informational.",
            "break", "both",
            [prime(own), expect(STX, within=RETRY, note="the IUT's STX"),
             send(STX, note="the tester's STX (high priority) crosses it"), expect(DLE, note="the IUT defers and receives"),
             send("41 42", note="the tester's block begins"),
             brk("4*CHAR", note="BREAK: the line is held at space (shorter than ADT, so the deferred STX is not lost in it)"),
             expect(STX, after="-6*CHAR", within=RETRY, optional=True, absent_grade="informational",
                    note="the deferred job's STX (it may start while the line is still at space), or nothing (A21)"),
             silence("2*CHAR", note="no NAK"),
             partner("3*ADT + BLOCK + 100*CHAR", note="the tester answers the deferred job, if it comes")],
            iut=(["16#080D"], ["16#1E0D", "16#0709", "16#0703", "16#0701"]), delivered=[own], sent=[own], requires=ECHO,
            readings=["A15", "A21"], provenance="[S][F][O]",
            rules=["3964.BREAK.RECEIVE", "3964.CONFLICT.JOB-KEPT"]))
    if p.priority == "high":
        for at, name in OFFSETS:
            room = _high_room(p, at, name)
            if name == "THREE-QUARTERS-ADT":
                # no room for a silence before the IUT's ADT runs out: the DLE follows the STX
                # back to back, and an IUT that answered the STX (with DLE) fails at its block
                wait = [send(DLE, note="the tester defers and acknowledges the IUT's STX")]
            else:
                wait = [silence("0.15*ADT", note="the IUT must not answer it"),
                        send(DLE, note="the tester defers and acknowledges the IUT's STX")]
            out.append(case(
                p, f"CONFLICT.HIGH-{name}", f"Conflict, IUT high: the tester's STX {name.lower().replace('-', ' ')} into the IUT's setup",
                "§2.2.2 Initialization conflict; Fig. 2-10 'high priority'",
                "A high-priority station neither answers nor is disturbed by the partner's STX during its own setup: it waits for the DLE and sends its block.",
                "conflict", "both",
                [prime(own), expect(STX, within=RETRY, note="the IUT's STX"),
                 send(STX, at=at, note="the tester's STX (low priority) crosses it")] + wait
                + [expect(body(own, p), within="CDT", note="the IUT's block"), send(DLE)]
                + receive_block(theirs, p),
                delivered=[own, theirs], sent=[own], echo_after=[theirs], requires=ECHO, readings=["A23"],
                provenance="[S][F][I]", rules=["3964.CONFLICT.HIGH-WAITS"],
                extra={"unsupported": room} if room else None))
        out.append(_high_no_dle(p, own))
    return out



def _high_room(p, at: str, name: str) -> str:
    """Why the tester's STX at ``at`` after the IUT's, then (after a silence of 0.15*ADT but
    at three quarters) its DLE, cannot all arrive within the IUT's ADT with a character to
    spare ("": they can). At a low baud rate and a short ADT two characters take longer than
    the quarter of ADT left; the IUT then rightly times out and the case is not about that."""
    frac = float(at.split("*")[0]) + (0.15 if name not in ("THREE-QUARTERS-ADT",) else 0.0)
    if frac * p.adt + 3 * p.char_time <= p.adt:
        return ""
    return (f"the tester's STX at {at} after the IUT's, then its DLE, do not fit into ADT = {p.adt_ms} ms with a "
            f"character to spare at {p.baud_rate} bit/s (a character takes {p.char_time * 1000:.1f} ms)")


def _high_no_dle(p, own):
    """The partner's STX crosses the IUT's and no DLE follows: the IUT's ADT runs out, which is
    a failed setup attempt: a new STX, or with ``setup_attempts = 1`` NAK and the end of the job
    (Fig. 2-10 'T > T_ADT', 'X > 6', 'send NAK')."""
    steps = [prime(own), replace(expect(STX, within=RETRY, note="the IUT's STX"), mark=True),
             send(STX, note="the tester's STX crosses it; no DLE follows")]
    window = dict(after="ADT - 2*CHAR", within="ADT + 4*CHAR", since="mark")
    title = "Conflict, IUT high: no DLE follows the partner's STX, so ADT runs out and "
    if p.setup_attempts >= 2:
        steps += [expect(STX, note="the next STX, ADT after the first (not restarted by the tester's STX: A23)", **window),
                  send(DLE), expect(body(own, p), within="CDT"), send(DLE)]
        title += "a new STX follows"
        iut, sent, rules = ((), ["16#0703"]), [own], ["3964.CONFLICT.HIGH-NO-DLE"]
    else:
        steps += [expect(NAK, note="setup_attempts = 1: the IUT's NAK, ADT after its STX (not restarted: A23)",
                         **window)]
        title += "its only setup attempt has failed: NAK (setup_attempts = 1)"
        iut, sent = (["16#0703|16#0709"], ["16#0703", "16#0709"]), []
        rules = ["3964.CONFLICT.HIGH-NO-DLE", "3964.TX.SETUP-FINAL-NAK"]
    return case(
        p, "CONFLICT.HIGH-NO-DLE", title, "Fig. 2-10 'high priority', 'T > T_ADT', 'X+1'; Table 8-1 16#0702, 16#0703",
        "The partner's STX is no refused setup (STX is excluded from 16#0702): the high-priority station keeps "
        "waiting and its ADT runs out, a failed setup attempt: it sends a new STX, or NAK if it has no attempt left.",
        "conflict", "both", steps, iut=iut, delivered=[own], sent=sent, requires=ECHO, readings=["A23"],
        provenance="[F][S]", rules=rules)
