"""Every page's examples run as printed (issue 32, item 9): the command blocks (```sh, ```bash, and the
``$ `` lines of ```console blocks) and the ```python blocks of every ``docs/**/*.md`` page, in the order the
page prints them, in one folder per page that holds the files a reader has at that point: the kit of
tests/test_examples.py (the bundled robots, the UR5 and Panda URDFs copied from example-robot-data as
docs/getting-started.md copies them, files made from them). One test per page.

A page is a session: its shell variables (``R=...``) and its folder carry from one command block to the
next, its Python blocks share one namespace (a later block uses the ``robot`` an earlier one loaded), and a
file one block writes is there for the next. ``robkin`` commands run in-process through
``robkin.cli.main``; a line bash must run (a heredoc, a loop, a redirection, ``python -m ...``) runs in bash
with a ``robkin`` on its PATH that is the robkin under test. ``robkin gui`` is only parsed and its input
loaded (it serves until stopped).

What does not run is listed in ``NOT_RUN`` below, each entry with its reason; a command expected to exit
non-zero is in ``EXIT_STATUS``. An entry that matches nothing fails the test (the lists cannot go stale).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from test_examples import BASH, ROBOTS_DIR, ROOT, _argv, _env, kit, run_example, workdir  # noqa: F401 - fixtures

import robkin
from robkin.cli import main

DOCS = ROOT / "docs"
PAGES = sorted(str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md"))
pytestmark = pytest.mark.skipif(BASH is None, reason="bash is needed to run the examples as a shell does")

#: (page, text a command or Python block starts with) -> why it does not run here. A command is one
#: shell command of a block (continuation lines joined); a Python block is matched by its first line.
NOT_RUN: dict[tuple[str, str], str] = {
    # the reader's set-up, not an example: make builds and tests everything, pip needs the network
    ("getting-started.md", "make "): "the set-up itself (make demo/test/docs/dist: builds, the network)",
    ("getting-started.md", "pip install"): "installs the wheel make dist built (another venv, the network)",
    ("simulation.md", "pip install"): "the network",
    # interactive windows: they run until the reader closes them
    ("mjcf.md", "python -m mujoco.viewer"): "an interactive window",
    ("simulation.md", "python -m mujoco.viewer"): "an interactive window",
    # files and folders the reader supplies (the page names them as stand-ins for the reader's own)
    ("meshes.md", "robkin gui ur5.urdf --tip-link tool0 --package-path ur_description=~/ws"):
        "a ROS workspace of the reader's (~/ws/src/ur_description)",
    ("meshes.md", "robkin plot ur5.urdf --tip-link tool0 --package-path ur_description=~/ws"):
        "a ROS workspace of the reader's (~/ws/src/ur_description)",
    ("robot-files.md", "robkin convert panda.xml"): "robosuite's MJCF Panda (robosuite is not installed)",
    ("robot-files.md", "robkin fk ur5e.xml"): "robosuite's MJCF UR5e (robosuite is not installed)",
    ("robot-files.md", "robkin check arm.sdf arm.urdf"): "the reader's SDF/URDF pair",
    ("lint.md", "robkin lint arm.urdf"): "the reader's faulty arm.urdf (tests/test_lint.py builds its defects)",
    ("synthesis.md", "robkin estimate --pose P1 --pose P2 --pose P3"): "P1-P3 stand for the reader's poses",
    ("synthesis.md", "from robkin.synthesis.sweep import"):
        "800 optimiser runs (minutes of CPU) and a Dask cluster at the reader's address (the network)",
}

#: (page, text a command starts with) -> the exit status the page says it has
EXIT_STATUS: dict[tuple[str, str], int] = {
    # check's 1: the nominal model is not the measured robot (the page shows the verdict, then calibrates)
    ("calibration.md", "robkin check ur5.urdf measurements.csv"): 1,
    ("calibration.md", "robkin check ur5.urdf cycles.csv"): 1,
}


def _blocks(page: str) -> list[tuple[str, int, str]]:
    """(kind, line number, text) of every runnable fenced block, in page order."""
    text = (DOCS / page).read_text()
    out = []
    for m in re.finditer(r"^```(sh|bash|console|python)[ \t]*\n(.*?)^```", text, flags=re.S | re.M):
        out.append((m.group(1), text.count("\n", 0, m.start()) + 2, m.group(2)))
    return out


def _complete(chunk: str) -> bool:
    """Whether bash reads ``chunk`` as whole commands (a heredoc, a loop or a quote may span lines)."""
    if chunk.rstrip().endswith("\\"):
        return False
    if not re.search(r"<<|^\s*(for|while|until|if|case)\b|['\"(]", chunk, flags=re.M):
        return True
    return subprocess.run([BASH, "-n"], input=chunk, capture_output=True, text=True).returncode == 0


def shell_commands(kind: str, text: str) -> list[str]:
    """The commands of a shell block: continuation lines joined, a heredoc or loop kept whole; of a
    console block only the lines a prompt starts (``$ `` or ``robkin``), the rest being output."""
    lines = text.splitlines()
    if kind == "console":
        keep, cont = [], False
        for line in lines:
            if cont or line.startswith(("$ ", "robkin ")):
                keep.append(line[2:] if line.startswith("$ ") else line)
                cont = line.rstrip().endswith("\\")
        lines = keep
    out, chunk, heredoc = [], "", None
    for line in lines:
        if not chunk and (not line.strip() or line.lstrip().startswith("#")):
            continue
        chunk += line + "\n"
        if heredoc is None and (m := re.search(r"<<-?\s*['\"]?(\w+)['\"]?", line)):
            heredoc = m.group(1)            # the document runs to its delimiter line
            continue
        if heredoc is not None:
            if line.strip() != heredoc:
                continue
            heredoc = None
        if _complete(chunk):
            out.append(re.sub(r"[ \t]*\\\n\s*", " ", chunk).strip() if "<<" not in chunk else chunk.strip())
            chunk = ""
    assert not chunk, f"an unfinished command: {chunk}"
    return out


def _listed(table: dict, page: str, text: str, used: set | None = None):
    """The entry of ``table`` for a command or block of ``page`` (None if none), noted in ``used``."""
    for (p, start), value in table.items():
        if p == page and text.lstrip().startswith(start):
            if used is not None:
                used.add((p, start))
            return value
    return None


def _in_bash(command: str, env: dict[str, str], bin_dir: Path) -> tuple[int, str]:
    """Run ``command`` in bash (the robkin under test on its PATH); keep its variables and folder.
    Returns the exit status and what it wrote to stderr."""
    dump = bin_dir / "env.out"
    script = f"set -a\n{command}\nstatus=$?\nenv -0 > {dump}\nexit $status"
    run_env = _env(env)
    run_env["PATH"] = str(bin_dir) + os.pathsep + run_env["PATH"]
    done = subprocess.run([BASH, "-c", script], env=run_env, capture_output=True, text=True)
    if dump.is_file():
        after = dict(item.split("=", 1) for item in dump.read_text().split("\0") if "=" in item)
        for name, value in after.items():
            if name not in ("PATH", "PYTHONPATH", "PWD", "OLDPWD", "SHLVL", "_") and run_env.get(name) != value:
                env[name] = value
        os.chdir(after.get("PWD", os.getcwd()))   # the workdir fixture's monkeypatch restores the folder
        dump.unlink()
    return done.returncode, done.stderr


def _simple_robkin(command: str) -> bool:
    """A 'robkin ...' command the in-process runner handles (no redirection, heredoc or command list)."""
    return command.startswith("robkin ") and not re.search(r"[<>;&`]|\$\(", command.split(" | ")[0])


def _robkin_shim(folder: Path) -> Path:
    bin_dir = folder / ".bin"
    bin_dir.mkdir(exist_ok=True)
    shim = bin_dir / "robkin"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -c "import sys; from robkin.cli import main; '
                    f'sys.exit(main())" "$@"\n')
    shim.chmod(0o755)
    return bin_dir




@pytest.fixture
def page_dir(workdir, monkeypatch):
    """The kit as a reader has it: no ROS package path (meshes come from the --package-path a page
    gives), and the files the pages name that example-robot-data ships under other names."""
    for name in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        monkeypatch.delenv(name, raising=False)
    shutil.copy("ur5.urdf", "ur5_robot.urdf")            # example-robot-data's own name of the UR5
    talos = Path(ROBOTS_DIR) / "talos_data" / "robots" / "talos_reduced.urdf"
    if talos.is_file():
        shutil.copy(talos, "talos.urdf")
    ur5 = robkin.load("ur5.urdf", tip_link="tool0")
    np.save("targets.npy", ur5.fk(ur5.random_q(5, rng=0)))   # (N, 4, 4) tool poses
    return workdir


@pytest.mark.parametrize("page", PAGES)
def test_page_examples_run_as_printed(page, page_dir, capsys):
    blocks = _blocks(page)
    if not blocks:
        pytest.skip(f"{page} has no command or Python blocks")
    bin_dir = _robkin_shim(Path(page_dir).parent)
    env: dict[str, str] = {}
    namespace: dict[str, object] = {"__name__": "__docs__"}
    failures = []
    for kind, line, text in blocks:
        if kind == "python":
            if _listed(NOT_RUN, page, text) is None:
                try:
                    exec(compile(text, f"{page}:{line}", "exec"), namespace)   # noqa: S102 - the page's example
                except Exception as exc:   # noqa: BLE001 - report every block, not only the first
                    failures.append(f"{page}:{line} [python] {type(exc).__name__}: {exc}")
            continue
        for command in shell_commands(kind, text):
            if _listed(NOT_RUN, page, command) is not None:
                continue
            expected = _listed(EXIT_STATUS, page, command) or 0
            capsys.readouterr()
            try:
                if not _simple_robkin(command):
                    status, err = _in_bash(command, env, bin_dir)
                elif expected == 0:
                    run_example(command, env)          # 'robkin gui' parsed and its input loaded only
                    status, err = 0, ""
                else:
                    status, err = main(_argv(command.split(" | ")[0], env)[1:]), capsys.readouterr().err
            except SystemExit as exc:                # argparse's refusal
                status, err = exc.code, capsys.readouterr().err
            except Exception as exc:   # noqa: BLE001 - report every command
                status, err = None, f"{type(exc).__name__}: {exc}\n{capsys.readouterr().err}"
            if status != expected:
                failures.append(f"{page}:{line} {command[:120]!r}: exit {status}, expected {expected}\n"
                                f"    {err.strip()[-400:]}")
    capsys.readouterr()
    assert not failures, "examples that do not run as printed:\n" + "\n".join(failures)


def test_every_not_run_entry_names_a_block():
    """Every entry of NOT_RUN and EXIT_STATUS names a command or block its page has (none goes stale)."""
    wanted, used = set(NOT_RUN) | set(EXIT_STATUS), set()
    for page in {p for p, _ in wanted}:
        for kind, _, text in _blocks(page):
            items = [text] if kind == "python" else shell_commands(kind, text)
            for item in items:
                _listed(NOT_RUN, page, item, used)
                _listed(EXIT_STATUS, page, item, used)
    assert wanted <= used, f"entries that match no block: {sorted(wanted - used)}"


def test_blocks_are_read_as_a_shell_reads_them():
    """Console output is not run, continuation lines join, a heredoc and a loop stay whole."""
    console = "$ robkin fk a.yaml \\\n      --q 0,0\nIK solutions\n1  0.5\nrobkin info a.yaml\n"
    assert shell_commands("console", console) == ["robkin fk a.yaml --q 0,0", "robkin info a.yaml"]
    sh = ("# a comment\nX=1\npython - <<'EOF'\nprint('a \\\\')\nEOF\nfor i in 1 2; do\n  echo $i\ndone\n"
          "robkin convert a.yaml \\\n    --to dh   # 'quoted; comment'\n")
    assert shell_commands("sh", sh) == ["X=1", "python - <<'EOF'\nprint('a \\\\')\nEOF",
                                        "for i in 1 2; do\n  echo $i\ndone",
                                        "robkin convert a.yaml --to dh   # 'quoted; comment'"]
    blocks = [b for page in PAGES for b in _blocks(page)]
    commands = [c for kind, _, text in blocks if kind != "python" for c in shell_commands(kind, text)]
    # the pages' examples are found (a fence the pattern missed would silently run nothing)
    assert sum(kind == "python" for kind, _, _ in blocks) >= 25 and len(commands) >= 100
