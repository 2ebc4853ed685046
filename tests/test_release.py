"""The release: one version everywhere, a clean public namespace, and ``make dist``'s check that a
wheel carries the GUI's three.js within its size and contents budget and that an sdist carries the
compiled core's sources (.ci/check_dist.py)."""

from __future__ import annotations

import os
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


CORE_SOURCES = sorted(str(p.relative_to(ROOT / "src")) for p in (ROOT / "src/robkin/compiled").rglob("*")
                      if p.suffix in (".pyx", ".pxd", ".pxi", ".h", ".pyi") and p.is_file())


GUI_FILES = sorted(p.name for p in (ROOT / "src/robkin/viz/static").iterdir() if p.is_file())


def _fake_release(folder: Path, version: str, vendor: list[str], wheel_extra: dict[str, bytes] | None = None,
                  sources: list[str] = CORE_SOURCES, gui: list[str] = GUI_FILES) -> None:
    with zipfile.ZipFile(folder / f"robkin-{version}-cp311-cp311-linux_x86_64.whl", "w") as z:
        z.writestr("robkin/compiled/chain/fk.cpython-311-x86_64-linux-gnu.so", b"")
        for name in vendor:
            z.writestr(f"robkin/viz/static/vendor/{name}", b"x")
        for name in gui:
            z.writestr(f"robkin/viz/static/{name}", b"x")
        for name, data in (wheel_extra or {}).items():
            z.writestr(name, data)
    with tarfile.open(folder / f"robkin-{version}.tar.gz", "w:gz") as t:
        path = folder / "f"
        path.write_bytes(b"x")
        for name in vendor:
            t.add(path, arcname=f"robkin-{version}/src/robkin/viz/static/vendor/{name}")
        for name in gui:
            t.add(path, arcname=f"robkin-{version}/src/robkin/viz/static/{name}")
        for name in sources:
            t.add(path, arcname=f"robkin-{version}/src/{name}")


def _check_dist(folder: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(ROOT / ".ci" / "check_dist.py"), str(folder)],
                          capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("drop", [None, "three.module.js"])
def test_check_dist_refuses_a_release_without_three_js(tmp_path, drop):
    _fake_release(tmp_path, robkin.__version__, [n for n in VENDOR if n != drop])
    done = _check_dist(tmp_path)
    if drop is None:
        assert done.returncode == 0, done.stderr
    else:
        assert done.returncode == 1 and f"vendor/{drop} missing" in done.stderr


def test_check_dist_refuses_a_wheel_without_the_gui_page(tmp_path):
    assert "index.html" in GUI_FILES
    _fake_release(tmp_path, robkin.__version__, VENDOR, gui=[n for n in GUI_FILES if n != "index.html"])
    done = _check_dist(tmp_path)
    assert done.returncode == 1 and "robkin/viz/static/index.html missing" in done.stderr


@pytest.mark.parametrize("byproduct", ["robkin/compiled/chain/fk.c", "robkin/compiled/ik/closed_form.html"])
def test_check_dist_refuses_a_wheel_with_build_byproducts(tmp_path, byproduct):
    _fake_release(tmp_path, robkin.__version__, VENDOR, wheel_extra={byproduct: b"/* generated */"})
    done = _check_dist(tmp_path)
    assert done.returncode == 1 and f"carries the build byproduct {byproduct}" in done.stderr


def test_check_dist_refuses_a_wheel_over_its_size_budget(tmp_path):
    # incompressible: 8 MB of random bytes stay 8 MB in the zip
    _fake_release(tmp_path, robkin.__version__, VENDOR,
                  wheel_extra={"robkin/compiled/chain/big.cpython-311-x86_64-linux-gnu.so": os.urandom(8_000_000)})
    done = _check_dist(tmp_path)
    assert done.returncode == 1 and "over the budget of 8 MB" in done.stderr


def test_check_dist_refuses_an_sdist_without_the_cython_sources(tmp_path):
    assert "robkin/compiled/chain/fk.pyx" in CORE_SOURCES
    _fake_release(tmp_path, robkin.__version__, VENDOR,
                  sources=[n for n in CORE_SOURCES if n != "robkin/compiled/chain/fk.pyx"])
    done = _check_dist(tmp_path)
    assert done.returncode == 1 and "src/robkin/compiled/chain/fk.pyx missing" in done.stderr
