"""The hypothesis settings profiles of ptpcert, for both levels of the fuzzer; they extend
hypothesis's built-in ``ci`` profile. They are registered where a program starts that needs
them (``ptpcert fuzz``, its worker processes, the pytest plugin and the test suite's
conftest), never as a side effect of an import."""

from __future__ import annotations

from hypothesis import HealthCheck, settings

#: the profiles :func:`register_profiles` registers
PROFILES = ("ptpcert-quick", "ptpcert-thorough")

_SUPPRESSED = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]


def register_profiles() -> None:
    """Register ``ptpcert-quick`` (60 examples, 40 stateful steps) and ``ptpcert-thorough``
    (2,000 examples, 120 steps, not derandomized); registering again changes nothing."""
    ci = settings.get_profile("ci")
    settings.register_profile("ptpcert-quick", parent=ci, max_examples=60, stateful_step_count=40,
                              suppress_health_check=_SUPPRESSED)
    settings.register_profile("ptpcert-thorough", parent=ci, derandomize=False, max_examples=2000,
                              stateful_step_count=120, suppress_health_check=_SUPPRESSED)
