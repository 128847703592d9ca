"""ptpcert: conformance test suite and fuzzer for the 3964 / 3964R point-to-point procedures.

The package is layered (see DESIGN): ``harness.model`` is the pure reference model,
``harness.scenario`` the vector schema, ``harness.transport`` the ways to reach an IUT,
``harness.runner`` the one blocking driver, ``harness.cli`` the command line.
"""

__version__ = "0.1.0"
