"""Evidence bundles (issue 28): ``run --evidence`` writes one archive that ``verify`` checks
(hashes, signature, digests) and re-judges (the capture analysed offline against the bundled
profile agrees with the recorded verdicts); every part tampered with in turn makes ``verify``
fail with a line naming it."""

from __future__ import annotations

import io
import json
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.cli import main as cli_main
from ptpcert.evidence import bundle as B
from ptpcert.evidence import run_capture

ROOT = Path(__file__).resolve().parents[2]
PROFILES = ROOT / "conformance" / "profiles"
REF = PROFILES / "reference-20ms.toml"
PY = sys.executable
IUT = f"{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk"
#: a few groups of the 3964 suite: start-up, BREAK (what the broken variant breaks), BCC
SELECT = ["--select", "SUITE.STARTUP.*", "--select", "SUITE.BREAK.*", "--select", "SUITE.RECEIVE.BCC-*"]
SSH_KEYGEN = shutil.which("ssh-keygen")


def make_bundle(tmp_path, iut: str, profile: Path = REF, *extra: str, name: str = "bundle.zip") -> Path:
    path = tmp_path / name
    status = cli_main(["run", "--iut", iut, "--profile", str(profile), "-q", "--evidence", str(path), *extra])
    assert status in (0, 1) and path.is_file()
    return path


def verify(path: Path, capsys, *extra: str) -> tuple[int, list[str]]:
    capsys.readouterr()
    status = cli_main(["verify", str(path), *extra])
    return status, capsys.readouterr().out.splitlines()


def failing(lines: list[str]) -> list[str]:
    return [x for x in lines if x.startswith("FAIL")]


def members(path: Path) -> dict[str, bytes]:
    with zipfile.ZipFile(path) as z:
        return {n: z.read(n) for n in z.namelist()}


def rewrite(path: Path, out: Path, change, *, reseal: bool = True) -> Path:
    """``path`` with its members changed by ``change(members)``; ``reseal``: the manifest and
    the certificate's digest made to fit again, as someone without the key would."""
    m = members(path)
    change(m)
    if reseal:
        m.pop(B.MANIFEST)
        files = {n: B.sha256(b) for n, b in m.items() if n not in (B.CERTIFICATE, B.SIGNATURE)}
        old = json.loads(members(path)[B.MANIFEST])["bundle_digest"]
        m[B.CERTIFICATE] = m[B.CERTIFICATE].replace(old.encode(), B.bundle_digest(files).encode())
        m[B.MANIFEST] = B.manifest_bytes({n: b for n, b in m.items() if n != B.SIGNATURE})
    out.write_bytes(B.zip_bytes(m))
    return out


def edit_results(m: dict[str, bytes], edit, *, capture_too: bool = False) -> None:
    d = json.loads(m["results.json"])
    edit(d)
    m["results.json"] = (json.dumps(d, indent=1) + "\n").encode()
    if capture_too:   # the capture made again from the edited results: its marks agree with them
        m["capture.pcap"] = C.dumps(run_capture(R.RunResult.from_dict(d)), "pcap")


# ------------------------------------------------------------------ every procedure, sim:


@pytest.mark.parametrize("profile", ["reference-20ms", "rk512-reference", "ascii-reference"])
def test_a_bundle_of_each_procedure_verifies_and_its_capture_is_rejudged(tmp_path, capsys, profile):
    path = make_bundle(tmp_path, "sim:", PROFILES / f"{profile}.toml")
    names = sorted(members(path))
    assert names == sorted(B.MEMBERS + (B.MANIFEST,))
    status, lines = verify(path, capsys)
    assert status == 0, lines
    rejudged = [x for x in lines if x.startswith("ok    capture.pcap: re-judged offline")]
    assert rejudged and int(rejudged[0].split(": ")[2].split()[0]) > 10
    assert lines[-1].endswith("VERIFIED")


def test_a_broken_variant_s_bundle_verifies_in_each_procedure(tmp_path, capsys):
    for profile, mutant in (("reference-20ms", "break-as-data"), ("rk512-reference", "send-response-with-data")):
        path = make_bundle(tmp_path, f"sim:?mutant={mutant}", PROFILES / f"{profile}.toml", name=f"{profile}.zip")
        run = json.loads(members(path)["results.json"])
        assert run["verdict"] == "fail"
        status, lines = verify(path, capsys)
        assert status == 0, failing(lines)


