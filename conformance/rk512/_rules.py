"""The rules of the RK 512 catalogue (``harness/procedures/rk512/rules.toml``, ``ptpcert
rules --procedure RK512``) each case checks, by case id: one table for the whole suite, next
to the checklist items (L-, P-, A-) that name the cases. :func:`rules_of` gives a case its
ids; a case that matches no line here is a mistake (the suite refuses to build it).

Each line is a pattern of case ids (the part after ``SUITE.RK512.``, ``*`` for any text)
and the rules every case it matches checks; a case collects the rules of every line it
matches. ``LINK_ONLY`` names the rules a case checks only over one link procedure."""

from __future__ import annotations

from fnmatch import fnmatchcase

_P_ERRORS = ["RK512.RESP.ERROR-NO-DATA", "RK512.RESP.LAYOUT", "RK512.RESP.REATEL-VALUES",
             "RK512.STATUS.RESPONDER-EVENTS"]
_SEND = ["RK512.RESP.ONE-PER-COMMAND", "RK512.RESP.LAYOUT", "RK512.RESP.SEND-NO-DATA", "RK512.LINK.ONE-BLOCK"]
_FETCH = ["RK512.RESP.ONE-PER-COMMAND", "RK512.RESP.FETCH-DATA", "RK512.AREA.PROVIDE", "RK512.LEN.UNITS"]
_CMD = ["RK512.CMD.HEADER", "RK512.CMD.COMMAND-LETTERS", "RK512.CMD.FLAG-AND-CPU", "RK512.CPU.NUMBERS",
        "RK512.REQ.DONE"]

