"""ptpcert: conformance test suite and fuzzer for the 3964 / 3964R point-to-point procedures.

The package is layered (see DESIGN): ``ptpcert.model`` is the pure reference model,
``ptpcert.scenario`` the vector schema, ``ptpcert.transport`` the ways to reach an IUT,
``ptpcert.runner`` the one blocking driver, ``ptpcert.cli`` the command line.
"""

__version__ = "0.1.0"
