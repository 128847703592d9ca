"""The RK 512 suite against real-time IUTs through exactly the interface of an RK 512 IUT:

* the reference IUT (``ptpcert iut --procedure RK512``) passes the whole suite over exec: and
  pty:, in both roles, at both priorities and over 3964R and 3964 as the link;
* an RK 512 station written by someone else from the manual alone (tests/independent/rk512)
  passes it too: a case it fails is either a false alarm of ours or a deviation of that
  station from the manual, and the correct station has none;
* each of that station's broken variants is caught, by the case named here (the whole
  matrix: ``benchmarks/kill_matrix.py --procedure RK512 --independent``).

The suite is split over the four configurations (tests/procedures/rk512/rk512_shares.py), two running at a
time, so every case runs once in about half the time of one suite run."""

from __future__ import annotations

import json
import subprocess

import pytest

from rk512_profiles import (PY, ROOT, independent_command, independent_variants, iut_command, rk_profile_dict,
                            write_profile)
from rk512_shares import CONFIGS, OK, REALTIME, run_shares, shares


def test_the_shares_hold_every_case_of_every_configuration_once():
    from rk512_shares import suite_ids
    got = shares()
    flat = [cid for s in got for cid in s]
    assert len(flat) == len(set(flat))
    for (link, prio, _), share in zip(CONFIGS, got):
        assert set(share) <= set(suite_ids(link, prio))
    assert set(flat) == set().union(*(suite_ids(link, prio) for link, prio, _ in CONFIGS))
    # every configuration runs cases of both roles, and its share of the link's cases
    for share in got:
        assert any(".P-" in c for c in share) and any(".A-" in c for c in share) and any(".L-" in c for c in share)


def _judge(results):
    for cfg, p, data in results:
        bad = {c["id"]: c["message"] for c in data["cases"] if c["verdict"] not in OK}
        assert p.returncode == 0 and not bad, (cfg, bad)
        roles = {c["iut_role"] for c in data["cases"]}
        assert {"sender", "receiver"} <= roles, (cfg, roles)
        assert any(c["frames"] for c in data["cases"])


@pytest.mark.realtime
@pytest.mark.long
def test_the_whole_suite_passes_the_real_time_reference(tmp_path):
    """Done when: the suite passes the reference IUT over exec: and pty:, in both roles and
    at both priorities, and over 3964 as the link."""
    results = run_shares(tmp_path, lambda raw, scheme: iut_command(raw, scheme=scheme))
    _judge(results)
    # nothing but the strict reading: the reference takes the main reading of every open point
    assert all(c["verdict"] == "pass" for _, _, data in results for c in data["cases"])
    assert sum(len(data["cases"]) for _, _, data in results) == sum(map(len, shares()))


@pytest.mark.realtime
@pytest.mark.long
def test_the_whole_suite_passes_the_independent_station(tmp_path):
    """Done when: an implementation written independently from the manual, driven through
    exactly the interface of an RK 512 IUT, passes; cases that hinge on an open point where it
    takes another reading are graded down, never failed."""
    results = run_shares(tmp_path, lambda raw, scheme: independent_command(raw, scheme=scheme))
    _judge(results)
    assert sum(len(data["cases"]) for _, _, data in results) == sum(map(len, shares()))
    # its other readings are graded down, and only in cases that name their open point
    down = [c for _, _, data in results for c in data["cases"] if c["verdict"] != "pass"]
    assert all(c["readings"] for c in down), [c["id"] for c in down]


#: each broken variant of the independent station and a case that catches it (the first in the
#: kill matrix by the rule the variant breaks)
CAUGHT_BY = {
    "reatel-db-0c": "SUITE.RK512.P-07D.FETCH-DB200",
    "cont-byte3-changed": "SUITE.RK512.A-03.SEND-200",
    "no-tres-active": "SUITE.RK512.A-05.NO-RESPONSE",
    "tres-too-short": "SUITE.RK512.A-05.RESPONSE-AT-0.8-TRES",
    "length-in-bytes": "SUITE.RK512.A-01.SEND-DB",
    "odd-send-no-pad": "SUITE.RK512.A-09.SEND-ODD-LENGTH",
    "counter-letter-c": "SUITE.RK512.A-02.FETCH-COUNTERS",
    "unknown-reatel-0905": "SUITE.RK512.A-06.REATEL-01",
    "response-dle-not-doubled": "SUITE.RK512.L-02.DLE-AS-REATEL",
    "fetch-one-byte-too-many": "SUITE.RK512.P-05.FETCH-D-300",
    "cont-response-byte1-00": "SUITE.RK512.P-02.SEND-200",
    "no-tres-passive": "SUITE.RK512.P-10.CONTINUATION-TOO-LATE",
    "data-count-unchecked": "SUITE.RK512.P-07I.SEND-8-FOR-10",
    "flag-ignored": "SUITE.RK512.P-11.FLAG-SET-REFUSES",
}


def test_every_independent_variant_has_a_catching_case():
    assert set(CAUGHT_BY) == set(independent_variants())


@pytest.mark.realtime
@pytest.mark.long
@pytest.mark.parametrize("variant", sorted(CAUGHT_BY))
def test_the_independent_stations_broken_variants_are_caught(tmp_path, variant):
    raw = rk_profile_dict(**REALTIME)
    prof = write_profile(tmp_path / "p.toml", raw)
    j = tmp_path / "r.json"
    p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", independent_command(raw, brk=variant),
                        "--profile", str(prof), "--json", str(j), "-q", "--select", CAUGHT_BY[variant]],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    data = json.loads(j.read_text())
    assert p.returncode == 1
    assert [c["verdict"] for c in data["cases"]] == ["fail"], data["cases"][0]["message"]
