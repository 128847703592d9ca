"""Connection release and transmission attempts (§2.2.2 Send/release; Fig. 2-10;
3964r.md §7.3-7.5)."""

from ._build import DLE, NAK, STX, body, case, echo_send, expect, h, prime, send, send_error

ECHO = ["echo"]


def cases(p):
    M = p.transmission_attempts
    P = h("31 10 32 15 03")
    B = body(P, p)
    return [
        case(p, "RELEASE.NAK-RETRY", "Block refused with NAK: the IUT repeats it from STX",
             "§2.2.2 Send/release; Table 8-1 16#0706, 16#0701; 3964r.md §7.3 item 4, §7.4 item 5",
             "A NAK after the end sequence is a failed transmission attempt: the sender begins again with STX (first repetition: 16#0701).",
             "repetition", "sender",
             [prime(P), expect(STX), send(DLE), expect(B, within="CDT"), send(NAK, note="refused"),
              expect(STX, note="the repetition")] + echo_send(P, p)[1:],
             iut=((), ["16#0706", "16#0701"]), delivered=[P], sent=[P], requires=ECHO, provenance="[S][F]"),
        case(p, "RELEASE.OTHER-RETRY", "Block answered by another character (even STX): the IUT repeats it",
             "§2.2.2 Send/release; Table 8-1 16#0706; 3964r.md §7.3 item 4, §9 item 6",
             "Any character but DLE after the end sequence, STX included, is a failed transmission attempt, not a conflict.",
             "repetition", "sender",
             [prime(P), expect(STX), send(DLE), expect(B, within="CDT"), send(STX, note="STX instead of DLE"),
              expect(STX, note="the repetition, not a DLE")] + echo_send(P, p)[1:],
             iut=((), ["16#0706", "16#0701"]), delivered=[P], sent=[P], requires=ECHO, provenance="[S][I]"),
        case(p, "RELEASE.CHARACTER-ERROR-RETRY", "Block answered by a corrupted character: the IUT repeats it",
             "Fig. 2-10 'invalid character'; Table 8-1 16#080C; 3964r.md §7.3 item 4",
             "A character with a transmission error after the end sequence is a failed transmission attempt.",
             "character-error", "sender",
             [prime(P), expect(STX), send(DLE), expect(B, within="CDT"), send_error("10", note="DLE with a parity error"),
              expect(STX)] + echo_send(P, p)[1:],
             iut=((), ["16#080C", "16#0706", "16#0701"]), delivered=[P], sent=[P], requires=ECHO, provenance="[F]"),
        case(p, "RELEASE.TIMEOUT-RETRY", "No acknowledgement after the block: repeated after ADT, not before",
             "§2.2.2 Send/release; Table 8-1 16#0707; 3964r.md §7.3 item 4, §17 A12",
             "When no DLE comes within ADT after the end sequence the sender repeats the block from STX.",
             "repetition", "sender",
             [prime(P), expect(STX), send(DLE), expect(B, within="CDT", note="the tester stays silent"),
              expect(STX, after="ADT - CHAR", within="ADT + 2*CHAR", note="the repetition")] + echo_send(P, p)[1:],
             iut=((), ["16#0707", "16#0701"]), delivered=[P], sent=[P], requires=ECHO, readings=["A12"],
             provenance="[S]"),
        case(p, "RELEASE.ATTEMPTS-REFUSED", f"Every block refused: exactly {M} blocks, then one NAK",
             "§2.2.2 Send/release; Fig. 2-10 'W+1'; Table 2-4 'including the first'; Table 8-1 16#070A; 3964r.md §7.4, §7.5",
             "The sender makes exactly 'transmission attempts' attempts, the first included, then sends NAK (16#070A).",
             "release", "sender",
             [prime(P)] + sum(([expect(STX, note=f"attempt {i + 1}"), send(DLE), expect(B, within="CDT"), send(NAK)]
                               for i in range(M)), []) + [expect(NAK, note="the sender's NAK")],
             iut=(["16#0706|16#070A"], ["16#0701"]), delivered=[P], requires=ECHO, readings=["A3", "A5"],
             provenance="[S][F]"),
        case(p, "RELEASE.ATTEMPTS-TIMEOUT", f"No block acknowledged: {M} blocks at ADT spacing, then NAK",
             "§2.2.2 Send/release; Table 8-1 16#0707, 16#070A; 3964r.md §7.3, §13.5 D13",
             "Release timeouts are counted as transmission attempts; after the last the sender sends NAK (16#0707, 16#070A).",
             "release", "sender",
             [prime(P), expect(STX), send(DLE), expect(B, within="CDT")]
             + sum(([expect(STX, after="ADT - CHAR", within="ADT + 2*CHAR", note=f"attempt {i + 2}"), send(DLE),
                     expect(B, within="CDT")] for i in range(M - 1)), [])
             + [expect(NAK, after="ADT - CHAR", within="ADT + 2*CHAR", note="NAK")],
             iut=(["16#0707|16#070A"], ["16#0701"]), delivered=[P], requires=ECHO, readings=["A12"],
             provenance="[S]"),
    ]
