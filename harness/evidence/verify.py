"""``ptpcert verify``: the checks of a bundle, each one line naming the part it checks.

1. the manifest: readable, every member it lists present with its SHA-256, no member it
   does not list, the bundle digest it gives that of its lines, and the certificate's;
2. the signature, where the bundle has one (or where ``--allowed-signers`` asks for one);
3. the suite, vector and rules digests against the installed ptpcert (handed in: the suite
   is generated above this package);
4. the results against the JUnit view (the same cases);
5. the capture re-judged offline against the bundled profile, and its agreement with the
   recorded verdicts (:mod:`ptpcert.analysis.agreement`).

A check that fails is ``FAIL``; one that holds ``ok``; a point the reader should know that
does not make the bundle fail (an unsettled disagreement, an unsigned bundle) ``note``.
"""

from __future__ import annotations

import json
import re
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Any, Callable

from ptpcert import capture as C
from ptpcert import results as R

from .bundle import CERTIFICATE, FORMAT, MANIFEST, SIGNATURE, EvidenceError, bundle_digest, check_signature, sha256
from .facts import differences

OK, FAIL, NOTE = "ok", "FAIL", "note"


@dataclass(frozen=True)
class Check:
    status: str      # OK, FAIL or NOTE
    part: str        # the member or part checked
    text: str

    def line(self) -> str:
        return f"{self.status:<4}  {self.part}: {self.text}"


def _manifest(members: dict[str, bytes], out: list[Check]) -> dict[str, str] | None:
    raw = members.get(MANIFEST)
    if raw is None:
        out.append(Check(FAIL, MANIFEST, "missing: the bundle has no manifest"))
        return None
    try:
        doc = json.loads(raw.decode("utf-8"))
        files = doc["files"]
        if doc.get("format") != FORMAT or not isinstance(files, dict) or \
                not all(isinstance(k, str) and isinstance(v, str) for k, v in files.items()):
            raise ValueError("not a ptpcert evidence manifest")
    except (ValueError, KeyError, TypeError, UnicodeDecodeError) as exc:
        out.append(Check(FAIL, MANIFEST, f"cannot be read ({exc})"))
        return None
    good = True
    for name in sorted(files):
        if name not in members:
            out.append(Check(FAIL, name, "listed in the manifest, missing from the bundle"))
            good = False
        elif sha256(members[name]) != files[name]:
            out.append(Check(FAIL, name, "its SHA-256 is not the manifest's: the file was changed"))
            good = False
    for name in sorted(set(members) - set(files) - {MANIFEST, SIGNATURE}):
        out.append(Check(FAIL, name, "in the bundle, not in the manifest: a file was added"))
        good = False
    digest = bundle_digest(files)
    if doc.get("bundle_digest") != digest:
        out.append(Check(FAIL, MANIFEST, "its bundle digest is not that of its lines: the manifest was edited"))
        good = False
    shown = re.search(rb'id="bundle-digest">([0-9a-f]{64})<', members.get(CERTIFICATE, b""))
    if shown is None or shown.group(1).decode() != digest:
        out.append(Check(FAIL, CERTIFICATE, "the bundle digest it shows is not the manifest's"))
        good = False
    if good:
        out.append(Check(OK, MANIFEST, f"{len(files)} files, each with the SHA-256 the manifest lists; "
                                       f"bundle digest {digest}"))
    return files


def _signature(members: dict[str, bytes], allowed: str | None, out: list[Check]) -> None:
    sig = members.get(SIGNATURE)
    if sig is None:
        if allowed:
            out.append(Check(FAIL, SIGNATURE, "the bundle is not signed, and --allowed-signers asks for a signature"))
        else:
            out.append(Check(NOTE, SIGNATURE, "the bundle is not signed: its hashes show changes by accident, "
                                              "not by someone who rewrites the manifest too"))
        return
    if not allowed:
        out.append(Check(FAIL, SIGNATURE, "the bundle is signed; give --allowed-signers FILE to check the signature"))
        return
    try:
        good, who = check_signature(members.get(MANIFEST, b""), sig, allowed)
    except EvidenceError as exc:
        out.append(Check(FAIL, SIGNATURE, str(exc)))
        return
    out.append(Check(OK if good else FAIL, SIGNATURE, who))


def _json(members: dict[str, bytes], name: str) -> Any:
    return json.loads(members[name].decode("utf-8"))


def _junit(members: dict[str, bytes], run: R.RunResult, out: list[Check]) -> None:
    try:
        root = ET.fromstring(members["junit.xml"])
    except (KeyError, ET.ParseError) as exc:
        out.append(Check(FAIL, "junit.xml", f"cannot be read ({exc})"))
        return
    ids = [tc.get("name", "").split(" [")[0] for tc in root.iter("testcase") if tc.get("classname") != "ptpcert.run"]
    if sorted(ids) != sorted(c.id for c in run.cases):
        gone = sorted(set(ids) - {c.id for c in run.cases}) or sorted({c.id for c in run.cases} - set(ids))
        out.append(Check(FAIL, "results.json", f"its cases are not those of junit.xml (e.g. {', '.join(gone[:3])}): "
                                               "a case was removed or added"))
    else:
        out.append(Check(OK, "junit.xml", f"the same {len(ids)} cases as results.json"))


