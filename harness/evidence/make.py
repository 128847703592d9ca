"""Making a bundle from a finished run: the reports as ``run`` writes them, the run's capture
with its case marks, the profile as declared and as read (the PICS), the settings of the
run (the PIXIT), the tool's facts, the certificate, the manifest and the signature.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from ptpcert import capture as C
from ptpcert import results as R

from .bundle import CERTIFICATE, MANIFEST, SIGNATURE, bundle_digest, manifest_bytes, members_json, sha256, sign


def run_capture(result: R.RunResult) -> C.Capture:
    """The run's wire traffic on one timeline, every case that ran marked with its verdict
    (a run of one case too, which a capture of its own leaves unmarked)."""
    cap = C.from_results(result)
    ran = [c for c in result.cases if c.transcript]
    if len(ran) == 1 and not any(m.text.startswith("case ") for m in cap.marks):
        c = ran[0]
        cap.marks.insert(0, C.Mark(0.0, f"case {c.id} ({c.verdict})" + (f" {c.reference}" if c.reference else "")))
        cap.notes = [f"run of 1 case against {result.iut}"] + [n for n in cap.notes if n.startswith(C.PROCEDURE_NOTE)]
    return cap


def pics(profile: Any) -> dict[str, Any]:
    """The profile as the suite read it, every default filled in."""
    return {"procedure_title": profile.procedure.title, "identity": dict(profile.identity), **profile.to_dict()}


def make_members(result: R.RunResult, *, view: Any, profile: Any, pixit: dict[str, Any],
                 tool: dict[str, Any]) -> dict[str, bytes]:
    """Every member of the bundle but the certificate and the manifest."""
    from ptpcert import report as rep
    from ptpcert.report.html import write_html

    members: dict[str, bytes] = {}
    with tempfile.TemporaryDirectory() as d:
        rep.write_junit(result, Path(d) / "junit.xml", view)
        saved_link = result.html_path
        result.html_path = "report.html"
        try:
            write_html(result, Path(d) / "report.html", view)
            members["junit.xml"] = (Path(d) / "junit.xml").read_bytes()
            members["report.html"] = (Path(d) / "report.html").read_bytes()
            members["results.json"] = (result.to_json() + "\n").encode()
        finally:
            result.html_path = saved_link
    members["capture.pcap"] = C.dumps(run_capture(result), "pcap")
    try:
        members["profile.toml"] = Path(profile.path).read_bytes()
    except OSError:
        members["profile.toml"] = b""
    members["profile.json"] = members_json(pics(profile))
    members["pixit.json"] = members_json(pixit)
    members["tool.json"] = members_json(tool)
    return members


def seal(members: dict[str, bytes], result: R.RunResult, tool: dict[str, Any], key: str | None = None) -> dict[str, bytes]:
    """Add the certificate (with the bundle's digest), the manifest and, with ``key``, its
    signature."""
    from ptpcert.report.html.certificate import render_certificate

    files = {n: sha256(b) for n, b in members.items()}
    digest = bundle_digest(files)
    out = dict(members)
    out[CERTIFICATE] = render_certificate(result, tool=tool, digest=digest).encode()
    out[MANIFEST] = manifest_bytes(out)
    if key:
        out[SIGNATURE] = sign(out[MANIFEST], key)
    return out
