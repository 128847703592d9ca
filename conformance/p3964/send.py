"""The IUT as sender, made to send by the echo convention (§2.2.2 Send/setup, Sending data;
Figs. 2-4, 2-5, 2-10; Tables 2-4, 8-1)."""

from ._build import (DLE, NAK, PLAIN, RETRY, STX, body, case, echo_send, expect, h, long_payload, nak_after_cdt,
                     plain_1024, prime, send, send_error, seven_bit)

ECHO = ["echo"]
SEND_REF = "§2.2.2 Sending data; Fig. 2-5; Fig. 2-10 'send block, possibly with doubled DLE', 'send DLE, ETX', 'send BCC'"


def _echo_case(p, id, title, payload, rule, rules, ref=SEND_REF, max_gap=None, provenance="[S][F]"):
    payload = h(payload)
    return case(p, id, title, ref, rule, "send", "sender", [prime(payload)] + echo_send(payload, p, max_gap=max_gap),
                delivered=[payload], sent=[payload], requires=ECHO, provenance=provenance, rules=rules)


def _interrupted(p, id, title, ref, rule, stimulus, rules, *, note, readings=("A7",), quiet=None, stop_after="-20*CHAR"):
    """The IUT sends a 64-byte block; after its first 10 data bytes the tester sends
    ``stimulus`` (steps); the IUT stops, waits for CDT of quiet, sends NAK and begins again;
    with ``transmission_attempts = 1`` that NAK ends the job (Fig. 2-10 'W > 6'; one NAK, A6)."""
    L = long_payload(p)
    rest = body(L, p)[10:]
    steps = ([prime(L), expect(STX, within=RETRY), send(DLE), expect(L[:10], within="CDT", note="the first 10 data bytes")]
             + stimulus
             + [expect(rest, partial=True, after=stop_after, within="4*CHAR", note="the IUT stops")]
             + (quiet or [nak_after_cdt(since="sent")]))
    if p.transmission_attempts >= 2:
        steps += [expect(STX, within=RETRY, note="a new attempt")] + echo_send(L, p)[1:]
        iut, sent = ((), ["16#0704", "16#0701", "16#080C"]), [L]
    else:
        title += " (transmission_attempts = 1: that NAK ends the job)"
        iut, sent = (["16#0704|16#070A"], ["16#0704", "16#080C", "16#070A"]), []
        readings = tuple(readings) + ("A6",)
    return case(p, id, title, ref, rule, "send", "sender", steps, iut=iut, delivered=[L], sent=sent, requires=ECHO,
                readings=list(readings), provenance="[S][I]", rules=rules, notes=note)


