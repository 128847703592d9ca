"""The RK 512 frames on a line, for the reports: what a frame is (:func:`describe_frame`,
also the notes of the steps the description's macro steps expand to), and the 3964(R)
blocks of a transcript in each direction, each labelled with the RK 512 frame it carries and
how the other side answered it (:func:`decode_blocks`, what the description's
``describe_frames`` gives the reports' frame view).

Like the description, it names the RK 512 model only inside functions, so that a process
that loads the description (a 3964 IUT) does not load the model.
"""

from __future__ import annotations

from typing import Any

from ptpcert.procedures.p3964.model import codec


def describe_frame(frame: bytes) -> str:
    """What an RK 512 frame is, in a few words
    (:func:`ptpcert.procedures.rk512.model.codec.describe`; the model is loaded here, when a
    frame is first described, not with the description)."""
    from ptpcert.procedures.rk512.model.codec import describe
    return describe(frame)


def decode_blocks(transcript: list[dict[str, Any]], bcc: bool) -> list[dict[str, Any]]:
    """The 3964(R) blocks of a transcript in each direction, each labelled with the RK 512
    frame it carries (:func:`describe_frame`): a block begins after the other side's DLE
    answers the sender's STX, ends with DLE ETX (3964R: and the BCC), and is followed by
    the other side's DLE (accepted) or NAK (refused). Blocks cut off by the
    other side, with a DLE followed by another character, or not finished when the
    transcript ends (a case stops at its first divergence) are labelled as such."""
    out: list[dict[str, Any]] = []
    state: dict[str, Any] = {"iut": None, "tester": None}   # None, "setup", a block dict
    waiting: dict[str, dict | None] = {"iut": None, "tester": None}  # a finished block awaiting its answer
    for e in transcript:
        d = e.get("dir")
        if d not in ("iut", "tester"):
            continue
        other = "tester" if d == "iut" else "iut"
        t = e.get("t", 0.0)
        kind = e.get("kind")
        blk = state[other]
        if isinstance(blk, dict):   # the other side interrupts a block it is sending
            out.append({"dir": other, "t0": blk["t0"], "t1": t,
                        "label": f"block cut off after {len(blk['raw'])} bytes"})
            state[other] = None
        own = state[d]
        if kind != "byte":
            if isinstance(own, dict):
                own["error"] = "a character error" if kind == "char_error" else "a BREAK"
            continue
        b = e["byte"]
        if isinstance(own, dict):
            own["raw"].append(b)
            own["t1"] = t
            if own["bcc_next"]:
                x = 0
                for c in own["raw"][:-1]:
                    x ^= c
                _finish(out, own, waiting, d, bcc_ok=(x == b))
                state[d] = None
            elif own["esc"]:
                own["esc"] = False
                if b == codec.DLE:
                    own["data"].append(codec.DLE)
                elif b == codec.ETX:
                    if bcc:
                        own["bcc_next"] = True
                    else:
                        _finish(out, own, waiting, d, bcc_ok=None)
                        state[d] = None
                else:
                    own["error"] = own.get("error") or f"DLE followed by {b:02X}"
                    own["data"].append(b)
            elif b == codec.DLE:
                own["esc"] = True
            else:
                own["data"].append(b)
            continue
        w = waiting[other]
        if w is not None and b in (codec.DLE, codec.NAK):
            w["label"] += ", accepted (DLE)" if b == codec.DLE else ", refused (NAK)"
            waiting[other] = None
            continue
        if b == codec.STX:
            state[d] = "setup"
        elif b == codec.DLE and state[other] == "setup":
            state[other] = {"t0": t, "t1": t, "raw": bytearray(), "data": bytearray(), "esc": False,
                            "bcc_next": False, "error": None}
        elif b == codec.NAK and state[other] == "setup":
            state[other] = None
    for d in ("tester", "iut"):   # a block the transcript ends in (the case stopped there)
        blk = state[d]
        if isinstance(blk, dict) and blk["raw"]:
            label = describe_frame(bytes(blk["data"]))
            out.append({"dir": d, "t0": blk["t0"], "t1": blk["t1"],
                        "label": f"{label}, unfinished after {len(blk['raw'])} byte{'s' if len(blk['raw']) != 1 else ''}",
                        "frame": bytes(blk["data"]).hex(" ").upper()})
    out.sort(key=lambda f: f["t0"])
    return out


def _finish(out: list, blk: dict, waiting: dict, d: str, bcc_ok: bool | None) -> None:
    frame = bytes(blk["data"])
    label = describe_frame(frame)
    if blk.get("error"):
        label += f" ({blk['error']})"
    if bcc_ok is False:
        label += " (BCC wrong)"
    entry = {"dir": d, "t0": blk["t0"], "t1": blk["t1"], "label": label, "frame": frame.hex(" ").upper()}
    out.append(entry)
    waiting[d] = entry
