"""Attempt counters start afresh for every job, every transmission attempt and every block
(Fig. 2-10 'send request', 'W := 1', 'X := 1'; Figs. 2-11, 2-12 'W'). Each case runs two
jobs (or blocks) where the first one used up attempts, so an IUT that never resets its
counters runs out in the second."""

from dataclasses import replace

from ._build import (DLE, NAK, PLAIN, RETRY, STX, body, case, echo_send, expect, prime, send, silence)
from .receive import bad_block

ECHO = ["echo"]
SECOND = b"\x34\x35\x36"


def cases(p):
    N, M = p.setup_attempts, p.transmission_attempts
    P, Q = PLAIN, SECOND

    def setups_then_success(payload, job):
        b = body(payload, p)
        return (sum(([expect(STX, within=RETRY, note=f"job {job}: STX {i + 1}"), send(NAK, note="refused")]
                     for i in range(N - 1)), [])
                + [expect(STX, within=RETRY, note=f"job {job}: STX {N}, the last allowed"), send(DLE),
                   expect(b, within="CDT"), send(DLE, note=f"job {job} done")])

    def blocks_then_success(payload, job):
        b = body(payload, p)
        return (sum(([expect(STX, within=RETRY, note=f"job {job}: attempt {i + 1}"), send(DLE), expect(b, within="CDT"),
                      send(NAK, note="refused")] for i in range(M - 1)), [])
                + [expect(STX, within=RETRY, note=f"job {job}: attempt {M}, the last allowed"), send(DLE),
                   expect(b, within="CDT"), send(DLE, note=f"job {job} done")])

    out = [
        case(p, "COUNTERS.SETUP-PER-JOB", f"Each job gets all {N} setup attempts, also after one that used them up",
             "Fig. 2-10 'send request', 'X := 1', 'X <= 6 / X > 6'; Table 2-4 setup attempts",
             "A new job starts with the setup counter at 1: after a job whose setup succeeded only at the last allowed attempt, the next job again gets all its setup attempts.",
             "send", "sender",
             [prime(P)] + setups_then_success(P, 1) + [prime(Q)] + setups_then_success(Q, 2),
             iut=((), ["16#0702"]), delivered=[P, Q], sent=[P, Q], requires=ECHO, readings=["A8"],
             provenance="[F]", rules=["3964.TX.COUNTERS-PER-JOB"]),
        case(p, "COUNTERS.TRANSMISSION-PER-JOB",
             f"Each job gets all {M} transmission attempts, also after one that used them up",
             "Fig. 2-10 'send request', 'W := 1', 'W+1'; Table 2-4 transmission attempts",
             "A new job starts with the transmission counter at 1: after a job whose block got through only at the last allowed attempt, the next job again gets all its attempts.",
             "release", "sender",
             [prime(P)] + blocks_then_success(P, 1) + [prime(Q)] + blocks_then_success(Q, 2),
             iut=((), ["16#0706", "16#0701"]), delivered=[P, Q], sent=[P, Q], requires=ECHO, readings=["A8"],
             provenance="[F]", rules=["3964.TX.COUNTERS-PER-JOB"]),
    ]
    if M >= 2 and N >= 2:
        b = body(P, p)
        out.append(case(
            p, "COUNTERS.SETUP-PER-ATTEMPT", f"A repeated block gets its {N} setup attempts again",
            "Fig. 2-10 'X := 1', 'W+1'; Table 2-4 setup attempts",
            "A new transmission attempt starts its connection setup afresh: after a block refused at the first setup, the repetition may need all the setup attempts (whether an attempt that used some up resets the counter is open, A4, and not tested).",
            "repetition", "sender",
            [prime(P), expect(STX, within=RETRY, note="attempt 1"), send(DLE), expect(b, within="CDT"),
             send(NAK, note="the block is refused")]
            + sum(([expect(STX, within=RETRY, note=f"attempt 2: STX {i + 1}"), send(NAK, note="refused")]
                   for i in range(N - 1)), [])
            + [expect(STX, within=RETRY, note=f"attempt 2: STX {N}, the last allowed"), send(DLE),
               expect(b, within="CDT"), send(DLE, note="done")],
            iut=((), ["16#0706", "16#0701", "16#0702"]), delivered=[P], sent=[P], requires=ECHO,
            readings=["A4", "A8"], provenance="[F][O]", rules=["3964.TX.SETUP-COUNT-PER-ATTEMPT"]))
    if p.priority == "low" and M >= 2:
        v = _receive_per_block(p)
        if N < 2:
            # the deferred job's next STX is what shows the count on the line; with one setup
            # attempt the collided STX may have used it up (A21), and the job ends with NAK
            v = replace(v, extra={**v.extra, "unsupported": (
                "needs the deferred job to resume after the conflict; with setup_attempts = 1 the collided "
                "STX may have used its only setup attempt (open point A21), so the job may end with NAK instead")})
        out.append(v)
    return out


def _receive_per_block(p):
    """The receiver's count of receptions starts afresh for each block. On the line this shows
    where the IUT holds a deferred job: a low-priority station that took the partner's STX in a
    conflict (Fig. 2-8) resumes its own job only once the reception is over, so after refusing
    a block it keeps quiet while it waits for the repetition, and resumes at once once it has
    given up. Block 1 is refused M-1 times and then accepted; block 2 is refused once: an IUT
    that carried the count over would give up and resume its job instead of waiting."""
    M = p.transmission_attempts
    A, B1, B2 = PLAIN, b"\x41\x42\x43", b"\x44\x45\x46"
    refused, code = bad_block(p)

    def crossing(job):
        return [expect(STX, within=RETRY, note=f"the IUT's STX for {job}"),
                send(STX, note="the tester's STX (high priority) crosses it"),
                expect(DLE, note="the IUT defers its job and receives")]

    def deferred(payload, job):
        return [expect(STX, within=RETRY, note=f"the deferred job: {job}"), send(DLE),
                expect(body(payload, p), within="CDT"), send(DLE, note="done")]

    steps = ([prime(A)] + crossing("A")
             + sum((refused + [send(STX, note=f"repetition {i + 1} of block 1"), expect(DLE)] for i in range(M - 1)), [])
             + [send(body(B1, p), note="block 1, intact at the last allowed reception"), expect(DLE)]
             + deferred(A, "A") + crossing("the echo of block 1")
             + refused
             + [silence("2*CDT", note="block 2 was refused once: the IUT waits for its repetition and holds its job"),
                send(STX, note="repetition of block 2"), expect(DLE),
                send(body(B2, p), note="block 2, intact"), expect(DLE)]
             + deferred(B1, "the echo of block 1"))
    return case(p, "COUNTERS.RECEIVE-PER-BLOCK", f"Each block gets all {M} receptions, also after one that used them up",
                "Fig. 2-11 'STX received'; Fig. 2-12 'W > 5 / W <= 5', 'note repetition expected'; Fig. 2-8",
                "The receiver counts the receptions of each block afresh: after a block accepted only at its last allowed reception, the next block refused once is still awaited (the IUT holds its deferred job and stays quiet), not given up.",
                "repetition", "both", steps,
                iut=([code], ["16#0801", "16#0815"]), delivered=[A, B1, B2], sent=[A, B1], echo_after=[B2],
                requires=ECHO, readings=["A18", "A21"], provenance="[F][I]", timing_sensitive=True,
                rules=["3964.RX.COUNT-PER-BLOCK"])
