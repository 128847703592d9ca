"""The JUnit XML view of a run (written with junit-xml), for CI: one test case per case, a
failure's explanation and transcript tail in its output, the distinct deviations as suite
properties, an interrupted run as an error, and each case's device in a pool's run.

Part of :mod:`ptpcert.report`; the words come from :mod:`ptpcert.report.text`.
"""

from __future__ import annotations

from pathlib import Path

from ptpcert import results as R
from ptpcert.report.text import case_link, deviation_lines, failure_text, transcript_text
from ptpcert.view import NEUTRAL, ReportView

#: How each verdict shows in JUnit: as a pass, a failure, an error or a skip.
JUNIT_KIND = {
    R.PASS: "pass", R.NON_STRICT: "pass", R.INFORMATIONAL: "pass",
    R.FAIL: "failure", R.XPASS: "failure",
    R.ERROR: "error",
    R.UNSUPPORTED: "skipped", R.XFAIL: "skipped", R.NOT_RUN: "skipped",
}


def write_junit(run: R.RunResult, path: str | Path, view: ReportView | None = None) -> None:
    """Write the run as one JUnit test suite to ``path`` (whole or not at all); ``view``: the
    procedure's (its profile keys written as the profile writes them)."""
    from junit_xml import TestCase, TestSuite, to_xml_report_string

    cases = []
    devs = run.deviations()          # computed once: a run in progress keeps none stored
    group_of = {cid: i + 1 for i, g in enumerate(devs) for cid in g.get("cases", [])}
    n_groups = len(devs)
    for c in run.cases:
        name = f"{c.id} [{c.reference}]"
        out = [f"rule: {c.rule}", f"verdict: {c.verdict}",
               f"expected STATUS at the IUT: {c.expected_status}",
               f"a CP 341 in the tester's seat raises: {c.tester_status}"]
        if c.message:
            out.append(c.message)
        link = case_link(run, c)
        if link:
            out.append(f"report: {link}")
        tc = TestCase(name, classname=f"ptpcert.{c.group}", elapsed_sec=round(c.duration, 6),
                      stdout="\n".join(out), stderr=c.stderr_tail or None, url=link or None,
                      file=c.source or None)
        kind = JUNIT_KIND.get(c.verdict, "error")
        detail = failure_text(c) + "\n\ntranscript (tail):\n" + transcript_text(c)
        if link:
            detail += f"\n\nsequence diagram: {link}"
        if c.id in group_of:
            g = devs[group_of[c.id] - 1]
            detail = f"deviation {group_of[c.id]} of {n_groups}: {g['description']}\n\n" + detail
        if kind == "failure":
            tag = f"[deviation {group_of[c.id]} of {n_groups}] " if c.id in group_of else ""
            where = R.divergence_frame_text(c)
            msg = f"{tag}{c.verdict}: {c.message}" + (f"; {where}" if where else "")
            if len(msg) > 500 and where:   # the frame stays in view; the message gives way
                msg = f"{tag}{c.verdict}: {c.message}"[:480 - len(where)] + f"…; {where}"
            tc.add_failure_info(message=msg[:500], output=detail, failure_type=c.verdict)
        elif kind == "error":
            tc.add_error_info(message=c.message[:500], output=detail, error_type="harness")
        elif kind == "skipped":
            tc.add_skipped_info(message=f"{c.verdict}: {c.message}"[:500])
        cases.append(tc)
    if run.interrupted:
        # a CI view that reads only JUnit must not show an interrupted run as green
        done = sum(c.verdict != R.NOT_RUN for c in run.cases)
        why = (f"the run was interrupted (Ctrl-C or SIGTERM) after {done} of {len(run.cases)} cases; "
               "the cases not reached are reported as skipped (not-run)")
        tc = TestCase("run interrupted", classname="ptpcert.run", elapsed_sec=0.0, stdout=why)
        tc.add_error_info(message=why, error_type="interrupted")
        cases.append(tc)
    props = {"tool": f"ptpcert {run.tool_version}", "iut": run.iut, "profile": run.profile_path,
             "vector_set_hash": run.vector_set_hash, "verdict": run.verdict,
             "interrupted": str(run.interrupted).lower()}
    for k, v in run.iut_identity.items():
        props[f"identity.{k}"] = v
    if run.shard:
        props["shard"] = run.shard
    if run.merged_from:
        props["merged_from"] = " ".join(run.merged_from)
    for k, v in (view or NEUTRAL).settings(run.profile):
        props[f"profile.{k}"] = v
    for i, g in enumerate(devs, 1):
        props[f"deviation.{i}"] = g["description"]
    dev = "\n".join(deviation_lines(run, groups=devs)).strip()
    name = f"ptpcert {run.procedure} conformance" if run.procedure else "ptpcert conformance"
    suite = TestSuite(name, cases, timestamp=run.started,
                      properties=props, stdout=dev or None)
    xml = to_xml_report_string([suite], prettyprint=True)
    per_case = [{"rules": " ".join(c.rules), "device": c.device} for c in run.cases]
    if any(v for d in per_case for v in d.values()):
        xml = _with_properties(xml, per_case)
    R.write_atomic(path, xml)


def _with_properties(xml: str, per_case: list[dict[str, str]]) -> str:
    """Each test case gets its properties: ``rules``, the ids of the manual's rules it checks
    (space-separated), and in a pool's run ``device``, the IUT that ran it (the cases are in
    the results' order; the interrupted marker, if any, comes after). Empty ones are left out."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(xml)
    for tc, values in zip(root.iter("testcase"), per_case):
        if any(values.values()):
            props = ET.Element("properties")
            for name, value in values.items():
                if value:
                    ET.SubElement(props, "property", name=name, value=value)
            tc.insert(0, props)
    ET.indent(root, space="\t")
    return "<?xml version=\"1.0\" ?>\n" + ET.tostring(root, encoding="unicode") + "\n"

