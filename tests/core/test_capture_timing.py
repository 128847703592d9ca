"""A capture says how its times were taken (issue 25, item 12), and ``analyze`` judges it
with that by default: ``run --pcap`` then ``analyze --judge b`` gives the run's verdicts for
the IUT's seat whatever the IUT's pacing. The realtime test at the end runs the whole
suite against two stations over exec: (a pipe, no baud rate): the reference writing whole
blocks at once, and the same relayed one byte per millisecond."""

from __future__ import annotations

import bisect
import io
import json
import sys
from pathlib import Path

import pytest

from ptpcert import capture as C
from ptpcert.cli import main as cli_main

HERE = Path(__file__).parent
#: a real case of a run against an exec: station that writes whole blocks at once (the run
#: passed it); at resolution 0 analyze found "byte 1 of the block ... too early"
PIPE_CASE = HERE / "data" / "pipe-whole-blocks.hexlog"
PROFILE = HERE.parents[1] / "conformance" / "profiles" / "reference-20ms.toml"
PIPE = C.Timing("pipe", 0.005437, 0.001146)


def _analyze(path: Path, *extra: str) -> int:
    return cli_main(["analyze", str(path), "--profile", str(PROFILE), "--judge", "b", "-q", *extra])


@pytest.mark.parametrize("fmt", ["json", "hexlog", "pcap", "results"])
def test_every_format_carries_the_timing(fmt):
    cap = C.Capture([C.Chunk(0.001, "a", b"\x02"), C.Chunk(0.003, "b", b"\x10")], timing=PIPE)
    back = C.loads_json(C.dumps(cap, fmt)) if fmt in ("json", "results") else None
    if back is None:
        data = C.dumps(cap, fmt)
        back = C.read_pcap(data) if fmt == "pcap" else C.read_hexlog(data.decode())
    assert back.timing == PIPE
    assert [c.data for c in back.chunks] == [b"\x02", b"\x10"]


def test_captures_written_before_still_load():
    cap = C.Capture([C.Chunk(0.001, "a", b"\x02")])
    old_json = C.to_dict(cap)
    del old_json["timing"]
    assert C.from_dict(old_json).timing is None
    assert C.read_hexlog("0.001 a 02\n").timing is None
    assert C.read_pcap(C.pcap_bytes(cap)).timing is None      # the start record's payload is empty
    assert C.read_pcap(C.pcap_bytes(cap)).chunks == cap.chunks


def test_a_wrong_timing_is_refused_with_what_is_wrong():
    with pytest.raises(C.CaptureError, match="resolution"):
        C.read_hexlog("# timing: transport=pipe resolution=fast\n0.001 a 02\n")
    with pytest.raises(C.CaptureError, match="transport"):
        C.from_dict({**C.to_dict(C.Capture()), "timing": {"transport": "carrier pigeon"}})


def test_a_run_says_how_its_times_were_taken():
    assert C.run_timing("sim:", 0.001).resolution == 0
    assert C.run_timing("exec:ptpcert iut", 0.001146).transport == "pipe"
    assert C.run_timing("exec:x", 0.001).resolution == pytest.approx(3 * 0.001 + 0.002)
    assert C.run_timing("serial:///dev/ttyUSB0", 0.001).transport == "port"


def test_analyze_judges_a_pipe_capture_with_its_own_timing(tmp_path):
    cap = C.load(PIPE_CASE)
    assert cap.timing is not None and cap.timing.transport == "pipe"
    assert _analyze(PIPE_CASE) == 0
    pcap = tmp_path / "case.pcap"
    C.save(cap, pcap, "pcap")
    assert _analyze(pcap) == 0                                # pcap carries it too
    # an explicit --resolution-ms wins: the exact reading finds the pipe's early stamps
    assert _analyze(pcap, "--resolution-ms", "0") == 1
    # what a pcap without it gave (the issue): no timing, no run named, exact times
    cap.timing, cap.notes = None, []
    old = tmp_path / "old.pcap"
    C.save(cap, old, "pcap")
    assert _analyze(old) == 1