def cases(p):
    N, M = p.setup_attempts, p.transmission_attempts
    P = PLAIN
    bcc_rule = ["3964.TX.BCC"] if p.has_bcc else ["3964.TX.NO-BCC"]
    out = [
        _echo_case(p, "SEND.ECHO-PLAIN", "The IUT sends a block: STX, data, DLE ETX" + (", BCC" if p.has_bcc else ""), P,
                   "A sender's block is STX, the partner's DLE, the data, DLE ETX and, for 3964R, the XOR of all bytes after STX through DLE ETX; a 3964 sender sends no BCC.",
                   ["3964.TX.SETUP-STX", "3964.TX.BLOCK-LAYOUT"] + bcc_rule),
        _echo_case(p, "SEND.ECHO-P1", "The IUT sends a block with a data DLE: doubled" + (", counted twice in the BCC" if p.has_bcc else ""),
                   "31 10 32 15 03",
                   "A sender doubles every data DLE" + (" and its BCC counts both DLEs." if p.has_bcc else "."),
                   ["3964.TX.DLE-DOUBLING"] + (["3964.TX.BCC"] if p.has_bcc else []),
                   ref="§2.2.2 Control characters, Note; §2.2.2 Block check character, Note; Fig. 2-5"),
        _echo_case(p, "SEND.ECHO-ONE-BYTE", "The IUT sends a one-byte block", "00",
                   "The smallest block, one user byte, is framed like any other.", ["3964.TX.LENGTH"],
                   ref="Table 6-2 LEN 1..1024; Fig. 2-5"),
        _echo_case(p, "SEND.ECHO-ONLY-DLES", "The IUT sends a block made of data DLEs", "10 10 10 10 10",
                   "Every data DLE is sent twice, also in a block that holds nothing else" + ("; the BCC counts both." if p.has_bcc else "."),
                   ["3964.TX.DLE-DOUBLING"], ref="§2.2.2 Control characters, Note; Fig. 2-10"),
        _echo_case(p, "SEND.ECHO-CONTROL-VALUES", "The IUT sends STX, ETX, NAK, 00 and the highest value as plain data",
                   seven_bit(p, "02 03 15 00 FF 10 02 15 03"),
                   "Only DLE is doubled; 02, 03, 15, 00 and FF (7F with 7 data bits) go out unchanged.",
                   ["3964.TX.ONLY-DLE-DOUBLED"], ref="§2.2.2 Control characters; Fig. 2-12", provenance="[S][I]"),
        _echo_case(p, "SEND.ECHO-MAX-1024", "The IUT sends a block of 1024 bytes without gaps longer than CDT",
                   plain_1024(p),
                   "A block of 1024 user bytes goes out whole, and the sender does not pause longer than CDT between two of its characters (the receiver would NAK).",
                   ["3964.TX.LENGTH", "3964.TX.NO-GAPS"], ref="§2.2.2 Sending data; §7.3 Note; Table A-5"),
    ]
    if p.has_bcc:
        out.append(_echo_case(p, "SEND.ECHO-BCC-EQUALS-DLE", "The IUT sends a block whose BCC is 10, not doubled",
                              "41 42 10", "The BCC after DLE ETX is never doubled, even when it equals DLE.",
                              ["3964.TX.BCC-NOT-DOUBLED"], ref="§2.2.2 Block check character; Figs. 2-5, 2-8",
                              provenance="[I]"))
    # connection setup
    out += [
        _setup_failed(p, "SEND.SETUP-REFUSED-BY-NAK", "STX answered by NAK",
                      "§2.2.2 Send/setup; Fig. 2-10 'any character except DLE, STX'; Table 8-1 16#0702",
                      "A NAK in answer to STX is a failed setup attempt: the sender sends STX again (no guard time is set: A8)",
                      "send", [send(NAK, note="refused")], "16#0702", provenance="[S]",
                      rules=["3964.TX.SETUP-REFUSED"]),
        _setup_failed(p, "SEND.SETUP-REFUSED-BY-OTHER", "STX answered by another character",
                      "§2.2.2 Send/setup; Fig. 2-10 'any character except DLE, STX'; Table 8-1 16#0702",
                      "Any character other than DLE or STX in answer to STX is a failed setup attempt",
                      "send", [send("41", note="not DLE")], "16#0702", provenance="[S]",
                      rules=["3964.TX.SETUP-REFUSED"]),
        _setup_failed(p, "SEND.SETUP-TIMEOUT-RETRY", "No answer to STX within ADT",
                      "§2.2.2 Send/setup; Fig. 2-10 'T > T_ADT'; Table 8-1 16#0703",
                      "When no DLE comes within ADT the setup attempt has failed; the sender does not give up on it early",
                      "send", [], "16#0703", timeout=True, provenance="[S]", rules=["3964.TX.SETUP-TIMEOUT"]),
        case(p, "SEND.SETUP-ATTEMPTS-REFUSED", f"Setup refused {N} times: exactly {N} STX, then one NAK",
             "§2.2.2 Send/setup; Fig. 2-10 'X+1', 'X > 6', 'send NAK'; Table 2-4 setup attempts; Table 8-1 16#0709",
             "The sender makes exactly 'setup attempts' connection setups and then sends NAK and gives up (16#0709).",
             "send", "sender",
             [prime(P)] + sum(([expect(STX, within=RETRY, note=f"STX {i + 1}"), send(NAK)] for i in range(N)), [])
             + [expect(NAK, within=RETRY, note="the sender's NAK")],
             iut=(["16#0702|16#0709"], ()), delivered=[P], requires=ECHO, readings=["A8", "A9"], provenance="[S][F]",
             rules=["3964.TX.SETUP-ATTEMPTS", "3964.TX.SETUP-FINAL-NAK"]),
        case(p, "SEND.SETUP-ATTEMPTS-TIMEOUT", f"No answer to {N} STX: then one NAK, each ADT apart",
             "§2.2.2 Send/setup; Fig. 2-10 'T > T_ADT', 'X > 6', 'send NAK'; Table 8-1 16#0703, 16#0709",
             "Setup attempts that time out are counted like refused ones; after the last the sender sends NAK (16#0703, 16#0709).",
             "send", "sender",
             [prime(P), expect(STX, within=RETRY, note="STX 1")]
             + [expect(STX, after="ADT", within="ADT + 2*CHAR", note=f"STX {i + 2}") for i in range(N - 1)]
             + [expect(NAK, after="ADT", within="ADT + 2*CHAR", note="NAK")],
             iut=(["16#0703|16#0709"], ()), delivered=[P], requires=ECHO, readings=["A9"], provenance="[S][F]",
             rules=["3964.TX.SETUP-ATTEMPTS", "3964.TX.SETUP-FINAL-NAK"]),
        _mixed_setup(p, P),
        _setup_failed(p, "SEND.SETUP-CHARACTER-ERROR", "STX answered by a character with a parity error",
                      "Fig. 2-10 'invalid character'; Table 8-1 16#080C",
                      "A corrupted character in answer to STX is a failed setup attempt",
                      "character-error", [send_error("10", note="DLE with a parity error")], "16#080C",
                      also=("16#0702",), provenance="[F]", rules=["3964.TX.SETUP-CHARACTER-ERROR"]),
    ]
    if M >= 2:
        B = body(P, p)
        out.append(case(
            p, "SEND.SETUP-EXHAUSTED-ENDS-JOB", f"Setup attempts used up after a refused block: NAK, the job ends",
            "§2.2.2 Send/setup; Fig. 2-10 'X > 6', 'send NAK'; Table 8-1 16#0709",
            "Running out of setup attempts ends the whole job, even when transmission attempts are left: after a refused block and then the last refused setup, the sender sends NAK and no new STX.",
            "send", "sender",
            [prime(P), expect(STX, within=RETRY), send(DLE), expect(B, within="CDT"), send(NAK, note="the block is refused")]
            + sum(([expect(STX, within=RETRY, note=f"attempt 2, STX {i + 1}"), send(NAK)] for i in range(N)), [])
            + [expect(NAK, within=RETRY, note="the sender's NAK: the job ends, no further STX")],
            iut=(["16#0709|16#0702|16#0706"], ["16#0706", "16#0701", "16#0702", "16#0709"]), delivered=[P],
            requires=ECHO, readings=["A4", "A8", "A9"], provenance="[F]", rules=["3964.TX.SETUP-FINAL-NAK"]))
    # data phase
    L = long_payload(p)
    rest = body(L, p)[10:]
    out += [
        _nak_during_data(p),
        _interrupted(p, "SEND.OTHER-DURING-DATA", "Another character during the data: stop, quiet for CDT, NAK, new STX",
                     "§2.2.2 Sending data; Table 8-1 16#0704",
                     "A character received while sending stops the block; the sender waits until CDT has passed, sends NAK, then STX.",
                     [send("42", note="an unexpected character")], ["3964.TX.DATA-OTHER"],
                     note="The character goes out after the IUT's 10th data byte; the IUT's remaining 54 are still to come."),
        _interrupted(p, "SEND.DLE-DURING-DATA", "A DLE during the data is no acknowledgement: stop, quiet, NAK, new STX",
                     "§2.2.2 Sending data; Table 8-1 16#0704, 16#0706",
                     "A DLE that comes in the middle of the block is 'another character' (A10): the sender stops, waits for CDT of quiet, sends NAK and begins again; it is not taken for the acknowledgement.",
                     [send(DLE, note="a DLE in the middle of the block")], ["3964.TX.DATA-OTHER"],
                     readings=("A7", "A10"), note="DLE during the end sequence would be 'too early' (A10); here the data is far from its end."),
        _interrupted(p, "SEND.STX-DURING-DATA", "A STX during the data is no conflict: stop, quiet, NAK, new STX",
                     "§2.2.2 Sending data; §2.2.2 Initialization conflict; Table 8-1 16#0704",
                     "A STX that comes while the block is being sent is 'another character', not an initialization conflict (that exists only while waiting for the setup DLE): the sender stops, waits for CDT of quiet, sends NAK and begins again.",
                     [send(STX, note="a STX in the middle of the block")], ["3964.TX.DATA-OTHER"],
                     note="Whatever the IUT's priority, it neither defers nor answers DLE here."),
        _interrupted(p, "SEND.CHARACTER-ERROR-DURING-DATA", "A corrupted character during the data: stop, quiet, NAK, new STX",
                     "§2.2.2 Sending data; Fig. 2-10 'invalid character'; Table 8-1 16#0704, 16#080C",
                     "A character with a transmission error that comes while the block is being sent stops it like any other character: quiet for CDT, NAK, a new attempt.",
                     [send_error("42", note="a character with a parity error")], ["3964.TX.DATA-OTHER"],
                     note="The corrupted character goes out after the IUT's 10th data byte."),
        _interrupted(p, "SEND.QUIET-RESTARTS", "Two characters during the data, half a CDT apart: one NAK",
                     "§2.2.2 Sending data",
                     "Further characters during the sender's wait before its NAK start the wait again (A7): one NAK, CDT after the last character (or, not restarted, CDT after the first), never earlier.",
                     [send("42", note="an unexpected character"), send("43", at="0.5*CDT", note="another, half a CDT later")],
                     ["3964.TX.QUIET-RESTARTS"], stop_after="-0.5*CDT - 8*CHAR",
                     quiet=[expect(NAK, after="0.5*CDT - 2*CHAR", within="CDT + 2*CHAR", since="sent",
                                   note="one NAK: CDT after the second (A7), or CDT after the first")],
                     note="The first character goes out after the IUT's 10th data byte."),
        case(p, "SEND.EVERY-ATTEMPT-INTERRUPTED", f"NAK during the data of every attempt: {M} attempts, then NAK",
             "§2.2.2 Sending data; Table 2-4 transmission attempts; Fig. 2-10 'W+1', 'send NAK'; Table 8-1 16#0704, 16#070A",
             "A NAK during the data is a failed transmission attempt; after the last the sender sends NAK (16#070A).",
             "send", "sender",
             [prime(L)] + sum(([expect(STX, within=RETRY, note=f"attempt {i + 1}"), send(DLE), expect(L[:10], within="CDT"),
                                send(NAK), expect(rest, partial=True, after="-20*CHAR", within="4*CHAR")] for i in range(M)), [])
             + [expect(NAK, within=RETRY, note="the sender's NAK")],
             iut=(["16#0704|16#070A"], ["16#0701"]), delivered=[L], requires=ECHO, readings=["A8", "A9"],
             provenance="[S][I]", rules=["3964.TX.ATTEMPTS", "3964.TX.FINAL-NAK"]),
    ]
    return out


