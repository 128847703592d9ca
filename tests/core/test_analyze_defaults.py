"""What ``analyze`` judges when not told (issue 27, items 7 and 18): in the capture of a run
of the suite, the IUT's seat b only (seat a is the tester, whose deviations are the cases'
deliberate stimuli), so that a clean run's capture passes; both seats in any other capture;
the summary says which and why. A capture of a run names its procedure, and a profile of
another procedure is refused with one line."""

from __future__ import annotations

from pathlib import Path

import pytest

from ptpcert import capture as C
from ptpcert.cli import main as cli_main

PROFILES = Path(__file__).resolve().parents[2] / "conformance" / "profiles"
PROFILE = PROFILES / "reference-20ms.toml"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A few cases of the suite against the model, with deliberate deviations of the tester
    (a wrong BCC, a NAK out of turn), as results JSON, pcap and a converted hex log."""
    d = tmp_path_factory.mktemp("run")
    assert cli_main(["run", "--iut", "sim:", "--profile", str(PROFILE), "--select", "3964R.D0*",
                     "--json", str(d / "run.json"), "--pcap", str(d / "run.pcap"), "-q"]) == 0
    assert cli_main(["capture", "convert", str(d / "run.pcap"), str(d / "run.hexlog")]) == 0
    return d


@pytest.mark.parametrize("name", ["run.json", "run.pcap", "run.hexlog"])
def test_the_capture_of_a_clean_run_passes_judging_the_iuts_seat(run, name, capsys):
    capsys.readouterr()
    rc = cli_main(["analyze", str(run / name), "--profile", str(PROFILE)])
    out = capsys.readouterr().out
    assert rc == 0, out[-2000:]
    said = [x for x in out.splitlines() if x.startswith("judged: ")]
    assert said == ["judged: seat b (the IUT's: the capture is of a run against sim:, whose seat a is the suite's "
                    "tester with its deliberate deviations; --judge both judges it too)"]
    # the tester's deliberate deviations are there: judged when asked for
    assert cli_main(["analyze", str(run / name), "--profile", str(PROFILE), "--judge", "both", "-q"]) == 1
    assert "judged: seats a and b (--judge both)" in capsys.readouterr().out


def test_a_capture_that_names_no_run_is_judged_in_both_seats(run, tmp_path, capsys):
    cap = C.load(run / "run.pcap")
    cap.notes, cap.timing = [], None          # a recorder's capture: no run, no run's transport
    C.save(cap, tmp_path / "tap.pcap")
    capsys.readouterr()
    rc = cli_main(["analyze", str(tmp_path / "tap.pcap"), "--profile", str(PROFILE), "-q"])
    out = capsys.readouterr().out
    assert rc == 1 and "judged: seats a and b (the capture names no run" in out


def test_a_capture_of_a_run_names_its_procedure(run):
    for name in ("run.json", "run.pcap", "run.hexlog"):
        assert C.PROCEDURE_NOTE + "3964/3964R" in C.load(run / name).notes, name


@pytest.mark.parametrize("profile", ["rk512-reference.toml", "ascii-reference.toml"])
def test_a_profile_of_another_procedure_is_refused(run, profile, capsys):
    capsys.readouterr()
    assert cli_main(["analyze", str(run / "run.pcap"), "--profile", str(PROFILES / profile)]) == 2
    out, err = capsys.readouterr()
    assert not out and len(err.splitlines()) == 1
    assert "the capture is of a run of 3964/3964R, the profile is for" in err