CITES: tuple[tuple[str, tuple[str, ...]], ...] = tuple((pat, tuple(ids)) for pat, ids in (
    # -- the link below (L-01..L-07)
    ("L-01.*", ["RK512.LINK.EIGHT-DATA-BITS", "RK512.LINK.ONE-BLOCK", "RK512.RESP.DATA-STORED"]),
    ("L-02.DLE-IN-HEADER-AND-DATA", ["RK512.LINK.DLE-DOUBLING", "RK512.RESP.DATA-STORED"]),
    ("L-02.DLE-AS-REATEL", ["RK512.LINK.DLE-DOUBLING", "RK512.CHECK.BYTE4"]),
    ("L-02.BCC-10-*", ["RK512.LINK.DLE-DOUBLING", "RK512.LINK.BCC"]),
    ("L-03.*", ["RK512.LINK.REFUSED-BLOCK-NOT-ACTED-ON", "RK512.LINK.BCC"]),
    ("L-04.*", ["RK512.LINK.REPEATED-BLOCK-ANSWERED-ONCE", "RK512.RESP.ONE-PER-COMMAND"]),
    ("L-06.*", ["RK512.LINK.CHARACTER-DELAY", "RK512.LINK.REFUSED-BLOCK-NOT-ACTED-ON"]),
    ("L-07.*", ["RK512.LINK.LARGEST-BLOCK", "RK512.LINK.DLE-DOUBLING"]),
    ("L-05.*", ["RK512.LINK.CONFLICT"]),
    ("L-08.*", ["RK512.LINK.RESPONSE-NOT-SENT", "RK512.RESP.ONE-PER-COMMAND"]),
    # -- the IUT passive: SEND, FETCH (P-01..P-05, P-13, P-14, P-18)
    ("P-01.*", _SEND + ["RK512.RESP.DATA-STORED", "RK512.LEN.UNITS"]),
    ("P-01.DATA-WORD-ADDRESSING", ["RK512.RESP.WORD-BYTE-ORDER"]),
    ("P-01.SEND-1-WORD", ["RK512.LEN.UNITS"]),
    ("P-02.*", _SEND + ["RK512.SEG.SEND-SERVED", "RK512.RESP.MIRRORS-COMMAND", "RK512.LEN.WHOLE-REQUEST",
                        "RK512.SEG.CHUNK-128", "RK512.RESP.DATA-STORED"]),
    ("P-02.SEND-1024", ["RK512.LEN.MAX-1024"]),
    ("P-03.*", ["RK512.TRES.RESPONSE-IN-TIME", "RK512.RESP.ONE-PER-COMMAND"]),
    ("P-18.*", ["RK512.RESP.SEND-NO-DATA", "RK512.RESP.LAYOUT"]),
    ("P-14.SEND-TO-DX*", _SEND + ["RK512.AREA.RECEIVE-DX"]),
    ("P-14.SEND-TO-DX-*", ["RK512.SEG.SEND-SERVED", "RK512.RESP.MIRRORS-COMMAND"]),
    ("P-04.*", _FETCH + ["RK512.RESP.LAYOUT"]),
    ("P-04.FETCH-D-*", ["RK512.RESP.WORD-BYTE-ORDER"]),
    ("P-04.FETCH-X-*", ["RK512.AREA.PROVIDE-DX"]),
    ("P-05.*", _FETCH + ["RK512.SEG.FETCH-ON-REQUEST", "RK512.SEG.CHUNK-128", "RK512.RESP.MIRRORS-COMMAND",
                         "RK512.LEN.WHOLE-REQUEST", "RK512.TRES.RESPONDER-WAITS"]),
    ("P-05.*-1024", ["RK512.LEN.MAX-1024"]),
    ("P-05.FETCH-X-*", ["RK512.AREA.PROVIDE-DX"]),
    ("P-13.*", ["RK512.AREA.CELL-FETCH-32"]),
    ("P-14.FETCH-FROM-DX", ["RK512.AREA.PROVIDE-DX"]),
    # -- the IUT passive: header checks (P-06..P-08, P-17)
    ("P-07A.*", _P_ERRORS + ["RK512.CHECK.BYTE1"]),
    ("P-07B.BYTE3-4*", _P_ERRORS + ["RK512.CHECK.BYTE3"]),
    ("P-07B.BYTE3-6*", _P_ERRORS + ["RK512.CHECK.BYTE3"]),
    ("P-07B.BYTE3-00", ["RK512.CHECK.RESPONSE-OR-COMMAND", "RK512.RESP.NOT-ANSWERED"]),
    ("P-07C.*", _P_ERRORS + ["RK512.CHECK.BYTE4"]),
    ("P-07D.*", _P_ERRORS + ["RK512.CHECK.BLOCK-NUMBER"]),
    ("P-07E.*", _P_ERRORS + ["RK512.CHECK.START-ADDRESS"]),
    ("P-07F.*", _P_ERRORS + ["RK512.CHECK.LENGTH"]),
    ("P-07F.FETCH-513-WORDS", ["RK512.LEN.MAX-1024"]),
    ("P-07G.*", _P_ERRORS + ["RK512.CHECK.FLAG"]),
    ("P-07H.*", _P_ERRORS + ["RK512.CHECK.CPU"]),
    ("P-07I.*", _P_ERRORS + ["RK512.CHECK.SEND-DATA-COUNT"]),
    ("P-07I.FIRST-FRAME-SHORT", ["RK512.SEG.CHUNK-128"]),
    ("P-07J.*", _P_ERRORS + ["RK512.CHECK.FETCH-WITH-DATA"]),
    ("P-06.*", _P_ERRORS + ["RK512.CHECK.FETCH-WITH-DATA", "RK512.RESP.MIRRORS-COMMAND"]),
    ("P-08.*-BYTE3", _P_ERRORS + ["RK512.CHECK.CONTINUATION-BYTE3", "RK512.RESP.MIRRORS-COMMAND"]),
    ("P-08.*-BYTE4", _P_ERRORS + ["RK512.CHECK.CONTINUATION-BYTE4", "RK512.RESP.MIRRORS-COMMAND"]),
    ("P-07K.*", ["RK512.CHECK.TOO-SHORT"]),
    ("P-07L.*", ["RK512.CHECK.BYTE2"]),
    ("P-17.*", _P_ERRORS),
    # -- the IUT passive: sequence, T_RES, the CPU (P-09..P-12, P-15, P-16)
    ("P-09A.*", _P_ERRORS + ["RK512.CHECK.SEQUENCE"]),
    ("P-09B.*", ["RK512.CHECK.FIRST-WHILE-CONTINUATION-EXPECTED"]),
    ("P-09C.*", _P_ERRORS + ["RK512.CHECK.SEQUENCE"]),
    ("P-15.*", ["RK512.RESP.NOT-ANSWERED"]),
    ("P-16.*", ["RK512.QFD.REQUEST-WHILE-SERVING", "RK512.QFD.NESTING-DEPTH-1"]),
    ("P-10.CONTINUATION-IN-TIME", ["RK512.TRES.RESPONDER-WAITS", "RK512.SEG.SEND-SERVED"]),
    ("P-10.CONTINUATION-TOO-LATE", ["RK512.TRES.RESPONDER-EXPIRES", "RK512.CHECK.SEQUENCE"]),
    ("P-11.FLAG-SET-REFUSES", _P_ERRORS + ["RK512.FLAG.LOCKED"]),
    ("P-11.FLAG-RESET-ALLOWS", ["RK512.FLAG.SET-AFTER-TRANSFER", "RK512.FLAG.LOCKED"]),
    ("P-12.*", _P_ERRORS + ["RK512.CHECK.NOT-READY"]),
    # -- the IUT active: commands (A-01..A-03, A-09, A-11)
    ("A-01.*", _CMD + ["RK512.LINK.ONE-BLOCK"]),
    ("A-01.SEND-*", ["RK512.CMD.DB-ADDRESS", "RK512.TYPE.LETTERS", "RK512.LEN.UNITS"]),
    ("A-01.SEND-DX", ["RK512.CMD.SEND-DX"]),
    ("A-01.SEND-DLE-IN-HEADER", ["RK512.LINK.DLE-DOUBLING"]),
    ("A-01.FETCH-*", ["RK512.CMD.FETCH-NO-DATA", "RK512.TYPE.LETTERS", "RK512.LEN.UNITS",
                      "RK512.AREA.FETCH-DESTINATION"]),
    ("A-01.FETCH-DB", ["RK512.CMD.DB-ADDRESS"]),
    ("A-01.FETCH-DX", ["RK512.CMD.DB-ADDRESS", "RK512.TYPE.FETCH-DX"]),
    ("A-01.FETCH-FLAGS", ["RK512.CMD.BYTE-ADDRESS"]),
    ("A-02.*", _CMD + ["RK512.CMD.FETCH-NO-DATA", "RK512.TYPE.LETTERS", "RK512.CMD.BYTE-ADDRESS",
                       "RK512.LEN.UNITS", "RK512.AREA.FETCH-DESTINATION"]),
    ("A-02.FETCH-COUNTERS", ["RK512.TYPE.COUNTER-Z"]),
    ("A-09.SEND-ODD-LENGTH", _CMD + ["RK512.LEN.ODD-SEND", "RK512.LEN.ODD-OFFSET", "RK512.CMD.DB-ADDRESS"]),
    ("A-09.FETCH-ODD-LENGTH", _CMD + ["RK512.LEN.ODD-FETCH", "RK512.AREA.FETCH-DESTINATION"]),
    ("A-03.*", _CMD + ["RK512.SEG.CHUNK-128", "RK512.LEN.WHOLE-REQUEST", "RK512.SEG.NEXT-AFTER-RESPONSE"]),
    ("A-03.SEND-*", ["RK512.SEG.SEND-FRAMES"]),
    ("A-03.SEND-1024", ["RK512.LEN.MAX-1024"]),
    ("A-03.SEND-DX-*", ["RK512.CMD.SEND-DX"]),
    ("A-03.FETCH-300", ["RK512.LINK.EIGHT-DATA-BITS"]),
    ("A-03.FETCH-*", ["RK512.SEG.FETCH-FRAMES", "RK512.CMD.FETCH-NO-DATA", "RK512.AREA.FETCH-DESTINATION"]),
    ("A-11.LOCAL-CHECK-LEN-*", ["RK512.LOCAL.LENGTH"]),
    ("A-11.LOCAL-CHECK-DB-0", ["RK512.LOCAL.DB-NUMBER"]),
    ("A-11.LOCAL-CHECK-FLAG-BIT-8", ["RK512.LOCAL.FLAG-BIT"]),
    ("A-11.LOCAL-CHECK-CPU-5", ["RK512.LOCAL.CPU-NUMBER"]),
    ("A-11.LOCAL-CHECK-SEND-TO-FLAGS", ["RK512.LOCAL.SEND-DESTINATION"]),
    # -- the IUT active: responses (A-06..A-08, A-12)
    ("A-06.REATEL-??", ["RK512.REQ.REATEL-EVENT"]),
    ("A-06.REATEL-??-CONTINUATION", ["RK512.REQ.REATEL-EVENT", "RK512.SEG.ERROR-ENDS-REQUEST"]),
    ("A-06.REATEL-??-*OF-THREE", ["RK512.REQ.REATEL-EVENT", "RK512.SEG.ERROR-ENDS-REQUEST"]),
    ("A-06.REATEL-01*", ["RK512.REQ.UNKNOWN-REATEL"]),
    ("A-06.REATEL-42*", ["RK512.REQ.UNKNOWN-REATEL"]),
    ("A-06.REATEL-FF*", ["RK512.REQ.UNKNOWN-REATEL"]),
    ("A-07.BYTE1-01", ["RK512.REQ.RESPONSE-STRUCTURE"]),
    ("A-07.SEND-RESPONSE-WITH-DATA", ["RK512.REQ.SEND-RESPONSE-WITH-DATA"]),
    ("A-07.FETCH-ONE-*", ["RK512.REQ.FETCH-DATA-COUNT"]),
    ("A-07.*-RESPONSE-TO-*", ["RK512.REQ.RESPONSE-SEQUENCE"]),
    ("A-07.ERROR-RESPONSE-WITH-DATA", ["RK512.REQ.ERROR-RESPONSE-WITH-DATA"]),
    ("A-07.SHORT-RESPONSE", ["RK512.REQ.SHORT-RESPONSE"]),
    ("A-12.*", ["RK512.REQ.FETCH-ERROR-NOTHING-STORED", "RK512.REQ.REATEL-EVENT"]),
    ("A-08.TESTER-SEND-BEFORE-RESPONSE", ["RK512.QFD.SERVE-WHILE-WAITING"]),
    ("A-08.FIGURE-2-17", ["RK512.QFD.COMMAND-BEFORE-RESPONSE", "RK512.QFD.SERVE-WHILE-WAITING"]),
    # -- the IUT active: timing
    ("A-04.*", ["RK512.SEG.NEXT-AFTER-RESPONSE", "RK512.QFD.NESTING-DEPTH-1"]),
    ("A-05.RESPONSE-AT-*", ["RK512.TRES.REQUESTER-WAITS", "RK512.REQ.DONE"]),
    ("A-05.NO-RESPONSE", ["RK512.TRES.REQUESTER-EXPIRES"]),
    ("A-10.*", ["RK512.LINK.COMMAND-NOT-SENT"]),
))

#: rules a case checks only over one link: the BCC of 3964R, the plain blocks of 3964
LINK_ONLY = {"RK512.LINK.BCC": "3964R", "RK512.LINK.PLAIN-3964": "3964"}
#: the cases that show the link's block layout, checked over whichever link the IUT uses
_LAYOUT = ("P-01.SEND-10", "A-01.SEND-DB", "P-04.FETCH-D-6", "A-01.FETCH-DB")


def rules_of(short_id: str, link: str) -> tuple[str, ...]:
    """The rule ids the case ``SUITE.RK512.<short_id>`` checks over ``link``."""
    out: list[str] = []
    for pattern, ids in CITES:
        if fnmatchcase(short_id, pattern):
            out += ids
    if short_id in _LAYOUT:
        out.append("RK512.LINK.BCC" if link == "3964R" else "RK512.LINK.PLAIN-3964")
    out = [r for r in dict.fromkeys(out) if LINK_ONLY.get(r, link) == link]
    if not out:
        raise ValueError(f"SUITE.RK512.{short_id} cites no rule: add it to conformance/rk512/_rules.py")
    return tuple(out)
