"""The rules of the RK 512 catalogue (``ptpcert rules --procedure RK512``) each golden vector
checks, by the vector's file name (``rk512_golden.file_name`` without ``.toml``; ``*`` and
``?`` as in fnmatch): a vector collects the rules of every pattern it matches."""

from __future__ import annotations

from fnmatch import fnmatchcase

E = ["RK512.RESP.ERROR-NO-DATA", "RK512.RESP.LAYOUT", "RK512.STATUS.RESPONDER-EVENTS"]
RULES = [
 ("dle-bcc", ["RK512.LINK.DLE-DOUBLING", "RK512.LINK.BCC"]),
 ("dle-data", ["RK512.LINK.DLE-DOUBLING", "RK512.RESP.FETCH-DATA"]),
 ("dle-header", ["RK512.LINK.DLE-DOUBLING", "RK512.RESP.DATA-STORED"]),
 ("dle-reatel", ["RK512.LINK.DLE-DOUBLING", "RK512.CHECK.BYTE4"]),
 ("err06-0601", E + ["RK512.CHECK.BYTE1"]), ("err06-0602", E + ["RK512.CHECK.BYTE3"]),
 ("err06-0603", E + ["RK512.CHECK.CONTINUATION-BYTE3"]), ("err06-0604", E + ["RK512.CHECK.BYTE4"]),
 ("err06-0605", E + ["RK512.CHECK.CONTINUATION-BYTE4"]), ("err06-0606", E + ["RK512.CHECK.BLOCK-NUMBER"]),
 ("err06-0607", E + ["RK512.CHECK.START-ADDRESS"]), ("err06-0608", E + ["RK512.CHECK.LENGTH"]),
 ("err06-0609", E + ["RK512.CHECK.FLAG"]), ("err06-060a", E + ["RK512.CHECK.CPU"]),
 ("err06-060b", E + ["RK512.CHECK.SEND-DATA-COUNT"]), ("err06-060c", E + ["RK512.CHECK.FETCH-WITH-DATA"]),
 ("err06-060d", E + ["RK512.CHECK.NOT-READY"]), ("err06-060e", E + ["RK512.CHECK.SEQUENCE"]),
 ("err06-060f", E + ["RK512.FLAG.LOCKED"]), ("err06-0610", ["RK512.CHECK.TOO-SHORT"]),
 ("err06-0611", E + ["RK512.CHECK.SEND-DATA-COUNT"]), ("err06-0612", ["RK512.LINK.RESPONSE-NOT-SENT"]),
 ("err0a-0a01", ["RK512.REQ.RESPONSE-SEQUENCE"]), ("err0a-0a02", ["RK512.REQ.RESPONSE-STRUCTURE"]),
 ("err0a-0a03", ["RK512.REQ.FETCH-DATA-COUNT"]), ("err0a-0a04", ["RK512.REQ.SEND-RESPONSE-WITH-DATA"]),
 ("err0a-0a05", ["RK512.TRES.REQUESTER-EXPIRES"]),
 ("ex1-send-10-active", ["RK512.LINK.ONE-BLOCK", "RK512.CMD.HEADER", "RK512.CMD.FLAG-AND-CPU", "RK512.CPU.NUMBERS", "RK512.LINK.BCC"]),
 ("ex1-send-10-no-cpu-active", ["RK512.CMD.FLAG-AND-CPU", "RK512.LINK.BCC"]),
 ("ex1-send-10-passive-3964", ["RK512.LINK.PLAIN-3964", "RK512.RESP.LAYOUT", "RK512.RESP.SEND-NO-DATA"]),
 ("ex1-send-10-passive", ["RK512.LINK.ONE-BLOCK", "RK512.RESP.LAYOUT", "RK512.RESP.SEND-NO-DATA", "RK512.LINK.BCC"]),
 ("ex2-send-200-active", ["RK512.SEG.SEND-FRAMES", "RK512.SEG.CHUNK-128", "RK512.LEN.WHOLE-REQUEST"]),
 ("ex2-send-200-passive", ["RK512.SEG.SEND-SERVED", "RK512.RESP.MIRRORS-COMMAND"]),
 ("ex3-fetch-6-active", ["RK512.CMD.FETCH-NO-DATA", "RK512.CMD.DB-ADDRESS", "RK512.LEN.UNITS"]),
 ("ex3-fetch-6-passive", ["RK512.RESP.FETCH-DATA", "RK512.RESP.DATA-STORED"]),
 ("ex4-fetch-300-active", ["RK512.SEG.FETCH-FRAMES", "RK512.SEG.CHUNK-128"]),
 ("ex4-fetch-300-passive", ["RK512.SEG.FETCH-ON-REQUEST", "RK512.RESP.FETCH-DATA", "RK512.SEG.CHUNK-128"]),
 ("ex5-reatel-??", ["RK512.REQ.REATEL-EVENT"]),
 ("ex5-reatel-??-continuation", ["RK512.REQ.REATEL-EVENT", "RK512.SEG.ERROR-ENDS-REQUEST"]),
 ("ex5-reatel-01*", ["RK512.REQ.UNKNOWN-REATEL"]), ("ex5-reatel-42*", ["RK512.REQ.UNKNOWN-REATEL"]),
 ("ex5-reatel-ff*", ["RK512.REQ.UNKNOWN-REATEL"]),
 ("ex6-dle-in-header-and-data-passive", ["RK512.LINK.DLE-DOUBLING", "RK512.RESP.DATA-STORED"]),
 ("ex6-fetch-counters-active", ["RK512.TYPE.COUNTER-Z", "RK512.CMD.BYTE-ADDRESS"]),
 ("ex6-fetch-dx-active", ["RK512.TYPE.FETCH-DX", "RK512.CMD.DB-ADDRESS"]),
 ("ex6-fetch-flags-active", ["RK512.TYPE.LETTERS", "RK512.CMD.BYTE-ADDRESS"]),
 ("ex6-fetch-odd-len-active", ["RK512.LEN.ODD-FETCH", "RK512.LEN.ODD-OFFSET"]),
 ("ex6-flag-cpu-2-active", ["RK512.CMD.FLAG-AND-CPU", "RK512.CPU.NUMBERS"]),
 ("ex6-send-dx-active", ["RK512.CMD.SEND-DX"]),
 ("ex6-send-odd-len-active", ["RK512.LEN.ODD-SEND", "RK512.LEN.ODD-OFFSET"]),
 ("fetch-*", ["RK512.AREA.PROVIDE", "RK512.RESP.FETCH-DATA", "RK512.LEN.UNITS"]),
 ("fetch-*-300", ["RK512.SEG.FETCH-ON-REQUEST", "RK512.SEG.CHUNK-128"]),
 ("fetch-*-1024", ["RK512.SEG.FETCH-ON-REQUEST", "RK512.SEG.CHUNK-128", "RK512.LEN.MAX-1024"]),
 ("fetch-x-*", ["RK512.AREA.PROVIDE-DX"]),
 ("send-d?-*", ["RK512.RESP.SEND-NO-DATA", "RK512.RESP.DATA-STORED", "RK512.RESP.ONE-PER-COMMAND"]),
 ("send-d?-129", ["RK512.SEG.SEND-SERVED"]), ("send-d?-200", ["RK512.SEG.SEND-SERVED"]),
 ("send-d?-1024", ["RK512.SEG.SEND-SERVED", "RK512.LEN.MAX-1024"]),
 ("send-dx-*", ["RK512.AREA.RECEIVE-DX"]),
 ("qfd-crossing-iut-low", ["RK512.LINK.CONFLICT", "RK512.QFD.REQUEST-WHILE-SERVING"]),
 ("qfd-tester-send-while-waiting", ["RK512.QFD.SERVE-WHILE-WAITING"]),
 ("tres-active-expiry", ["RK512.TRES.REQUESTER-EXPIRES"]),
 ("tres-passive-expiry", ["RK512.TRES.RESPONDER-EXPIRES"]),
]


def rules_for(stem: str) -> list[str]:
    """The rule ids of the vector whose file is ``stem``.toml; none is a mistake."""
    ids: list[str] = []
    for pattern, rules in RULES:
        if fnmatchcase(stem, pattern):
            ids += rules
    if not ids:
        raise ValueError(f"vector {stem} cites no rule: add it to rk512_vector_rules.py")
    return list(dict.fromkeys(ids))
