"""What a real-time run of a correct IUT must show: no false alarm, whatever the machine.

Nothing fails. A case may end in *error* only as a harness timing fault: the machine kept
the harness from its own timing in every attempt (a loaded CI runner, a VM whose host takes
its CPUs away for tens of milliseconds), which is never blamed on the IUT. And only a few
cases may: a harness that could not keep its timing at all must still fail the test."""

from __future__ import annotations

import json
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

#: cases that may end as harness timing faults in one run before the test fails
MAX_TIMING_FAULTS = 3


def judged(p: subprocess.CompletedProcess, results: Path) -> list[dict]:
    """The cases of a `ptpcert run` (its --json file), checked as above; exit 2 exactly when
    a case ended in error."""
    assert p.returncode in (0, 2), p.stdout[-3000:] + p.stderr
    cases = json.loads(results.read_text())["cases"]
    verdicts = {c["verdict"] for c in cases}
    assert verdicts <= {"pass", "non-strict", "informational", "unsupported", "error"}, verdicts
    errors = [c for c in cases if c["verdict"] == "error"]
    assert all(c["message"].startswith("harness timing fault") for c in errors), \
        [(c["id"], c["message"]) for c in errors]
    assert len(errors) <= MAX_TIMING_FAULTS and (p.returncode == 2) == bool(errors), [c["id"] for c in errors]
    return cases


def junit_outcomes(xml: Path) -> tuple[dict[str, str], dict[str, str]]:
    """A pytest run's --junitxml file: each item's outcome (failed where it has a failure,
    else error, skipped or passed), and the message and text of each error."""
    outcomes, errors = {}, {}
    for tc in ET.parse(xml).getroot().iter("testcase"):
        kinds = {child.tag: child for child in tc}
        name = tc.get("name")
        if "failure" in kinds:
            outcomes[name] = "failed"
        elif "error" in kinds:
            outcomes[name] = "error"
            errors[name] = kinds["error"].get("message", "") + (kinds["error"].text or "")
        else:
            outcomes[name] = "skipped" if "skipped" in kinds else "passed"
    return outcomes, errors


def judged_junit(p: subprocess.CompletedProcess, xml: Path) -> dict[str, str]:
    """The same for a pytest run of the plugin (its --junitxml file): each case's outcome;
    an error only where the plugin raised a harness timing fault; pytest's exit 1 exactly
    when an item errored."""
    outcomes, errors = junit_outcomes(xml)
    assert set(outcomes.values()) <= {"passed", "skipped", "error"}, (outcomes, p.stdout[-3000:])
    assert all("harness timing fault" in m for m in errors.values()), (errors, p.stdout[-3000:])
    assert len(errors) <= MAX_TIMING_FAULTS and p.returncode == (1 if errors else 0), (p.returncode, errors,
                                                                                      p.stdout[-3000:])
    return outcomes
