"""Every command that draws degrades to one line and exit status 2 without its optional dependency.

The dependency is hidden the way a machine without it would see it: ``import matplotlib`` (and of any of
its submodules, even those this process has already imported) raises ImportError; the GUI's three.js is
"not installed" when its vendor folder is empty. Each command must say what is missing and how to get it,
in one line on stderr, exit 2, write nothing, and never print a traceback (issue 32, item 3:
``robkin estimate --plot`` printed a traceback and exited 1).
"""

from __future__ import annotations

import sys

import pytest

from robkin.cli import main
from robkin.examples import EXAMPLES_DIR

RRPR = EXAMPLES_DIR / "rrpr.yaml"
POSE = "-1,0.9,0.8,-3.08232,-1.04169,-3.01168"


@pytest.fixture
def no_matplotlib(monkeypatch):
    """``import matplotlib`` and ``from matplotlib.x import y`` raise ImportError, as if not installed."""
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.setitem(sys.modules, name, None)   # None in sys.modules: the import raises ImportError
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError):
        from matplotlib.figure import Figure  # noqa: F401 - the hiding itself, checked
    yield


@pytest.fixture
def no_threejs(monkeypatch, tmp_path):
    """The GUI's three.js modules not installed: an empty vendor folder."""
    import robkin.viz.assets as assets

    monkeypatch.setattr(assets, "VENDOR_DIR", tmp_path / "empty_vendor")
    assert assets.missing_assets()
    yield


def _one_line(err: str, *words: str) -> None:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    for w in words:
        assert w in lines[0], lines[0]


def test_estimate_plot_without_matplotlib(no_matplotlib, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = main(["estimate", "--pose", POSE, "--joints", "4", "--type", "all", "-o", "results",
                 "--plot", "cmp.png"])
    _one_line(capsys.readouterr().err, "--plot", "matplotlib", "robkin[plot]")
    assert code == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == []   # neither the estimates nor the picture


@pytest.mark.parametrize("suffix", [".png", ".svg", ".pdf"])
def test_plot_picture_without_matplotlib(no_matplotlib, tmp_path, capsys, suffix):
    out = tmp_path / f"rrpr{suffix}"
    code = main(["plot", str(RRPR), "--q", "0.1,0.2,0.3,0.4", "-o", str(out)])
    _one_line(capsys.readouterr().err, "matplotlib", "robkin[plot]")
    assert code == 2 and not out.exists()


def test_plot_metrics_without_matplotlib(no_matplotlib, tmp_path, monkeypatch, capsys):
    pytest.importorskip("yaml")
    monkeypatch.chdir(tmp_path)
    # estimation results to draw, made while matplotlib is hidden (writing them needs no matplotlib)
    assert main(["estimate", "--pose", POSE, "--joints", "4", "--type", "all", "-o", "est"]) == 0
    capsys.readouterr()
    code = main(["plot", "--metrics", *(f"est/estimate_{k}.yaml" for k in "ABCD"), "-o", "metrics.png"])
    _one_line(capsys.readouterr().err, "matplotlib", "robkin[plot]")
    assert code == 2 and not (tmp_path / "metrics.png").exists()


def test_plot_page_without_threejs(no_threejs, tmp_path, capsys):
    out = tmp_path / "rrpr.html"
    code = main(["plot", str(RRPR), "-o", str(out)])
    _one_line(capsys.readouterr().err, "three.js", "make assets")
    assert code == 2 and not out.exists()


def test_gui_without_threejs(no_threejs, capsys):
    # refused before it serves (were it to serve, this call would not return)
    code = main(["gui", str(RRPR), "--port", "0"])
    _one_line(capsys.readouterr().err, "three.js", "make assets")
    assert code == 2


def test_html_plot_needs_no_matplotlib(no_matplotlib, tmp_path, capsys):
    """The 3D page is three.js, not matplotlib: it is drawn with matplotlib hidden (when three.js is there)."""
    from robkin.viz.assets import missing_assets

    if missing_assets():
        pytest.skip("three.js is not installed (make assets)")
    out = tmp_path / "rrpr.html"
    assert main(["plot", str(RRPR), "-o", str(out)]) == 0
    assert out.stat().st_size > 1000