def test_the_zip_is_deterministic_and_its_members_sorted(tmp_path):
    path = make_bundle(tmp_path, "sim:", REF, "--select", "SUITE.STARTUP.*")
    m = members(path)
    assert B.zip_bytes(m) == path.read_bytes()                       # the same members make the same bytes
    with zipfile.ZipFile(path) as z:
        infos = z.infolist()
    assert [i.filename for i in infos] == sorted(m)
    assert {i.date_time for i in infos} == {B.ZIP_TIME}
    manifest = json.loads(m[B.MANIFEST])
    assert manifest["files"] == {n: B.sha256(b) for n, b in m.items() if n != B.MANIFEST}


def test_the_pics_pixit_and_tool_facts_are_in_the_bundle(tmp_path):
    path = make_bundle(tmp_path, "sim:", REF, "--select", "SUITE.STARTUP.*", "--tolerance-ms", "40")
    m = members(path)
    assert m["profile.toml"] == REF.read_bytes()
    pics = json.loads(m["profile.json"])
    assert pics["procedure_title"] == "3964/3964R" and "timer_tolerance_ms" in pics
    pixit = json.loads(m["pixit.json"])
    assert pixit["transport"] == ["sim:"] and pixit["tolerance_ms"] == 40 and pixit["select"] == ["SUITE.STARTUP.*"]
    tool = json.loads(m["tool.json"])
    run = json.loads(m["results.json"])
    assert tool["cases"] == len(run["cases"]) and len(tool["suite_digest"]) == 64
    assert tool["rules_catalogues"] and all(len(c["digest"]) == 64 for c in tool["rules_catalogues"])
    digest = json.loads(m[B.MANIFEST])["bundle_digest"]
    assert f'id="bundle-digest">{digest}<' in m[B.CERTIFICATE].decode()


# ------------------------------------------------------------------ tampering


