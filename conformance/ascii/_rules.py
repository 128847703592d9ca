"""The rules each case of the ASCII suite checks: case id (without ``SUITE.ASCII.``) -> ids of
the ASCII driver's catalogue (``harness/procedures/ascii/rules.toml``; ``ptpcert rules
--procedure ASCII`` prints the matrix). One table, so that a case and the rules it answers
for are read side by side; :func:`rules_of` refuses a case that has no entry.

A case the profile leaves no room for (``not_buildable``) and a placeholder for the modem
lines check nothing: they cite no rule (their rules are checked in other settings, or are
untestable without modem lines)."""

from __future__ import annotations

_F = "ASCII.FRAME."
_CDT, _EC, _EC2, _FL, _RX = "ASCII.RX-CDT.", "ASCII.RX-EC.", "ASCII.RX-EC2.", "ASCII.RX-FL.", "ASCII.RX."
_TX, _FC, _BUF, _LINE, _ST = "ASCII.TX.", "ASCII.FLOW.", "ASCII.BUFFER.", "ASCII.LINE.", "ASCII.STATUS."
_XOFF = (_FC + "XOFF-STOPS", _FC + "XON-RESUMES")

CITES: dict[str, tuple[str, ...]] = {
    # expiry of the CDT
    "CDT.ONE-FRAME": (_CDT + "FRAME-END", _TX + "FRAME-AS-GIVEN"),
    "CDT.TWO-FRAMES": (_CDT + "FRAME-END", _CDT + "GAP-OVER"),
    "CDT.GAP-MERGES": (_CDT + "GAP-UNDER",),
    "CDT.EDGE-UNDER": (_CDT + "GAP-UNDER",),
    "CDT.EDGE-OVER": (_CDT + "GAP-OVER",),
    "CDT.CHARACTER-ERROR": (_CDT + "CHARACTER-ERROR", _ST + "080C"),
    "CDT.CHARACTER-ERROR-GAPS": (_CDT + "CHARACTER-ERROR", _ST + "080C"),
    "CDT.TRANSPARENT": (_RX + "TRANSPARENT", _F + "ALL-CODES"),
    "CDT.MAX-1024": (_RX + "MAX-FRAME", _TX + "LEN-MAX"),
    "CDT.TOO-LONG": (_RX + "TOO-LONG", _ST + "0816"),
    "CDT.ENDS-AFTER-CDT": (_CDT + "FRAME-END",),
    # end characters
    "EC.END-INCLUDED": (_EC + "END-INCLUDED", _TX + "FRAME-AS-GIVEN"),
    "EC.BACK-TO-BACK": (_EC + "COMPLETES-AT-ONCE",),
    "EC.LONE-END": (_EC + "END-INCLUDED",),
    "EC.TRAILING-DISCARDED": (_EC + "TRAILING-DISCARDED",),
    "EC.TRAILING-MERGED": (_EC + "TRAILING-MERGED",),
    "EC.TRAILING-EDGE-OVER": (_EC + "TRAILING-DISCARDED",),
    "EC.NO-END-DISCARDED": (_EC + "NO-END-DISCARDED", _ST + "0806"),
    "EC.NO-END-MERGED": (_EC + "NO-END-MERGED",),
    "EC.EDGE-UNDER": (_EC + "GAP-UNDER",),
    "EC.EDGE-OVER": (_EC + "NO-END-DISCARDED", _ST + "0806"),
    "EC.CHARACTER-ERROR": (_EC + "CHARACTER-ERROR", _ST + "080C"),
    "EC.CHARACTER-ERROR-ENDS-AT-END-CHAR": (_EC + "CHARACTER-ERROR", _ST + "080C"),
    "EC.COMPLETES-AT-ONCE": (_EC + "COMPLETES-AT-ONCE",),
    "EC2.LONE-FIRST-IS-DATA": (_EC2 + "SEQUENCE",),
    "EC2.HALF-PAIR": (_EC2 + "SEQUENCE", _EC2 + "SPLIT", _ST + "0806"),
    "EC2.SPLIT-ACROSS-CDT": (_EC2 + "SPLIT", _ST + "0806"),
    "EC2.LONE-SECOND-IS-DATA": (_EC2 + "SEQUENCE",),
    "EC2.REVERSED": (_EC2 + "SEQUENCE", _ST + "0806"),
    "EC2.OVERLAP": (_EC2 + "SEQUENCE",),
    # fixed length
    "FL.EXACT": (_FL + "FRAME-END", _TX + "FRAME-AS-GIVEN"),
    "FL.BACK-TO-BACK": (_FL + "FRAME-END",),
    "FL.EDGE-UNDER": (_FL + "GAP-UNDER",),
    "FL.CHARACTER-ERROR": (_FL + "CHARACTER-ERROR", _ST + "080C"),
    "FL.CHARACTER-ERROR-ENDS-AT-N": (_FL + "CHARACTER-ERROR", _ST + "080C"),
    "FL.TRANSPARENT": (_RX + "TRANSPARENT", _F + "ALL-CODES"),
    "FL.SHORT-DISCARDED": (_FL + "SHORT-DISCARDED", _ST + "0806"),
    "FL.SHORT-MERGED": (_FL + "SHORT-MERGED",),
    "FL.EDGE-OVER": (_FL + "SHORT-DISCARDED", _ST + "0806"),
    "FL.SURPLUS-DISCARDED": (_FL + "SURPLUS-DISCARDED",),
    "FL.SURPLUS-MERGED": (_FL + "SURPLUS-MERGED",),
    # sending
    "TX.PAUSE": (),   # by criterion: see rules_of
    "TX.VARIANT-UP-TO-END": (_TX + "VARIANT-UP-TO-END",),
    "TX.VARIANT-LEN-WITH-END": (_TX + "VARIANT-LEN-WITH-END",),
    "TX.VARIANT-APPEND-END": (_TX + "VARIANT-APPEND-END",),
    "TX.UP-TO-END-CUTS": (_TX + "VARIANT-UP-TO-END",),
    "TX.LEN-1024": (_TX + "LEN-MAX", _RX + "MAX-FRAME"),
    "TX.LEN-1": (_TX + "FRAME-AS-GIVEN",),
    "TX.LEN-0-REFUSED": (_TX + "LEN-ILLEGAL", _ST + "1E41"),
    "TX.LEN-1025-REFUSED": (_TX + "LEN-ILLEGAL", _ST + "1E41"),
    # flow control
    "FC.XON-AT-START-UP": (_FC + "XON-AT-START-UP",),
    "FC.XOFF-AFTER-FIRST": _XOFF,
    "FC.XOFF-MIDDLE": _XOFF,
    "FC.XOFF-NEAR-END": _XOFF,
    "FC.XON-WITHIN-WAIT": _XOFF,
    "FC.XON-WAIT-EXPIRES": (_FC + "XON-WAIT", _ST + "0708"),
    "FC.XOFF-WHILE-IDLE": (_FC + "XOFF-WHILE-IDLE",),
    "FC.CODES-NOT-DATA": (_FC + "CODES-NOT-DATA",),
    "FC.XOFF-AT-FRAME-COUNT": (_FC + "XOFF-AT-FRAME-COUNT", _FC + "XON-AFTER-READ"),
    "FC.XOFF-AT-974-BYTES": (_FC + "XOFF-AT-974", _FC + "XON-AFTER-READ"),
    "FC.OVERFLOW": (_FC + "OVERFLOW", _ST + "080A"),
    # the receive buffer
    "BUF.FIFO": (_BUF + "FIFO",),
    "BUF.FULL-PREVENT-OVERWRITE": (_BUF + "FULL-PREVENT",),
    "BUF.OVERWRITE": (_BUF + "OVERWRITE",),
    "BUF.BYTES-FULL": (_BUF + "BYTES", _ST + "080A"),
    # line conditions
    "LINE.ALL-CODES": (_F + "ALL-CODES", _F + "SETTINGS", _TX + "FRAME-AS-GIVEN"),
    "LINE.BREAK-IDLE": (_LINE + "BREAK", _ST + "080D"),
    "LINE.BREAK-IN-FRAME": (_LINE + "BREAK", _ST + "080D"),
    "LINE.BREAK-WHILE-SENDING": (_LINE + "BREAK-WHILE-SENDING", _ST + "080D"),
}


def rules_of(case_id: str, p) -> tuple[str, ...]:
    """The rule ids the case ``case_id`` (without ``SUITE.ASCII.``) checks in the profile's
    parameters ``p``."""
    if case_id == "TX.PAUSE":
        return (_TX + ("CDT-PAUSE" if p.end_criterion == "cdt" else "FL-PAUSE"),)
    if case_id == "LINE.ALL-CODES" and p.data_bits == 7:
        return CITES[case_id] + (_F + "SEVEN-BIT",)
    try:
        return CITES[case_id]
    except KeyError:
        raise KeyError(f"the ASCII case {case_id} cites no rule: add it to conformance/ascii/_rules.py") from None
