"""The run in words: the text every view shares. A case's anchor in the HTML report and the
link to it, the step a divergence is at, the tail of a transcript and the frames as text
lines, a failure's explanation, the distinct deviations, and the console's progress lines
and summary.

Part of :mod:`ptpcert.report`: the JUnit file (:mod:`ptpcert.report.junit`), the HTML
report (:mod:`ptpcert.report.html`), the pytest plugin and the command line use it. It
reads only the results object.
"""

from __future__ import annotations

from ptpcert import results as R


def anchor(case_id: str) -> str:
    """The HTML anchor of a case (shared by the console, JUnit and HTML views)."""
    return "case-" + "".join(c if c.isalnum() else "-" for c in case_id)


def case_link(run: R.RunResult, c: R.CaseResult) -> str:
    return f"{run.html_path}#{anchor(c.id)}" if run.html_path else ""


def step_text(step: int) -> str:
    """ "step 3, " for a divergence at a step of a case; "" where there are no steps (a
    prologue, or an analysis of a capture)."""
    return f"step {step + 1}, " if step >= 0 else ""


def transcript_text(c: R.CaseResult, tail: int = 40) -> str:
    """The last ``tail`` bytes, character errors and BREAKs of a case's transcript as text
    lines, and what the transcript did not keep."""
    last: list = []
    for t, d, kind, value, step in reversed(R.wire_runs(c.transcript)):
        if kind == "break":
            last.append((t, d, kind, value, step))
        else:
            last.extend((t, d, kind, b, step) for b in reversed(value[-tail:]))
        if len(last) >= tail:
            break
    lines = []
    for t, d, kind, value, _ in reversed(last[:tail]):
        who = "tester" if d == "tester" else "IUT   "
        what = {"byte": "", "break": "BREAK ", "char_error": "char-error "}[kind]
        val = "" if kind == "break" else f"{value:02X}"
        lines.append(f"{t * 1000:10.3f} ms  {who} -> {what}{val}")
    lines += [R.dropped_note(e) for e in c.transcript if e.get("kind") == "dropped"]
    if c.frames and lines:
        lines += ["", "frames:"] + frame_lines(c, tail=12)
    return "\n".join(lines)


def frame_lines(c: R.CaseResult, tail: int | None = None) -> list[str]:
    """The case's frames as text lines (the last ``tail`` of them): time span, sender,
    label, with end characters and windows named; the divergence's frame marked."""
    frames = c.frames if tail is None else c.frames[-tail:]
    out = []
    if tail is not None and len(c.frames) > tail:
        out.append(f"  ({len(c.frames) - tail} earlier frames not shown)")
    for f in frames:
        try:
            t0, t1 = float(f["t0"]) * 1000, float(f["t1"]) * 1000
        except (KeyError, TypeError, ValueError):
            continue
        who = "tester" if f.get("dir") == "tester" else "IUT   "
        mark = ">>" if f.get("diverged") else "  "
        line = f"{mark}{t0:10.3f}-{t1:.3f} ms  {who} frame {f.get('label', '')}"
        num = (int, float)
        extra = [f"{m.get('name', '?')} at {m['t'] * 1000:.3f} ms" for m in f.get("marks") or []
                 if isinstance(m, dict) and isinstance(m.get("t"), num)]
        extra += [f"{w.get('name', '?')} {w['t0'] * 1000:.3f}-{w['t1'] * 1000:.3f} ms"
                  for w in f.get("windows") or []
                  if isinstance(w, dict) and isinstance(w.get("t0"), num) and isinstance(w.get("t1"), num)]
        if extra:
            line += "  [" + "; ".join(extra) + "]"
        if f.get("diverged") and f.get("expected") and f.get("expected") != f.get("label"):
            line += f"  (expected {f['expected']})"
        out.append(line)
    return out


def failure_text(c: R.CaseResult) -> str:
    parts = [c.message]
    if c.divergence is not None:
        d = c.divergence
        parts.append(f"first divergence at {step_text(d.step)}{d.time * 1000:.3f} ms: "
                     f"expected {d.expected}; {d.observed}")
        where = R.divergence_frame_text(c)
        if where:
            parts.append(where)
    parts.append(f"expected STATUS at the IUT: {c.expected_status}")
    if c.status_checked:
        parts.append("reported STATUS: " + (", ".join(c.observed_status) or "none"))
    return "\n".join(parts)

