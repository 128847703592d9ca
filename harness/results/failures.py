"""What a failed case's first divergence looks like, in words that survive other runs: the
frame it falls in (for the JUnit message, the console summary and the HTML), and its
signature, by which :func:`root_causes` groups failed cases into distinct deviations.

Part of :mod:`ptpcert.results`: :meth:`ptpcert.results.run.RunResult.deviations` keeps the
groups; the views show them.
"""

from __future__ import annotations

import re
from typing import Any, Callable, Iterable, Mapping

from ptpcert.results.cases import FAIL, CaseResult
from ptpcert.results.reading import is_kind
from ptpcert.results.transcripts import wire_runs


def divergence_frame(c: CaseResult) -> dict[str, Any] | None:
    """The frame the case's first divergence falls in, or None: the one the run marked
    ``diverged``; for results without the mark, the IUT's frame (else the tester's) whose
    span holds the divergence's time."""
    if c.divergence is None:
        return None
    for f in c.frames:
        if f.get("diverged"):
            return f
    t = float(c.divergence.time)
    hits = [f for f in c.frames if is_kind(f.get("t0"), (int, float)) and is_kind(f.get("t1"), (int, float))
            and float(f["t0"]) - 1e-6 <= t <= float(f["t1"]) + 1e-6]
    hits.sort(key=lambda f: f.get("dir") != "iut")
    return hits[0] if hits else None


def divergence_frame_text(c: CaseResult) -> str:
    """The divergence's frame in words: 'in the IUT's frame "response REATEL 0Ch -> ...",
    expected "response REATEL 14h -> ..."' ('during the tester's frame "..."' when it
    falls in one of the tester's); '' when it falls in no frame."""
    f = divergence_frame(c)
    if f is None:
        return ""
    where = "in the IUT's" if f.get("dir") == "iut" else "during the tester's"
    text = f"{where} frame \"{f.get('label', '?')}\""
    exp = f.get("expected")
    if exp and exp != f.get("label"):
        text += f", expected \"{exp}\""
    return text


# ------------------------------------------------------------------ root causes
#: the names of a case's bytes (its params -> {byte: name}; a procedure's view gives them, e.g.
#: the characters that steer its exchanges): a lone stimulus byte with a name is a class of its own
Names = Callable[[Mapping[str, Any]], Mapping[int, str]]
_HEX = re.compile(r"^(?:[0-9A-F]{2}(?:\*\d+)?)(?: [0-9A-F]{2}(?:\*\d+)?)*$")


def _bytes_word(data: bytes) -> str:
    """Up to three bytes in hex; a longer run (a block, whose data differ from case to case)
    as "a block"."""
    if not data:
        return "nothing"
    if len(data) <= 3:
        return " ".join(f"{b:02X}" for b in data)
    return "a block"


def _stimulus_word(c: CaseResult, until: float, names: Names | None = None) -> str:
    """What the tester sent last before ``until`` (case time), as a class that survives other
    payloads: a byte ``names`` names by that name (the characters that steer the procedure),
    BREAK, a corrupted character, a block (more than one byte at once), any other character;
    "" at the start."""
    last = None
    for t, d, kind, value, _ in wire_runs(c.transcript):
        if t > until + 1e-9:
            break
        if d == "tester":
            last = (kind, value)
    if last is None:
        return ""
    kind, value = last
    if kind == "break":
        return "BREAK"
    if kind == "char_error":
        return "corrupted character"
    data = bytes(value)
    if len(data) == 1:
        return (names(c.params) if names is not None else {}).get(data[0], "character")
    return "block"


def _words(text: str) -> str:
    """Free text without what changes from run to run: times, counts and positions."""
    text = re.sub(r"^step \d+: ", "", text)
    text = re.sub(r" \(reported: .*$", "", text)
    text = re.sub(r"-?\d+(?:\.\d+)? ?(?:ms|s)\b", "T", text)
    return re.sub(r"(?<![#\w])\d+(?![#\w])", "N", text).strip()


