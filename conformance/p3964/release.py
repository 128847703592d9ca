"""Connection release and transmission attempts (§2.2.2 Send/release; Fig. 2-10; Tables 2-4,
8-1)."""

from ._build import (DLE, NAK, PLAIN, RETRY, STX, body, case, echo_send, expect, long_payload, prime, send,
                     send_error)

ECHO = ["echo"]


def cases(p):
    M = p.transmission_attempts
    P = PLAIN
    B = body(P, p)
    return [
        _refused(p, "RELEASE.NAK-RETRY", "Block refused with NAK",
                 "§2.2.2 Send/release; Fig. 2-10 'any character except DLE', 'W+1'; Table 8-1 16#0706, 16#0701",
                 "A NAK after the end sequence is a failed transmission attempt",
                 "repetition", [send(NAK, note="refused")], ("16#0706",), provenance="[S][F]",
                 rules=["3964.TX.RELEASE-REFUSED"]),
        _refused(p, "RELEASE.OTHER-RETRY", "Block answered by another character (even STX)",
                 "§2.2.2 Send/release; Fig. 2-10 'any character except DLE'; Table 8-1 16#0706",
                 "Any character but DLE after the end sequence, STX included, is a failed transmission attempt, not a conflict",
                 "repetition", [send(STX, note="STX instead of DLE")], ("16#0706",), provenance="[S][I]",
                 rules=["3964.TX.RELEASE-REFUSED"]),
        _refused(p, "RELEASE.CHARACTER-ERROR-RETRY", "Block answered by a corrupted character",
                 "Fig. 2-10 'invalid character'; Table 8-1 16#080C",
                 "A character with a transmission error after the end sequence is a failed transmission attempt",
                 "character-error", [send_error("10", note="DLE with a parity error")], ("16#080C", "16#0706"),
                 provenance="[F]", rules=["3964.TX.RELEASE-CHARACTER-ERROR"]),
        _refused(p, "RELEASE.TIMEOUT-RETRY", "No acknowledgement after the block within ADT",
                 "§2.2.2 Send/release; Fig. 2-10 'start T_ADT', 'T > T_ADT'; Table 8-1 16#0707",
                 "When no DLE comes within ADT after the end sequence (counted from its last byte or from DLE ETX: A12) "
                 "the transmission attempt has failed; the sender does not give up on it early",
                 "repetition", [], ("16#0707",), timeout=True, provenance="[S]", rules=["3964.TX.RELEASE-TIMEOUT"]),
        case(p, "RELEASE.ATTEMPTS-REFUSED", f"Every block refused: exactly {M} blocks, then one NAK",
             "§2.2.2 Send/release; Fig. 2-10 'W+1', 'send NAK'; Table 2-4 transmission attempts; Table 8-1 16#070A",
             "The sender makes exactly 'transmission attempts' attempts, the first included, then sends NAK (16#070A).",
             "release", "sender",
             [prime(P)] + sum(([expect(STX, within=RETRY, note=f"attempt {i + 1}"), send(DLE), expect(B, within="CDT"),
                                send(NAK)] for i in range(M)), [])
             + [expect(NAK, within=RETRY, note="the sender's NAK")],
             iut=(["16#0706|16#070A"], ["16#0701"]), delivered=[P], requires=ECHO, readings=["A3", "A5", "A8", "A9"],
             provenance="[S][F]", rules=["3964.TX.ATTEMPTS", "3964.TX.FINAL-NAK"]),
        case(p, "RELEASE.ATTEMPTS-TIMEOUT", f"No block acknowledged: {M} blocks at ADT spacing, then NAK",
             "§2.2.2 Send/release; Fig. 2-10 'T > T_ADT', 'W+1', 'send NAK'; Table 8-1 16#0707, 16#070A",
             "Release timeouts are counted as transmission attempts; after the last the sender sends NAK (16#0707, 16#070A).",
             "release", "sender",
             [prime(P), expect(STX, within=RETRY), send(DLE), expect(B, within="CDT")]
             + sum(([expect(STX, after="ADT - CHAR", within="ADT + 2*CHAR", note=f"attempt {i + 2}"), send(DLE),
                     expect(B, within="CDT")] for i in range(M - 1)), [])
             + [expect(NAK, after="ADT - CHAR", within="ADT + 2*CHAR", note="NAK")],
             iut=(["16#0707|16#070A"], ["16#0701"]), delivered=[P], requires=ECHO, readings=["A9", "A12"],
             provenance="[S]", rules=["3964.TX.ATTEMPTS", "3964.TX.FINAL-NAK"]),
        _mixed(p),
    ]