def _nak_during_data(p):
    """NAK in the middle of the IUT's block: it stops and, with transmission attempts left,
    begins again with STX and no NAK of its own; with ``transmission_attempts = 1`` it sends NAK
    and gives up (16#070A; Fig. 2-10 'W > 6', 'send NAK')."""
    L = long_payload(p)
    rest = body(L, p)[10:]
    steps = [prime(L), expect(STX, within=RETRY), send(DLE), expect(L[:10], within="CDT", note="the first 10 data bytes"),
             send(NAK, note="NAK in the middle of the block"),
             expect(rest, partial=True, after="-20*CHAR", within="4*CHAR", note="the IUT stops")]
    title = "NAK during the data: the IUT stops, "
    if p.transmission_attempts >= 2:
        steps += [expect(STX, within=RETRY, note="new STX, no NAK before it")] + echo_send(L, p)[1:]
        title += "sends no NAK, starts again with STX"
        iut, sent, rules = ((), ["16#0704", "16#0701"]), [L], ["3964.TX.DATA-NAK"]
    else:
        steps += [expect(NAK, within=RETRY, note="transmission_attempts = 1: the sender's NAK, no new STX")]
        title += "its only attempt (transmission_attempts = 1): NAK, the job ends"
        iut, sent, rules = (["16#0704|16#070A"], ["16#0704", "16#070A"]), [], ["3964.TX.DATA-NAK", "3964.TX.FINAL-NAK"]
    return case(p, "SEND.NAK-DURING-DATA", title, "§2.2.2 Sending data; Table 8-1 16#0704, 16#0701, 16#070A",
                "A NAK received while sending the block cancels it; the sender starts a new attempt with STX and sends "
                "no NAK of its own, or, with no attempt left, sends NAK and gives up.",
                "send", "sender", steps, iut=iut, delivered=[L], sent=sent, requires=ECHO, readings=["A8"],
                provenance="[S]", rules=rules)