def _tampered(path: Path, tmp_path: Path, run: dict) -> dict[str, Path]:
    """Each part tampered with in turn."""
    first = run["cases"][0]["id"]
    failed = next((c["id"] for c in run["cases"] if c["verdict"] == "fail"), None)
    passed = next((c["id"] for c in run["cases"] if c["verdict"] == "pass"), None)
    flip = failed or passed

    def verdict(d):
        for c in d["cases"]:
            if c["id"] == flip:
                c["verdict"] = "pass" if c["verdict"] == "fail" else "fail"
                c["message"] = ""

    def byte(m):
        raw = bytearray(m["results.json"])
        raw[len(raw) // 2] ^= 0x01
        m["results.json"] = bytes(raw)

    def drop(d):
        d["cases"] = [c for c in d["cases"] if c["id"] != first]

    def truncate(m):
        m["capture.pcap"] = m["capture.pcap"][: len(m["capture.pcap"]) // 2]

    def manifest(m):
        doc = json.loads(m[B.MANIFEST])
        doc["files"]["junit.xml"] = "0" * 64
        m[B.MANIFEST] = (json.dumps(doc, indent=1, sort_keys=True) + "\n").encode()

    return {
        "results.json": rewrite(path, tmp_path / "byte.zip", byte, reseal=False),
        "verdict": rewrite(path, tmp_path / "verdict.zip", lambda m: edit_results(m, verdict)),
        "verdict with its capture": rewrite(path, tmp_path / "verdict2.zip",
                                            lambda m: edit_results(m, verdict, capture_too=True)),
        "case removed": rewrite(path, tmp_path / "drop.zip", lambda m: edit_results(m, drop)),
        "capture truncated": rewrite(path, tmp_path / "cut.zip", truncate),
        "manifest": rewrite(path, tmp_path / "manifest.zip", manifest, reseal=False),
    }


#: the part each tampering must be named by in a FAIL line
NAMED = {"results.json": "results.json", "verdict": "results.json", "verdict with its capture": "results.json",
         "case removed": "results.json", "capture truncated": "capture.pcap", "manifest": "manifest.json"}


def check_tampering(path: Path, tmp_path: Path, capsys, skip: tuple[str, ...] = ()) -> None:
    status, lines = verify(path, capsys)
    assert status == 0, failing(lines)
    run = json.loads(members(path)["results.json"])
    for what, bad in _tampered(path, tmp_path, run).items():
        if what in skip:
            continue
        status, lines = verify(bad, capsys)
        named = [x for x in failing(lines) if x.split()[1].rstrip(":") == NAMED[what]]
        assert status == 1 and named, (what, lines)
        assert lines[-1].endswith(f"NOT VERIFIED ({len(failing(lines))} check(s) failed)")


def test_each_tampered_part_fails_verification_naming_it(tmp_path, capsys):
    path = make_bundle(tmp_path, "sim:?mutant=break-as-data", REF, *SELECT)
    check_tampering(path, tmp_path, capsys)


def test_an_edited_verdict_is_found_by_rejudging_even_where_everything_else_fits(tmp_path, capsys):
    path = make_bundle(tmp_path, "sim:?mutant=break-as-data", REF, *SELECT)
    run = json.loads(members(path)["results.json"])
    bad = _tampered(path, tmp_path, run)["verdict with its capture"]
    status, lines = verify(bad, capsys)
    assert status == 1
    assert [x for x in failing(lines) if x.startswith("FAIL  results.json: verdict of ")], lines
    assert not [x for x in failing(lines) if "SHA-256" in x or "digest" in x], lines   # hashes all fit


# ------------------------------------------------------------------ signatures


def _keys(tmp_path: Path, name: str) -> tuple[Path, Path]:
    key = tmp_path / name
    subprocess.run([SSH_KEYGEN, "-q", "-t", "ed25519", "-N", "", "-C", name, "-f", str(key)], check=True, timeout=30)
    allowed = tmp_path / f"{name}.allowed"
    allowed.write_text(f"{name}@example {Path(str(key) + '.pub').read_text()}")
    return key, allowed


@pytest.mark.skipif(SSH_KEYGEN is None, reason="ssh-keygen (OpenSSH) is not installed")
def test_a_signed_bundle_verifies_with_its_signer_and_fails_with_another(tmp_path, capsys):
    key, allowed = _keys(tmp_path, "vendor")
    _, stranger = _keys(tmp_path, "stranger")
    path = make_bundle(tmp_path, "sim:", REF, "--select", "SUITE.STARTUP.*", "--sign", str(key))
    assert B.SIGNATURE in members(path)
    status, lines = verify(path, capsys, "--allowed-signers", str(allowed))
    assert status == 0 and any(x.startswith("ok    manifest.json.sig: good signature by vendor@example")
                               for x in lines), lines
    status, lines = verify(path, capsys, "--allowed-signers", str(stranger))
    assert status == 1 and [x for x in failing(lines) if x.startswith("FAIL  manifest.json.sig:")], lines
    status, lines = verify(path, capsys)                               # signed, nothing to check it with
    assert status == 1 and "--allowed-signers" in failing(lines)[0]
    # the manifest re-sealed after an edit: the signature no longer fits
    bad = rewrite(path, tmp_path / "resealed.zip", lambda m: edit_results(m, lambda d: d["cases"].pop()))
    status, lines = verify(bad, capsys, "--allowed-signers", str(allowed))
    assert status == 1 and [x for x in failing(lines) if x.startswith("FAIL  manifest.json.sig:")], lines


@pytest.mark.skipif(SSH_KEYGEN is None, reason="ssh-keygen (OpenSSH) is not installed")
def test_a_key_that_cannot_sign_is_refused_before_anything_runs(tmp_path, capsys):
    bad = tmp_path / "not-a-key"
    bad.write_text("hello\n")
    status = cli_main(["run", "--iut", "sim:", "--profile", str(REF), "-q", "--evidence", str(tmp_path / "b.zip"),
                       "--sign", str(bad)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and err[0].startswith(f"ptpcert run: --sign {bad}: ")
    assert not (tmp_path / "b.zip").exists()


# ------------------------------------------------------------------ bad usage, start-up, bounds


def test_bad_paths_and_files_are_one_line(tmp_path, capsys):
    (tmp_path / "dir.zip").mkdir()
    status = cli_main(["run", "--iut", "sim:", "--profile", str(REF), "-q", "--evidence", str(tmp_path / "dir.zip")])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and err == [f"ptpcert run: --evidence {tmp_path / 'dir.zip'}: is a directory; give a file name in it"]
    status = cli_main(["run", "--iut", "sim:", "--profile", str(REF), "-q", "--sign", "k"])
    assert status == 2 and "--sign needs --evidence" in capsys.readouterr().err
    junk = tmp_path / "junk.zip"
    junk.write_bytes(b"not a zip")
    status = cli_main(["verify", str(junk)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and "not a readable zip" in err[0]


def test_identity_is_validated_and_shown_in_every_report(tmp_path, capsys):
    profile = tmp_path / "p.toml"
    text = REF.read_text()
    profile.write_text(text + '\n[iut.identity]\nvendor = "ACME"\nproduct = "PtP-9"\nversion = "2.1"\n')
    bad = tmp_path / "bad.toml"
    bad.write_text(text + '\n[iut.identity]\ncolour = "red"\n')
    assert cli_main(["profile", "--check", str(bad)]) == 2
    assert "iut.identity.colour: unknown key" in capsys.readouterr().err
    bad.write_text(text + '\n[iut.identity]\nversion = 2\n')
    assert cli_main(["profile", "--check", str(bad)]) == 2
    assert "iut.identity.version: 2 is not allowed: a string" in capsys.readouterr().err
    path = make_bundle(tmp_path, "sim:", profile, "--select", "SUITE.STARTUP.*", "--junit", str(tmp_path / "j.xml"))
    out = capsys.readouterr().out
    assert "IUT: vendor ACME; product PtP-9; version 2.1" in out
    m = members(path)
    for name in ("junit.xml", "report.html", "certificate.html", "results.json"):
        assert "PtP-9" in m[name].decode(), name
    assert 'name="identity.vendor" value="ACME"' in (tmp_path / "j.xml").read_text()


@pytest.mark.realtime
def test_a_bundle_is_complete_when_the_iut_dies_at_start_up(tmp_path, capsys):
    path = tmp_path / "b.zip"
    status = cli_main(["run", "--iut", f"exec:{PY} -c 'import sys; sys.exit(3)'", "--profile", str(REF), "-q",
                       "--select", "SUITE.STARTUP.*", "--evidence", str(path)])
    assert status == 2 and path.is_file()
    run = json.loads(members(path)["results.json"])
    assert run["cases"] and {c["verdict"] for c in run["cases"]} == {"error"}
    status, lines = verify(path, capsys)
    assert status == 0, failing(lines)


@pytest.mark.realtime
def test_a_flooding_iut_s_bundle_stays_small(tmp_path, capsys):
    flood = (f"exec:{PY} -c \"import sys, itertools; [sys.stdout.buffer.write(b'x' * 4096) or sys.stdout.flush() "
             "for _ in itertools.count()]\"")
    path = tmp_path / "b.zip"
    cli_main(["run", "--iut", flood, "--profile", str(REF), "-q", "--select", "SUITE.RECEIVE.BCC-*",
              "--evidence", str(path)])
    assert path.is_file() and path.stat().st_size < 4_000_000
    assert max(len(b) for b in members(path).values()) < 8_000_000


# ------------------------------------------------------------------ real time (issue 28, Done when)


@pytest.mark.realtime
@pytest.mark.parametrize("mutant", [None, "break-as-data"])
def test_a_real_time_bundle_verifies_and_every_tampering_is_named(tmp_path, capsys, mutant):
    iut = "exec:" + IUT + (f" --mutant {mutant}" if mutant else "")
    path = make_bundle(tmp_path, iut, REF, *SELECT)
    run = json.loads(members(path)["results.json"])
    if mutant:
        assert any(c["verdict"] == "fail" for c in run["cases"])
    # in real time the line analysis blames a BREAK case's failure on the block the BREAK cut
    # (not on the case's rule), so there an edited verdict is caught by the capture's marks,
    # not by re-judging alone (the sim: test above shows re-judging alone)
    check_tampering(path, tmp_path, capsys, skip=("verdict with its capture",))


@pytest.mark.realtime
def test_a_bundle_is_complete_when_the_run_is_interrupted(tmp_path, capsys):
    import signal
    import time

    path = tmp_path / "b.zip"
    proc = subprocess.Popen([PY, "-m", "ptpcert.cli", "run", "--iut", "exec:" + IUT, "--profile", str(REF), "-q",
                             "--evidence", str(path)], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    time.sleep(3.0)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and path.is_file(), out[-2000:] + err
    run = json.loads(members(path)["results.json"])
    verdicts = {c["verdict"] for c in run["cases"]}
    assert run["interrupted"] is True and "not-run" in verdicts and "pass" in verdicts
    status, lines = verify(path, capsys)
    assert status == 0, failing(lines)


def test_a_bundle_of_one_case_marks_it_and_is_rejudged(tmp_path, capsys):
    path = make_bundle(tmp_path, "sim:?mutant=break-as-data", REF, "--select", "SUITE.BREAK.DATA")
    marks = C.read_pcap(members(path)["capture.pcap"]).marks
    assert [m.text.split()[:3] for m in marks if m.text.startswith("case ")] == [["case", "SUITE.BREAK.DATA", "(fail)"]]
    status, lines = verify(path, capsys)
    assert status == 0, failing(lines)
    run = json.loads(members(path)["results.json"])
    bad = _tampered(path, tmp_path, run)["verdict with its capture"]
    status, lines = verify(bad, capsys)
    assert status == 1 and [x for x in failing(lines) if x.startswith("FAIL  results.json: verdict of SUITE.BREAK.DATA")]
