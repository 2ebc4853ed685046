"""The release: one version everywhere, a clean public namespace, and ``make dist``'s check that a
wheel carries the GUI's three.js (.ci/check_dist.py)."""

from __future__ import annotations

import re
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

import robkin
from robkin.viz.assets import VENDOR

ROOT = Path(__file__).resolve().parent.parent


def test_one_version_everywhere(capsys):
    from robkin.cli import main

    version = re.search(r'^version = "([^"]+)"', (ROOT / "pyproject.toml").read_text(), re.M).group(1)
    assert robkin.__version__ == version
    with pytest.raises(SystemExit):
        main(["--version"])
    assert capsys.readouterr().out.strip() == f"robkin {version}"


def test_dir_shows_the_public_api_only():
    names = set(dir(robkin))
    assert {"os", "annotations", "TYPE_CHECKING", "lazy_exports"}.isdisjoint(names)
    assert set(robkin.__all__) <= names and "DHTable" in names  # lazy exports are listed too


def _fake_release(folder: Path, version: str, vendor: list[str]) -> None:
    with zipfile.ZipFile(folder / f"robkin-{version}-cp311-cp311-linux_x86_64.whl", "w") as z:
        z.writestr("robkin/compiled/chain/fk.cpython-311-x86_64-linux-gnu.so", b"")
        for name in vendor:
            z.writestr(f"robkin/viz/static/vendor/{name}", b"x")
    with tarfile.open(folder / f"robkin-{version}.tar.gz", "w:gz") as t:
        for name in vendor:
            path = folder / "f"
            path.write_bytes(b"x")
            t.add(path, arcname=f"robkin-{version}/src/robkin/viz/static/vendor/{name}")


@pytest.mark.parametrize("drop", [None, "three.module.js"])
def test_check_dist_refuses_a_release_without_three_js(tmp_path, drop):
    _fake_release(tmp_path, robkin.__version__, [n for n in VENDOR if n != drop])
    done = subprocess.run([sys.executable, str(ROOT / ".ci" / "check_dist.py"), str(tmp_path)],
                          capture_output=True, text=True, timeout=60)
    if drop is None:
        assert done.returncode == 0, done.stderr
    else:
        assert done.returncode == 1 and f"vendor/{drop} missing" in done.stderr
