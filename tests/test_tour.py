"""The README's tour runs as printed in the environment ``make demo`` makes (issue 32, item 1).

``tests/test_examples.py`` runs the tour's commands in the test suite's own environment, which has every
optional dependency; this test makes a fresh venv the way ``make demo`` does and runs the tour there, as a
user would right after ``make demo``, so a command that needs something ``make demo`` does not install
fails here. What goes into the venv is read from the repository, not copied: the ``demo`` target's
prerequisites in the Makefile, the extras their rules install (``$(EXTRA) NAME``) and the plain packages
they install (``$(PIP) install NAME``), with pyproject.toml's dependencies and those extras' lists. robkin
itself is the source tree under test, put on the venv's path with a ``.pth`` file, which is what the
Makefile's ``pip install -e .`` leaves (setuptools' editable install is that same ``.pth``; the compiled core
is already built beside the sources), and a ``robkin`` script as pip writes one.

``robkin demo`` runs first, as ``make demo`` ends with it. The shell lines are README.md's first ``sh``
block with ``robkin convert`` (the tour), run by bash with
``set -e`` from a folder holding the venv as ``.venv`` (the tour starts with ``source .venv/bin/activate``).
``robkin gui`` serves until stopped: the line runs with ``--port 0`` added and ``BROWSER=true`` (``--open``
opens nothing), is checked to serve its page, then stopped. The README's Python block then runs in the
tour's folder with the venv's python.

Cost: pip installs the packages (from pip's cache after the first run: ~1 min, most of it unpacking
example-robot-data's 414 MB) and the tour runs (~1 min). Without a network, pip cannot install and the test
is skipped, unless ``ROBKIN_REQUIRE_TOUR=1`` (``.ci/run`` sets it), which makes that a failure.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import robkin

ROOT = Path(__file__).resolve().parent.parent
BASH = shutil.which("bash")
#: pip's messages when the package index cannot be reached (then: skip, unless required)
OFFLINE = ("Failed to establish a new connection", "Temporary failure in name resolution", "NewConnectionError",
           "Network is unreachable", "ProxyError", "Could not fetch URL")

pytestmark = pytest.mark.skipif(BASH is None or sys.platform == "win32", reason="the tour is a bash session")


def demo_requirements() -> list[str]:
    """What ``make demo`` installs besides robkin: pyproject's dependencies, the extras the demo target's
    prerequisites install and the packages they install by name."""
    tomllib = pytest.importorskip("tomllib")     # Python >= 3.11
    makefile = (ROOT / "Makefile").read_text()
    prereqs = re.search(r"^demo:(.*)$", makefile, re.M)
    assert prereqs, "Makefile: no demo target"
    extras: list[str] = []
    plain: list[str] = []
    for target in prereqs.group(1).split():
        rule = re.search(rf"^{re.escape(target)}:.*\n((?:\t.*\n)*)", makefile, re.M)
        if rule:
            extras += re.findall(r"\$\(EXTRA\) ([\w-]+)", rule.group(1))
            plain += re.findall(r"\$\(PIP\) install ([A-Za-z][\w.\-\[\]<>=,']*)\s*$", rule.group(1), re.M)
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert extras, "Makefile: the demo target installs no extra"
    requirements = list(project["dependencies"]) + plain
    for extra in extras:
        requirements += project["optional-dependencies"][extra]
    return sorted(set(requirements))


def tour_lines() -> list[str]:
    text = (ROOT / "README.md").read_text()
    tour = next(b for b in re.findall(r"```sh\n(.*?)```", text, flags=re.S) if "robkin convert" in b)
    return tour.splitlines()


def readme_python() -> str:
    text = (ROOT / "README.md").read_text()
    return next(b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S) if "robkin.load" in b)


def _skip_or_fail(reason: str) -> None:
    if os.environ.get("ROBKIN_REQUIRE_TOUR") == "1":
        pytest.fail(f"ROBKIN_REQUIRE_TOUR=1 but {reason}")
    pytest.skip(reason)


#: bash run before the tour: `robkin gui` (it serves until stopped) gets a free port, opens no browser,
#: must serve its page, and is then stopped
GUI_WRAPPER = r"""
robkin() {
  if [ "${1:-}" = gui ]; then
    local log="$TOUR_GUI_LOG" pid url i
    BROWSER=true command robkin "$@" --port 0 >"$log" 2>&1 &
    pid=$!
    for i in $(seq 1 240); do
      grep -q "serving on" "$log" && break
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.5
    done
    if ! grep -q "serving on" "$log"; then cat "$log" >&2; kill "$pid" 2>/dev/null; return 1; fi
    url=$(grep -o "http://[^ ]*" "$log" | head -n 1)
    python -c "import sys, urllib.request; assert b'<html' in urllib.request.urlopen(sys.argv[1], timeout=30).read().lower()" "$url" \
      || { kill "$pid"; return 1; }
    kill "$pid"; wait "$pid" 2>/dev/null || true     # stopped by this kill: its status is 143
    return 0
  fi
  command robkin "$@"
}
trap 'echo "tour: this line failed: $BASH_COMMAND" >&2' ERR
set -eo pipefail
"""


def test_readme_tour_runs_in_the_venv_make_demo_makes(tmp_path):
    requirements = demo_requirements()
    work = tmp_path / "repo"          # plays the repository: the tour's venv is ./.venv
    (work / "tmp").mkdir(parents=True)
    venv = work / ".venv"
    try:
        _make_venv(venv, requirements)
        env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV", "ROBKIN_"))}
        env.update(TMPDIR=str(work / "tmp"), TOUR_GUI_LOG=str(tmp_path / "gui.log"), MPLBACKEND="Agg",
                   HOME=str(tmp_path / "home"), MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
        # after the tour, the folder it ended in (its `cd "$(mktemp -d)"`)
        # what `make demo` itself runs last, then the tour
        script = GUI_WRAPPER + ".venv/bin/robkin demo > /dev/null\n" + "\n".join(tour_lines()) + \
            f'\npwd > "{tmp_path / "tour_dir"}"\n'
        done = subprocess.run([BASH, "-c", script], cwd=work, env=env, capture_output=True, text=True, timeout=1800)
        assert done.returncode == 0, f"the tour failed after make demo:\n{done.stderr[-4000:]}"
        tour = Path((tmp_path / "tour_dir").read_text().strip())
        assert tour.parent == work / "tmp"      # it worked in its own scratch folder
        assert (tour / "cmp.png").stat().st_size > 0 and (tour / "rrpr.png").stat().st_size > 0
        assert any((tour / "ur5_mjcf" / "meshes").glob("*.stl"))
        # the README's Python, in the tour's folder (ur5.urdf and panda.urdf are there), with the venv's python
        (tmp_path / "readme.py").write_text(readme_python())
        py = subprocess.run([str(venv / "bin" / "python"), str(tmp_path / "readme.py")], cwd=tour, env=env,
                            capture_output=True, text=True, timeout=900)
        assert py.returncode == 0, f"the README's Python failed after make demo:\n{py.stderr[-4000:]}"
        assert "verdict: different robots" in py.stdout
    finally:
        shutil.rmtree(venv, ignore_errors=True)     # ~0.6 GB: not left to pytest's kept temporary folders


def _make_venv(venv: Path, requirements: list[str]) -> None:
    """A venv with the requirements (pip, as the Makefile runs it: its cache is used) and robkin from the
    tree under test, as the Makefile's editable install leaves it."""
    base = getattr(sys, "_base_executable", sys.executable)     # the interpreter the compiled core is built for
    subprocess.run([base, "-m", "venv", str(venv)], check=True, capture_output=True)
    python = venv / "bin" / "python"
    pip = subprocess.run([str(python), "-m", "pip", "--disable-pip-version-check", "-q", "install", *requirements],
                         capture_output=True, text=True, timeout=1800)
    if pip.returncode != 0:
        if any(s in pip.stderr for s in OFFLINE):
            _skip_or_fail("pip cannot reach the package index: " + pip.stderr.strip().splitlines()[-1])
        pytest.fail(f"pip install {' '.join(requirements)} failed:\n{pip.stderr[-3000:]}")
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                          check=True, capture_output=True, text=True).stdout.strip()
    source = Path(robkin.__file__).resolve().parent.parent   # the tree under test (src/, core built in place)
    Path(site, "__editable__.robkin.pth").write_text(f"{source}\n")
    script = venv / "bin" / "robkin"
    script.write_text(f"#!{python}\nimport sys\nfrom robkin.cli import main\nsys.exit(main())\n")
    script.chmod(0o755)
    # nothing of the test's own environment leaks in: robkin's optional dependencies are what pip installed
    check = subprocess.run([str(python), "-c", "import robkin, sys; print(robkin.__file__)"],
                           capture_output=True, text=True, env={"PATH": os.environ.get("PATH", "")})
    assert check.returncode == 0 and str(source) in check.stdout, check.stderr
