"""The compiled core is loaded lazily, a module when first needed: `import robkin` imports none of it.
Building a Robot loads only the rigid-transform test (``robkin.compiled.runtime.rigid``, no dependencies), so
`robkin info` and a conversion to PoE load that alone. ``check`` confirms its verdict by FK at sample
configurations and ``convert`` measures every DH/MDH/Hayati table it writes against the robot's FK
(its near-parallel warnings state that error), so both load the FK module (~0.6 ms) with the batch kernels'
table (``robkin.compiled.chain.kernels``, ~0.3 ms, and its AVX2 build on a CPU that runs it, left out of the
lists below: ``test_kernels.py`` checks that choice); ``convert`` to a DH-type table also loads the frame
placement (``robkin.compiled.conversions.frames``), and nothing else."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "src" / "robkin" / "examples" / "rrpr.yaml"


def _loaded_after(statements: str) -> list[str]:
    # the extension modules only: not the sub-packages, nor the plain-Python constants beside the
    # kernels (compiled/scanners/vocabulary.py, compiled/conversions/tolerances.py), which load no code
    code = ("import sys, io, contextlib\n" + statements +
            "\nprint(sorted(m for m in sys.modules if m.startswith('robkin.compiled.')"
            " and not (getattr(sys.modules[m], '__file__', None) or '.py').endswith('.py')))")
    env = dict(os.environ, ROBKIN_PLAIN="1")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    loaded = eval(out.stdout.strip().splitlines()[-1])  # noqa: S307 - our own printed list
    return [m for m in loaded if m != "robkin.compiled.chain.kernels_avx2"]


def test_import_and_non_kinematic_commands_load_no_kinematics_module():
    def command(*argv: str) -> str:
        return ("from robkin.cli import main\n"
                f"with contextlib.redirect_stdout(io.StringIO()):\n    main({list(argv)!r})")

    assert _loaded_after("import robkin") == []
    assert _loaded_after(command("info", str(EXAMPLE))) == ["robkin.compiled.runtime.rigid"]
    assert _loaded_after(command("convert", str(EXAMPLE), "--to", "poe")) == ["robkin.compiled.runtime.rigid"]
    assert _loaded_after(command("convert", str(EXAMPLE), "--to", "dh")) == ["robkin.compiled.chain.fk",
                                                                              "robkin.compiled.chain.kernels",
                                                                              "robkin.compiled.conversions.frames",
                                                                              "robkin.compiled.runtime.rigid",
                                                                              "robkin.compiled.runtime.threads"]
    check = ("from robkin.cli import main\nwith contextlib.redirect_stdout(io.StringIO()):\n"
             f"    main(['check', {str(EXAMPLE)!r}, {str(EXAMPLE)!r}])")
    assert _loaded_after(check) == ["robkin.compiled.chain.fk", "robkin.compiled.chain.kernels", "robkin.compiled.runtime.rigid",
                                    "robkin.compiled.runtime.threads"]


def test_first_kinematics_call_loads_it():
    loaded = _loaded_after(f"import robkin\nrobkin.load({str(EXAMPLE)!r}).fk([0, 0, 0, 0])")
    assert loaded == ["robkin.compiled.chain.fk", "robkin.compiled.chain.kernels", "robkin.compiled.runtime.rigid",
                      "robkin.compiled.runtime.threads"]
