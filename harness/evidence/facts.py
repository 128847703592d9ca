"""What a bundle says of the tool that made it: ptpcert's version, the Python and the
platform, a digest of the suite (the cases generated for the profile, with the golden
vectors), one of every vector file the cases came from, and one of every rules catalogue
present. ``verify`` computes the same of the installed ptpcert and says which differ.
"""

from __future__ import annotations

import hashlib
import platform
from typing import Any, Iterable


def suite_digest(cases: Iterable[Any]) -> str:
    """SHA-256 of the cases (each its id and its content's digest, in id order)."""
    h = hashlib.sha256()
    for v in sorted(cases, key=lambda v: v.id):
        h.update(f"{v.id}\0{v.digest()}\n".encode())
    return h.hexdigest()


def vector_digests(cases: Iterable[Any]) -> dict[str, str]:
    """For every vector file the cases came from (a source ending ``.toml``): SHA-256 of its
    vectors' ids and digests."""
    by_file: dict[str, list] = {}
    for v in cases:
        if str(v.source).endswith(".toml"):
            by_file.setdefault(str(v.source), []).append(v)
    return {f: suite_digest(vs) for f, vs in sorted(by_file.items())}


def catalogue_facts() -> list[dict[str, Any]]:
    """Every rules catalogue present: its procedure, title, number of rules and the SHA-256
    of its file (the catalogue's version)."""
    from ptpcert.registry import by_id
    from ptpcert.rules import catalogues

    out = []
    for cat in catalogues():
        entry = by_id(cat.procedure).rules_file()
        digest = hashlib.sha256(entry.read_bytes()).hexdigest() if entry is not None else ""
        out.append({"procedure": cat.procedure, "title": cat.title, "rules": len(cat), "digest": digest})
    return sorted(out, key=lambda c: c["procedure"])


def tool_facts(cases: list[Any]) -> dict[str, Any]:
    """The tool's identity and the digests of what it judged with."""
    from ptpcert import __version__

    return {"ptpcert": __version__, "python": platform.python_version(),
            "implementation": platform.python_implementation(), "platform": platform.platform(),
            "cases": len(cases), "suite_digest": suite_digest(cases), "vector_files": vector_digests(cases),
            "rules_catalogues": catalogue_facts()}


def differences(bundled: dict[str, Any], installed: dict[str, Any]) -> list[tuple[str, str]]:
    """Where the bundle's digests differ from the installed ptpcert's: (part, what)."""
    out = []
    if bundled.get("ptpcert") != installed.get("ptpcert"):
        out.append(("tool.json ptpcert", f"the bundle was made with ptpcert {bundled.get('ptpcert')}, "
                                         f"{installed.get('ptpcert')} is installed"))
    if bundled.get("suite_digest") != installed.get("suite_digest"):
        out.append(("tool.json suite_digest", f"the suite generated for the profile differs from the installed "
                                              f"one's ({bundled.get('cases')} cases in the bundle, "
                                              f"{installed.get('cases')} installed)"))
    mine, theirs = bundled.get("vector_files") or {}, installed.get("vector_files") or {}
    for f in sorted(set(mine) | set(theirs)):
        if mine.get(f) != theirs.get(f):
            what = ("not installed" if f not in theirs else "not in the bundle" if f not in mine else "differs")
            out.append((f"tool.json vector file {f}", what))
    cats = {c["procedure"]: c for c in bundled.get("rules_catalogues") or []}
    here = {c["procedure"]: c for c in installed.get("rules_catalogues") or []}
    for p in sorted(set(cats) | set(here)):
        if cats.get(p, {}).get("digest") != here.get(p, {}).get("digest"):
            what = ("not installed" if p not in here else "not in the bundle" if p not in cats else "differs")
            out.append((f"tool.json rules catalogue {p}", what))
    return out
