"""The package's version, in one leaf module: the writers stamp it into the files they write (``<!-- written by
robkin X -->``) without importing the package's front (``robkin/__init__``). ``pyproject.toml`` says the
same number (``tests/test_release.py``)."""

__version__ = "0.3.0"
