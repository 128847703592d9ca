"""Initialization conflict (§2.2.2 Initialization conflict; Figs. 2-8, 2-10; 3964r.md §9).
The cases follow the IUT's own priority from its profile."""

from ._build import DLE, STX, body, case, expect, h, prime, receive_block, send, silence

ECHO = ["echo"]
OFFSETS = (("0", "AT-ONCE"), ("0.25*ADT", "QUARTER-ADT"), ("0.5*ADT", "HALF-ADT"), ("0.75*ADT", "THREE-QUARTERS-ADT"))


def cases(p):
    own, theirs = h("31 32 33"), h("41 42 10")
    out = []
    if p.priority == "low":
        for at, name in OFFSETS:
            out.append(case(
                p, f"CONFLICT.LOW-{name}", f"Conflict, IUT low: the tester's STX {name.lower().replace('-', ' ')} into the IUT's setup",
                "§2.2.2 Initialization conflict; Fig. 2-8; 3964r.md §9 item 3",
                "A low-priority station that receives STX while waiting for its setup DLE defers its job, answers DLE, receives the block, and then sets up its own connection again.",
                "conflict", "both",
                [prime(own), expect(STX, note="the IUT's STX"),
                 send(STX, at=at, note="the tester's STX (high priority) crosses it"),
                 expect(DLE, note="the IUT defers and acknowledges"),
                 send(body(theirs, p), note="the tester's block"), expect(DLE, note="received"),
                 expect(STX, note="the deferred job's next setup attempt"), send(DLE),
                 expect(body(own, p), within="CDT", note="the IUT's own block"), send(DLE)],
                delivered=[own, theirs], sent=[own], echo_after=[theirs], requires=ECHO, readings=["A21"],
                provenance="[S][F]"))
    else:
        for at, name in OFFSETS[:3]:
            out.append(case(
                p, f"CONFLICT.HIGH-{name}", f"Conflict, IUT high: the tester's STX {name.lower().replace('-', ' ')} into the IUT's setup",
                "§2.2.2 Initialization conflict; Fig. 2-10 'high priority'; 3964r.md §9 item 4",
                "A high-priority station neither answers nor is disturbed by the partner's STX during its own setup: it waits for the DLE and sends its block.",
                "conflict", "both",
                [prime(own), expect(STX, note="the IUT's STX"),
                 send(STX, at=at, note="the tester's STX (low priority) crosses it"),
                 silence("0.15*ADT", note="the IUT must not answer it"),
                 send(DLE, note="the tester defers and acknowledges the IUT's STX"),
                 expect(body(own, p), within="CDT", note="the IUT's block"), send(DLE)]
                + receive_block(theirs, p),
                delivered=[own, theirs], sent=[own], echo_after=[theirs], requires=ECHO, readings=["A23"],
                provenance="[S][F][I]"))
    return out