def deviation_lines(run: R.RunResult, indent: str = "  ", groups: list | None = None) -> list[str]:
    """The distinct deviations (failures grouped by root cause), largest first, each with
    the number of cases it explains and their ids; nothing when no case failed."""
    groups = run.deviations() if groups is None else groups
    if not groups:
        return []
    lines = ["", f"distinct deviations ({len(groups)}; failed cases grouped by their first divergence):"]
    for i, g in enumerate(groups, 1):
        lines.append(f"{indent}{i}. {g['description']}")
        ids = list(g.get("cases", []))
        shown = ", ".join(ids[:8]) + (f", and {len(ids) - 8} more" if len(ids) > 8 else "")
        lines.append(f"{indent}   {shown}")
    return lines


def progress_line(i: int, n: int, c: R.CaseResult) -> str:
    w = len(str(n))
    extra = ""
    if c.verdict not in (R.PASS,):
        extra = f"  {c.message[:110]}" if c.message else ""
    return f"[{i:>{w}}/{n}] {c.verdict:<13} {c.id}  ({c.duration:.2f} s){extra}"


def timer_tolerance_text(run: R.RunResult) -> str:
    """The declared accuracy of the IUT's own timers, as every report shows it."""
    ms = run.profile.get("timer_tolerance_ms") or 0
    how = "declared in the profile" if ms else "none declared"
    return (f"IUT timer tolerance: {ms:g} ms ({how}, [iut] timer_tolerance_ms; widens only the late side of "
            "windows that end on an IUT timer, beyond the harness's own tolerance)")


def identity_text(run: R.RunResult) -> str:
    """The IUT's identity (the profile's ``[iut.identity]``) in one line, or ""."""
    return "; ".join(f"{k} {v}" for k, v in run.iut_identity.items())


def summary(run: R.RunResult) -> str:
    counts = run.counts()
    virtual = run.harness_scheduling.startswith("virtual time")
    # in virtual time the harness keeps every window exactly: the IUT's tolerance is worth a
    # line only where one is declared
    lines = [""] + ([timer_tolerance_text(run)] if run.profile.get("timer_tolerance_ms") or not virtual else [])
    if run.iut_identity:
        lines.insert(1, f"IUT: {identity_text(run)}")
    if run.harness_scheduling:
        lines.append(f"harness scheduling: {run.harness_scheduling}")
    if run.shard:
        lines.append(f"shard {run.shard} of the selection")
    if run.merged_from:
        lines.append(f"merged from {', '.join(run.merged_from)}")
    lines += ["", "verdict        cases"]
    for v in R.VERDICTS:
        if counts.get(v):
            lines.append(f"  {v:<13}{counts[v]:>6}")
    lines.append(f"  {'total':<13}{len(run.cases):>6}")
    bad = [c for c in run.cases if c.verdict in (R.FAIL, R.XPASS, R.ERROR)]
    devs = run.deviations()
    lines += deviation_lines(run, groups=devs)
    group_of = {cid: i + 1 for i, g in enumerate(devs) for cid in g.get("cases", [])}
    if bad:
        lines.append("")
        lines.append("not passed:")
        for c in bad:
            tag = f"  (deviation {group_of[c.id]})" if c.id in group_of else ""
            lines.append(f"  {c.verdict:<6} {c.id}  [{c.reference}]{tag}")
            d = c.divergence
            # the divergence is said once: with its time where the message is its own words
            if d is None or d.step < 0 or not c.message.startswith(step_text(d.step).rstrip(", ") + ":"):
                lines.append(f"         {c.message[:200]}")
            if d is not None:
                lines.append(f"         {step_text(d.step)}at {d.time * 1000:.1f} ms: expected {d.expected}; {d.observed}")
                where = R.divergence_frame_text(c)
                if where:
                    lines.append(f"         {where[:300]}")
            link = case_link(run, c)
            if link:
                lines.append(f"         {link}")
    lines.append("")
    state = "INTERRUPTED, " if run.interrupted else ""
    lines.append(f"{state}{len(run.cases)} cases in {run.wall_time:.1f} s: overall {run.verdict.upper()}")
    return "\n".join(lines)

