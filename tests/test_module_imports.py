"""Every module of robkin imports on its own, first, in a fresh interpreter state: no import cycle
that only works in one order (``from robkin.io.urdf.chain import robot_from_urdf`` once failed
unless ``robkin.io.urdf`` had been imported before)."""

from __future__ import annotations

import subprocess
import sys

CODE = r"""
import importlib, pkgutil, sys
import robkin
names = sorted(m.name for m in pkgutil.walk_packages(robkin.__path__, "robkin."))
failed = []
for name in names:
    for loaded in [m for m in sys.modules if m == "robkin" or m.startswith("robkin.")]:
        del sys.modules[loaded]
    try:
        importlib.import_module(name)
    except ImportError as exc:
        if exc.name and not exc.name.startswith("robkin"):  # an optional dependency not installed
            continue
        failed.append(f"{name}: {exc}")
print(len(names))
print("\n".join(failed))
"""


def test_every_module_imports_first():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, check=True).stdout
    count, *failed = out.strip().split("\n")
    assert int(count) > 80
    assert [f for f in failed if f] == []
