"""The `rockcal` command line: a thin layer over the Python API."""