def failure_signature(c: CaseResult, names: Names | None = None) -> tuple[str, str, str]:
    """The signature of a failed case's first divergence, as (context, expected, observed):
    what the tester had last sent, what the IUT was expected to send and what it sent
    instead, in words that survive other payloads and other timings (a block is "a
    block", a byte position inside a block's data is not kept, times are not kept).
    Cases with the same signature fail for one root cause. ``names``: the names of the
    case's bytes for the tester's last stimulus (:attr:`ptpcert.view.ReportView.names`)."""
    d = c.divergence
    if d is None:
        return "", "", _words(c.message)
    step = c.steps[d.step] if 0 <= d.step < len(c.steps) else {}
    raw = str(step.get("data", "")) if step.get("kind") == "expect" else ""
    try:
        want = bytes.fromhex(raw) if raw else b""
    except ValueError:
        want = b""
    expected = _bytes_word(want) if want else _words(d.expected)
    obs = d.observed
    if d.expected.endswith("block(s) from the IUT"):   # the echo the epilogue waits for
        intact = re.match(r"^received (\d+) intact block", obs)
        return "", "its echo of the block", (
            "sends no intact block" if intact and intact.group(1) == "0" else
            "sends fewer intact blocks" if intact else _words(obs))
    m = re.match(r"^received ([0-9A-F]{2})$", obs)
    n = re.match(r"^([0-9A-F]{2}) came .* too (late|early)$", obs)
    k = re.match(r"^byte (\d+) is ([0-9A-F]{2}) \(after .*\)$", obs)
    if m:
        observed = f"sends {m.group(1)}"
    elif n:
        observed = f"sends {n.group(1)} too {n.group(2)}"
    elif k:
        pos, byte = int(k.group(1)), k.group(2)
        from_end = len(want) - pos if want else -1
        if len(want) <= 3:
            observed = f"sends {byte} as byte {pos}"
        elif from_end == 0:
            observed = "sends the block with another last byte (its BCC or end)"
        elif 0 < from_end <= 2:
            observed = f"sends the block with another byte {from_end + 1} from its end"
        else:
            observed = "sends the block with other data"
    elif obs == "nothing received":
        observed = "sends nothing"
    elif obs.startswith("got ") and ", then nothing" in obs:
        observed = "stops in the middle"
    elif obs.startswith("it still sent "):
        observed = "goes on sending after it must stop"
    elif obs.startswith("it sent "):
        observed = "sends " + _bytes_word(bytes.fromhex(obs[8:].replace("…", "").strip()) if _HEX.match(
            obs[8:].strip()) and "*" not in obs else b"\x00" * 4)
    else:
        observed = _words(obs)
    if n:   # the right byte at the wrong time: the IUT's timer, whatever the tester sent before
        return "", expected, observed
    return _stimulus_word(c, d.time, names), expected, observed


def describe_signature(sig: tuple[str, str, str], count: int) -> str:
    """A group of ``count`` cases with signature ``sig`` in one sentence, in the signature's
    masked words (for a group without a case to show; :func:`describe_group` gives the
    first case's real bytes and times)."""
    context, expected, observed = sig
    head = f"{count} case{'s' if count != 1 else ''}: "
    if not expected:
        return head + observed
    where = f"after the tester's {context}, " if context else ""
    return head + f"{where}the IUT {observed} where {expected} is due"


_MODEL = re.compile(r"^the IUT's byte (\d+) is ([0-9A-F]{2}); the model sends (.+?)(?: \((after .*)\))?$")


