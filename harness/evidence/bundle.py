"""The evidence bundle as a file: its members, the manifest of their SHA-256, the optional
OpenSSH signature of the manifest, and the zip written deterministically (members in name
order, one fixed timestamp, fixed attributes and compression) and atomically (a temporary
file in the same directory, renamed over the target when complete).

``docs/evidence.md`` describes the members.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import secrets
import shutil
import subprocess
import tempfile
import zipfile
from pathlib import Path
from typing import Any

#: the manifest's format
FORMAT = "ptpcert-evidence/1"
MANIFEST = "manifest.json"
SIGNATURE = "manifest.json.sig"
CERTIFICATE = "certificate.html"
#: the members the manifest lists, in the order a reader meets them
MEMBERS = ("certificate.html", "results.json", "junit.xml", "report.html", "capture.pcap", "profile.toml",
           "profile.json", "pixit.json", "tool.json")
#: the signature's namespace (ssh-keygen -Y sign -n)
NAMESPACE = "ptpcert"
#: every member's timestamp in the zip (the earliest a zip can hold)
ZIP_TIME = (1980, 1, 1, 0, 0, 0)
#: the largest bundle read back (verify): far above what a run's bounded reports make
MAX_BYTES = 256 * 1024 * 1024


class EvidenceError(ValueError):
    """A bundle that cannot be read or written, or a key that cannot sign: one line."""


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def bundle_digest(files: dict[str, str]) -> str:
    """The bundle's digest, as the certificate shows it: SHA-256 of the manifest's lines
    (``name  sha256``, in name order) of every member but the certificate itself."""
    text = "".join(f"{n}  {h}\n" for n, h in sorted(files.items()) if n != CERTIFICATE)
    return sha256(text.encode())


def manifest_bytes(members: dict[str, bytes]) -> bytes:
    """The manifest of ``members`` (certificate included)."""
    files = {n: sha256(members[n]) for n in sorted(members)}
    doc = {"format": FORMAT, "files": files, "bundle_digest": bundle_digest(files)}
    return (json.dumps(doc, indent=1, sort_keys=True) + "\n").encode()


def zip_bytes(members: dict[str, bytes]) -> bytes:
    """The zip of ``members``: name order, fixed time and attributes, deflated."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name in sorted(members):
            info = zipfile.ZipInfo(name, date_time=ZIP_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.create_system = 3
            info.external_attr = 0o644 << 16
            z.writestr(info, members[name], compress_type=zipfile.ZIP_DEFLATED, compresslevel=9)
    return buf.getvalue()


def write_bundle(path: str | Path, members: dict[str, bytes]) -> None:
    """Write the zip whole or not at all."""
    p = Path(path)
    if p.exists() and not p.is_file():
        raise OSError(f"{p}: exists and is not a regular file")
    data = zip_bytes(members)
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.parent / f".{p.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
    try:
        with open(tmp, "xb") as f:
            f.write(data)
        os.replace(tmp, p)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def read_bundle(path: str | Path) -> dict[str, bytes]:
    """The members of a bundle. Raises :class:`EvidenceError` naming what is wrong."""
    try:
        size = Path(path).stat().st_size
    except OSError as exc:
        raise EvidenceError(f"{path}: cannot be read ({exc.strerror})") from None
    if size > MAX_BYTES:
        raise EvidenceError(f"{path}: {size} bytes, more than a bundle holds ({MAX_BYTES})")
    try:
        with zipfile.ZipFile(path) as z:
            out = {}
            for info in z.infolist():
                if info.file_size > MAX_BYTES:
                    raise EvidenceError(f"{path}: {info.filename}: larger than a bundle holds")
                out[info.filename] = z.read(info)
            return out
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, EOFError) as exc:
        raise EvidenceError(f"{path}: not a readable zip ({exc})") from None


# ------------------------------------------------------------------ signatures (ssh-keygen)


def _ssh_keygen() -> str:
    exe = shutil.which("ssh-keygen")
    if exe is None:
        raise EvidenceError("ssh-keygen is not installed (OpenSSH's client tools sign and verify bundles)")
    return exe


def sign(data: bytes, key: str | Path) -> bytes:
    """The OpenSSH signature of ``data`` with the private key file ``key`` (namespace
    ``ptpcert``). Raises :class:`EvidenceError` with ssh-keygen's reason."""
    exe = _ssh_keygen()
    with tempfile.TemporaryDirectory() as d:
        msg = Path(d) / "manifest.json"
        msg.write_bytes(data)
        try:
            p = subprocess.run([exe, "-Y", "sign", "-n", NAMESPACE, "-f", str(key), str(msg)],
                               stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise EvidenceError(f"--sign {key}: ssh-keygen failed ({exc})") from None
        sig = msg.with_name("manifest.json.sig")
        if p.returncode != 0 or not sig.exists():
            why = " ".join((p.stderr or p.stdout).split())[:300] or f"exit status {p.returncode}"
            raise EvidenceError(f"--sign {key}: ssh-keygen cannot sign with it ({why}); give an OpenSSH private "
                                "key without a passphrase, or one an ssh-agent holds")
        return sig.read_bytes()


def check_signature(data: bytes, signature: bytes, allowed_signers: str | Path) -> tuple[bool, str]:
    """Whether ``signature`` is a good signature of ``data`` by a key of
    ``allowed_signers`` (namespace ``ptpcert``), and who signed or why not."""
    exe = _ssh_keygen()
    with tempfile.TemporaryDirectory() as d:
        sig = Path(d) / "manifest.json.sig"
        sig.write_bytes(signature)
        try:
            found = subprocess.run([exe, "-Y", "find-principals", "-s", str(sig), "-f", str(allowed_signers)],
                                   stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
        except (OSError, subprocess.TimeoutExpired) as exc:
            return False, f"ssh-keygen failed ({exc})"
        principals = [x.strip() for x in found.stdout.splitlines() if x.strip()]
        if found.returncode != 0 or not principals:
            return False, f"signed by a key that {allowed_signers} does not list"
        for who in principals:
            p = subprocess.run([exe, "-Y", "verify", "-f", str(allowed_signers), "-I", who, "-n", NAMESPACE,
                                "-s", str(sig)], input=data, capture_output=True, timeout=60)
            if p.returncode == 0:
                return True, f"good signature by {who}"
        why = " ".join(p.stderr.decode("utf-8", "replace").split())[:300]
        return False, f"the signature does not verify ({why})"


def members_json(doc: Any) -> bytes:
    """A JSON member: sorted keys, one space of indent, a final newline."""
    return (json.dumps(doc, indent=1, sort_keys=True, ensure_ascii=False) + "\n").encode()