def _setup_failed(p, id, title, ref, rule, group, answer, code, *, also=(), timeout=False, provenance, rules):
    """One setup attempt fails by ``answer`` (the tester's steps after the IUT's STX; none: no
    answer within ADT). With setup attempts left (Table 2-4) the IUT sends a new STX and the
    block; with ``setup_attempts = 1`` that was its only attempt (Fig. 2-10 'X > 6'): it sends
    NAK and gives up (16#0709), and the case checks that instead."""
    P = PLAIN
    window = dict(after="ADT", within="ADT + 2*CHAR") if timeout else dict(within=RETRY)
    codes = (code,) + tuple(also)
    steps = [prime(P), expect(STX, within=RETRY, note="the tester stays silent" if timeout else "")] + answer
    if p.setup_attempts >= 2:
        steps += [expect(STX, note="a new setup attempt" + (", ADT later" if timeout else ""), **window)]
        steps += echo_send(P, p)[1:]
        title += ": a new STX" + (" after ADT, not before" if timeout else "") + ", then the block"
        rule += ": the sender tries again with STX."
        iut, sent = ((), list(codes)), [P]
    else:
        steps += [expect(NAK, note="setup_attempts = 1: the sender's NAK, no new STX", **window)]
        title += ": its only setup attempt (setup_attempts = 1), so NAK and the job ends"
        rule += "; with setup_attempts = 1 there is no other, so the sender sends NAK and gives up (16#0709)."
        iut, sent = (["|".join(codes + ("16#0709",))], list(codes) + ["16#0709"]), []
        rules = list(rules) + ["3964.TX.SETUP-FINAL-NAK"]
    readings = ([] if timeout else ["A8"]) + ([] if sent else ["A9"])
    return case(p, id, title, ref, rule, group, "sender", steps, iut=iut, delivered=[P], sent=sent,
                requires=ECHO, readings=readings, provenance=provenance, rules=rules)