def _refused(p, id, title, ref, rule, group, answer, codes, *, timeout=False, provenance, rules):
    """The IUT's block is answered by ``answer`` (the tester's steps; none: no answer within
    ADT). With transmission attempts left (Table 2-4) the IUT repeats the block from STX (its
    first repetition: 16#0701); with ``transmission_attempts = 1`` that was its only attempt: it
    sends NAK and gives up (16#070A; Fig. 2-10 'W > 6', 'send NAK')."""
    P = PLAIN
    window = dict(after="ADT - CHAR", within="ADT + 2*CHAR") if timeout else dict(within=RETRY)
    steps = [prime(P), expect(STX, within=RETRY), send(DLE),
             expect(body(P, p), within="CDT", note="the tester stays silent" if timeout else "")] + answer
    readings = ["A12"] if timeout else ["A8"]
    if p.transmission_attempts >= 2:
        steps += [expect(STX, note="the repetition", **window)] + echo_send(P, p)[1:]
        title += ": the IUT repeats it from STX" + (" after ADT, not before" if timeout else "")
        rule += ": the sender begins again with STX (first repetition: 16#0701)."
        iut, sent = ((), list(codes) + ["16#0701"]), [P]
    else:
        steps += [expect(NAK, note="transmission_attempts = 1: the sender's NAK, no repetition", **window)]
        title += ": its only attempt (transmission_attempts = 1), so NAK and the job ends"
        rule += "; with transmission_attempts = 1 there is no other, so the sender sends NAK and gives up (16#070A)."
        iut, sent = (["|".join(codes + ("16#070A",))], list(codes) + ["16#070A"]), []
        rules, readings = list(rules) + ["3964.TX.FINAL-NAK"], readings + ["A9"]
    return case(p, id, title, ref, rule, group, "sender", steps, iut=iut, delivered=[P], sent=sent, requires=ECHO,
                readings=readings, provenance=provenance, rules=rules)


def _mixed(p):
    """Transmission attempts failing in turn by a NAK after the block, a timeout, a corrupted
    answer, another character, a NAK during the data: one counter for all of them."""
    M = p.transmission_attempts
    L = long_payload(p)
    B = body(L, p)
    kinds = ("NAK after the block", "no answer within ADT", "a corrupted answer", "another character",
             "NAK during the data")
    steps = [prime(L), expect(STX, within=RETRY, note="attempt 1")]
    for i in range(M):
        kind = kinds[i % len(kinds)]
        steps.append(send(DLE))
        if kind == "NAK during the data":
            steps += [expect(L[:10], within="CDT"), send(NAK, note="NAK during the data"),
                      expect(B[10:], partial=True, after="-20*CHAR", within="4*CHAR", note="the IUT stops")]
        else:
            steps.append(expect(B, within="CDT"))
            if kind == "NAK after the block":
                steps.append(send(NAK, note="refused"))
            elif kind == "a corrupted answer":
                steps.append(send_error("10", note="DLE with a parity error"))
            elif kind == "another character":
                steps.append(send("41", note="not DLE"))
        timeout = kind == "no answer within ADT"
        window = dict(after="ADT - CHAR", within="ADT + 2*CHAR") if timeout else dict(within=RETRY)
        last = i == M - 1
        steps.append(expect(NAK if last else STX, note=("the sender's NAK" if last else f"attempt {i + 2}")
                            + f" (after {kind})", **window))
    return case(p, "RELEASE.ATTEMPTS-MIXED", f"Transmission attempts failing in different ways: {M} in all, then NAK",
                "Table 2-4 transmission attempts ('including the first'); Fig. 2-10 'W := 1', 'W+1', 'send NAK'",
                "Failures after the block (NAK, another or a corrupted character, no answer) and in the data (NAK) count in the one transmission counter: exactly 'transmission attempts' blocks, then NAK.",
                "release", "sender", steps,
                iut=(["16#0706|16#0707|16#080C|16#0704|16#070A"],
                     ["16#0701", "16#0704", "16#0706", "16#0707", "16#080C", "16#070A"]),
                delivered=[L], requires=ECHO, readings=["A3", "A5", "A8", "A9", "A12"], provenance="[S][F]",
                rules=["3964.TX.ATTEMPTS"])