def verify(members: dict[str, bytes], *, allowed_signers: str | None = None,
           installed: Callable[[Any, dict[str, Any]], dict[str, Any]] | None = None) -> list[Check]:
    """Every check of a bundle's ``members``; ``installed(profile, pixit)`` gives the tool
    facts of the installed ptpcert for the bundle's profile and selection."""
    from ptpcert.profile import ProfileError, profile_from_dict

    out: list[Check] = []
    files = _manifest(members, out)
    _signature(members, allowed_signers, out)
    if files is None:
        return out
    try:
        run = R.RunResult.from_dict(_json(members, "results.json"))
    except (KeyError, ValueError, UnicodeDecodeError) as exc:
        out.append(Check(FAIL, "results.json", f"cannot be read ({' '.join(str(exc).split())[:200]})"))
        return out
    try:
        profile = profile_from_dict(tomllib.loads(members["profile.toml"].decode("utf-8")), "profile.toml")
        pixit, tool = _json(members, "pixit.json"), _json(members, "tool.json")
    except (KeyError, ValueError, UnicodeDecodeError, ProfileError) as exc:
        out.append(Check(FAIL, "profile.toml", f"cannot be read ({' '.join(str(exc).split())[:200]})"))
        return out
    here = None
    if installed is not None:
        try:
            here = installed(profile, pixit)
        except (ValueError, OSError) as exc:
            out.append(Check(FAIL, "tool.json", "the installed ptpcert cannot make the suite of the bundled profile "
                                                f"({' '.join(str(exc).split())[:200]})"))
    if here is not None:
        diffs = differences(tool, here)
        for part, what in diffs:
            out.append(Check(NOTE if part == "tool.json ptpcert" else FAIL, part, what))
        if not [d for d in diffs if d[0] != "tool.json ptpcert"]:
            out.append(Check(OK, "tool.json", f"the suite ({tool.get('cases')} cases), its vector files and the rules "
                                              "catalogues are the installed ptpcert's"))
    _junit(members, run, out)
    out += rejudge(members, run, profile, pixit)
    return out


def rejudge(members: dict[str, bytes], run: R.RunResult, profile: Any, pixit: dict[str, Any]) -> list[Check]:
    """The capture analysed against the bundled profile, and its agreement with the results."""
    from ptpcert.analysis.agreement import agreement, judge_run_capture

    try:
        cap = C.read_pcap(members["capture.pcap"], "capture.pcap")
    except (KeyError, C.CaptureError) as exc:
        return [Check(FAIL, "capture.pcap", f"cannot be read ({' '.join(str(exc).split())[:200]})")]
    try:
        an = judge_run_capture(cap, profile, tolerance_ms=float(pixit.get("tolerance_ms", 50.0)), url=run.iut)
    except ValueError as exc:
        return [Check(NOTE, "capture.pcap", f"not re-judged: {exc}")]
    ag = agreement(run, an)
    out = []
    for cid in ag.unmarked:
        out.append(Check(FAIL, "capture.pcap", f"case {cid} ran (results.json) but is not in the capture: the capture "
                                               "was cut or a case dropped from it"))
    for cid in ag.unknown:
        out.append(Check(FAIL, "results.json", f"case {cid} is in the capture but not in the results: a case was removed"))
    for cid, marked, recorded in ag.verdicts:
        out.append(Check(FAIL, "results.json", f"case {cid}: verdict {recorded}, the capture marks it {marked}: "
                                               "a verdict was edited"))
    for a in ag.standing:
        out.append(Check(FAIL, "results.json", f"verdict of {a.text()}"))
    for a in ag.unsettled:
        out.append(Check(NOTE, "capture.pcap", f"{a.text()} (a known, unsettled disagreement of the line analysis "
                                               "over a pipe: the tester's interruption reached a block already whole)"))
    for t in ag.tester:
        out.append(Check(FAIL, "capture.pcap", f"the tester deviates outside every case at {t}"))
    if ag.status_only:
        out.append(Check(NOTE, "capture.pcap", f"{len(ag.status_only)} case(s) failed on the STATUS the IUT reported, "
                                               "which the line does not carry: " + ", ".join(ag.status_only[:5])))
    if ag.unconfirmed:
        out.append(Check(NOTE, "capture.pcap", f"{len(ag.unconfirmed)} recorded failure(s) with their divergence that "
                                               "the line analysis does not confirm: " + ", ".join(ag.unconfirmed[:5])))
    if ag.holds:
        out.append(Check(OK, "capture.pcap", f"re-judged offline: {len(ag.agree)} cases agree with their recorded "
                                             f"verdicts, {len(an.exchanges)} exchanges"))
    return out