def _mixed_setup(p, P):
    """Setup attempts failing in turn by NAK, timeout, character error and a stray character:
    one counter for all of them."""
    N = p.setup_attempts
    kinds = ("NAK", "timeout", "character error", "other character")
    steps = [prime(P), expect(STX, within=RETRY, note="STX 1")]
    for i in range(N):
        kind = kinds[i % len(kinds)]
        if kind == "NAK":
            steps.append(send(NAK, note="refused by NAK"))
        elif kind == "character error":
            steps.append(send_error("10", note="a DLE with a parity error"))
        elif kind == "other character":
            steps.append(send("41", note="a character other than DLE"))
        window = dict(after="ADT", within="ADT + 2*CHAR") if kind == "timeout" else dict(within=RETRY)
        what = f"STX {i + 2}" if i < N - 1 else "the sender's NAK"
        steps.append(expect(STX if i < N - 1 else NAK, note=f"{what} (after a {kind})", **window))
    return case(p, "SEND.SETUP-ATTEMPTS-MIXED", f"Setup attempts failing by NAK, timeout, character error, other: {N} in all",
                "§2.2.2 Send/setup; Fig. 2-10 'X+1', 'X <= 6 / X > 6'; Table 2-4 setup attempts",
                "Every kind of failed setup (NAK, another character, a character error, no answer within ADT) counts in the one setup counter: exactly 'setup attempts' STX, then NAK.",
                "send", "sender", steps,
                iut=(["16#0702|16#0703|16#080C|16#0709"], ["16#0702", "16#0703", "16#080C", "16#0709"]),
                delivered=[P], requires=ECHO, readings=["A8", "A9"], provenance="[S][F]",
                rules=["3964.TX.SETUP-ATTEMPTS"])