# ------------------------------------------------------------------ the whole suite, real time

STATIONS = {
    "whole blocks": "ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk --baud 0",
    "a byte per ms": f"{sys.executable} {HERE / 'paced_station.py'} --gap-ms 1 -- "
                     "ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk --baud 0",
}
#: cases the run passed and the line analysis fails, per station: none. Whole blocks: a pipe
#: delivers a station's whole block at once, and the tester's interruption (BREAK, NAK, a
#: timeout) that reached it once the block was whole is stamped before the reads of the
#: block's tail; the ordering rule (ptpcert.analysis.order) takes characters stamped within
#: the resolution of each other in either order. A byte per ms: the relay goes on sending the
#: block's tail for tens of milliseconds after the BREAK; the analysis grants it the BREAK,
#: four characters and the late tolerance, as the run's SUITE.BREAK.DATA does.
KNOWN: dict[str, set[str]] = {"whole blocks": set(), "a byte per ms": set()}


def agreement(run_json: Path, analysis_json: Path) -> tuple[int, dict[str, str]]:
    """Cases whose run verdict for the IUT (fail or not) the analysis of the run's capture
    gives too, and the others with the run's verdict: the analysis's exchanges are placed in
    the cases by their times (the run's marks)."""
    run = json.loads(run_json.read_text())
    an = json.loads(analysis_json.read_text())
    starts = [(m.t, m.text.split()[1]) for m in C.load(run_json).marks if m.text.startswith("case ")]
    times = [t for t, _ in starts]
    failed = set()
    for c in an["cases"]:
        if c["verdict"] == "fail":
            t = float(c["notes"][0].split(": ")[1].split(" s ")[0])
            failed.add(starts[bisect.bisect_right(times, t) - 1][1])
    agree, apart = 0, {}
    for c in run["cases"]:
        if c["verdict"] in ("unsupported", "not-run", "error"):
            continue                       # the run gave no verdict on the IUT
        if (c["verdict"] == "fail") == (c["id"] in failed):
            agree += 1
        else:
            apart[c["id"]] = c["verdict"]
    return agree, apart


# a certification run (about 4 minutes), left out of CI while one disagreement remains open:
# on a loaded machine the harness reads a whole block in one read, the analysis spreads the
# read back at line pace (n-1 character times, more than a pipe's resolution) and puts the
# block's first bytes before the DLE they answer (seen once: SUITE.TIMING.SETUP-DLE-AT-80-ADT)
@pytest.mark.realtime
@pytest.mark.long
@pytest.mark.parametrize("station", list(STATIONS))
def test_analyze_of_a_runs_capture_gives_the_runs_verdicts(tmp_path, station, capsys):
    run_json, pcap = tmp_path / "run.json", tmp_path / "run.pcap"
    cli_main(["run", "--iut", "exec:" + STATIONS[station], "--profile", str(PROFILE), "-q",
              "--json", str(run_json), "--pcap", str(pcap)])
    back = C.load(pcap)
    assert back.timing.transport == "pipe" and back.marks == C.load(run_json).marks
    for capture in (pcap, run_json):
        out = tmp_path / f"analysis-{capture.suffix[1:]}.json"
        _analyze(capture, "--json", str(out))
        agree, apart = agreement(run_json, out)
        with capsys.disabled():
            print(f"\n{station}, {capture.name}: {agree} cases agree, apart: {apart}")
        assert agree > 100
        # the analysis fails no case the run passed (the IUT is the conforming reference)
        stricter = {c for c, v in apart.items() if v != "fail"}
        assert stricter <= KNOWN[station], apart
        # a case the run failed and the analysis did not is the run's false alarm on the
        # reference (e.g. a stimulus "during" a block the IUT had written whole while the
        # harness, loaded, had not yet read it): told, not asserted - this test is about analyze
        with capsys.disabled():
            print(f"  the run failed the reference where the analysis did not: "
                  f"{sorted(set(apart) - stricter) or 'none'}")
