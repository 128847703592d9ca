"""What a run writes as evidence: the options ``--evidence``/``--sign`` checked before anything
runs, the run's settings (the PIXIT), and the bundle written with the other reports. Used by
``ptpcert run`` and the pytest plugin alike (the options come as an argparse namespace)."""

from __future__ import annotations

import os
import sys
from typing import Any


def options_problem(args) -> str | None:
    """Why ``--evidence``/``--sign`` cannot work, checked before anything runs."""
    from ptpcert.evidence.bundle import EvidenceError, sign
    from ptpcert.results import report_path_problem

    path, key = getattr(args, "evidence", None), getattr(args, "sign", None)
    if key and not path:
        return "--sign needs --evidence FILE.zip (the bundle whose manifest it signs)"
    if not path:
        return None
    written = {os.path.realpath(p) for p in (getattr(args, k, None) for k in ("junit", "json", "html", "pcap")) if p}
    if str(path).strip() and os.path.realpath(path) in written:
        return f"--evidence {path}: is also a report; give each file its own name"
    why = report_path_problem(path)
    if why:
        return f"--evidence {path}: {why}"
    if key:
        if not os.path.isfile(key):
            return f"--sign {key}: no such key file (an OpenSSH private key)"
        try:
            sign(b"ptpcert: can this key sign?\n", key)
        except EvidenceError as exc:
            return str(exc)
    return None


def pixit(args, profile, urls: list[str], result) -> dict[str, Any]:
    """The run's settings (ISO/IEC 9646's PIXIT): how the IUT was reached and driven."""
    line = profile.line
    return {
        "transport": urls, "iut_command": [u.split(":", 1)[1] for u in urls if u.startswith(("exec:", "pty:"))],
        "line": line.describe() if hasattr(line, "describe") else str(line),
        "setups": dict(profile.setups), "tolerance_ms": getattr(args, "tolerance_ms", 50.0),
        "timer_tolerance_ms": profile.timer_tolerance_ms,
        "startup_timeout_s": getattr(args, "startup_timeout", None),
        "edge_attempts": getattr(args, "edge_attempts", None), "max_failures": getattr(args, "max_failures", 0),
        "select": list(getattr(args, "select", None) or []), "vectors": [str(v) for v in getattr(args, "vectors", [])],
        "vectors_only": bool(getattr(args, "vectors_only", False)), "jobs": getattr(args, "jobs", 1),
        "device_pool": urls if len(urls) > 1 else [], "priority": getattr(args, "priority", "normal"),
        "harness_scheduling": result.harness_scheduling,
        "shard": list(getattr(args, "shard", None) or []),
    }


def write_evidence(result, args, profile, cases, urls: list[str], view, cmd: str = "run") -> bool:
    """Write the bundle ``args.evidence`` asks for; False (said on stderr) where it cannot be."""
    from ptpcert.capture import CaptureError
    from ptpcert.evidence.bundle import EvidenceError, write_bundle
    from ptpcert.evidence.facts import tool_facts
    from ptpcert.evidence.make import make_members, seal

    path = getattr(args, "evidence", None)
    if not path:
        return True
    try:
        tool = tool_facts(cases)
        members = make_members(result, view=view, profile=profile, pixit=pixit(args, profile, urls, result), tool=tool)
        write_bundle(path, seal(members, result, tool, getattr(args, "sign", None)))
        return True
    except Exception as exc:   # one line, and the other reports stand
        if not isinstance(exc, (OSError, EvidenceError, CaptureError)):
            exc = f"a fault of ptpcert: {type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
        print(f"ptpcert {cmd}: --evidence {path}: cannot be written ({getattr(exc, 'strerror', None) or exc})",
              file=sys.stderr)
        return False
