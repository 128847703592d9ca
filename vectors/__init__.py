"""The golden vectors (data only): one TOML file per vector, a folder per procedure.
Found at run time with importlib.resources, so they work from an installed wheel."""