def _what_the_iut_did(obs: str) -> tuple[str, str | None]:
    """A divergence's observed text as what the IUT did, with its real bytes and times
    ("sent 15 at 1.0 ms", "sent 41 as byte 55 (after 41 41)"), and what the reference model
    sends instead when the observation says (else None)."""
    m = _MODEL.match(obs)
    if m:
        after = f" ({m.group(4)})" if m.group(4) else ""
        return f"sent {m.group(2)} as its byte {m.group(1)}{after}", m.group(3)
    for prefix, verb in (("received ", "sent "), ("it still sent ", "still sent "), ("it sent ", "sent "),
                         ("got ", "sent ")):
        if obs.startswith(prefix):
            return verb + obs[len(prefix):], None
    k = re.match(r"^byte (\d+) is ([0-9A-F]{2}) \((after .*)\)$", obs)
    if k:
        return f"sent {k.group(2)} as byte {k.group(1)} ({k.group(3)})", None
    n = re.match(r"^([0-9A-F]{2}) came (.*)$", obs)
    if n:
        return f"sent {n.group(1)} {n.group(2)}", None
    if obs == "nothing received":
        return "sent nothing", None
    if re.match(r"^\S.* (?:at -?\d+(?:\.\d+)? ms|ms later)$", obs):   # a line analysis's "NAK at 12.345 ms"
        return "sent " + obs, None
    return f"did this: {obs}" if obs else "did something else", None


def _last_stimulus(c: CaseResult, until: float, names: Names | None, tester: str = "the tester's") -> str:
    """The tester's last stimulus before ``until`` with its real bytes ("the tester's NAK
    (15)", "the tester's block 02 41 42 ... (12 bytes)"); "" at the start."""
    word = _stimulus_word(c, until, names)
    if not word:
        return ""
    if word in ("BREAK", "corrupted character"):
        return f"{tester} {word}"
    last = b""
    for t, d, kind, value, _ in wire_runs(c.transcript):
        if t > until + 1e-9:
            break
        if d == "tester" and kind not in ("break", "char_error"):
            last = bytes(value)
    shown = " ".join(f"{b:02X}" for b in last[:8]) + (f" ... ({len(last)} bytes)" if len(last) > 8 else "")
    return f"{tester} {word} ({shown})" if word not in ("block", "character") else f"{tester} {word} {shown}"


def describe_group(sig: tuple[str, str, str], count: int, first: CaseResult, names: Names | None = None) -> str:
    """A group of ``count`` cases in one sentence with its ``first`` case's real bytes and
    times: "3 cases (first: ID): at 12.5 ms, after the tester's NAK (15), the IUT sent 15 where
    02 within ADT is due"."""
    head = f"{count} case{'s' if count != 1 else ''} (first: {first.id}): "
    d = first.divergence
    if d is None:
        return head + (first.message or describe_signature(sig, count).split(": ", 1)[1])
    did, model = _what_the_iut_did(d.observed)
    who, stim = "the IUT", ""
    if first.group in ("seat a", "seat b"):   # a line analysis's finding: a seat, its partner the other
        who = first.group
        if who == "seat b":                    # (the transcript's "tester" is seat a)
            stim = _last_stimulus(first, d.time, names, "seat a's")
    else:
        stim = _last_stimulus(first, d.time, names)
    where = f"at {1000 * d.time:.1f} ms" + (f", after {stim}" if stim else "")
    if model is not None:
        return head + f"{where}, {who} {did} where the reference model fed the same line sends {model}"
    expected = d.expected or "something else"
    return head + f"{where}, {who} {did} where {expected} is due"


def root_causes(cases: Iterable[CaseResult], names: Names | None = None) -> list[dict[str, Any]]:
    """The failed cases grouped by the signature of their first divergence
    (:func:`failure_signature`, with ``names``, masked so that other payloads and timings
    group together): one group per distinct deviation, the largest first, each with its
    description (:func:`describe_group`: the first case's real bytes and times), the number of cases it explains and their ids."""
    groups: dict[tuple[str, str, str], list[CaseResult]] = {}
    for c in cases:
        if c.verdict == FAIL:
            groups.setdefault(failure_signature(c, names), []).append(c)
    ordered = sorted(groups.items(), key=lambda kv: -len(kv[1]))
    return [{"signature": list(sig), "description": describe_group(sig, len(cs), cs[0], names), "count": len(cs),
             "cases": [c.id for c in cs]} for sig, cs in ordered]
