"""The core commands in-process: convert, fk, demo, exit statuses, no half-written output."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from robkin.cli import main
from robkin.examples import EXAMPLES_DIR
from robkin.io.documents.reader import read_document

RRPR = str(EXAMPLES_DIR / "rrpr.yaml")
THREE_R = str(EXAMPLES_DIR / "arbitrary_3r.yaml")


def test_version_and_help(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out.startswith("robkin ")
    for cmd in ("convert", "fk", "demo"):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        assert "usage: robkin " + cmd in capsys.readouterr().out


def test_a_command_line_builds_only_its_command_the_same_parser():
    """``main`` builds only the named command's subparser (start-up time); it must be the very parser
    the full ``robkin`` parser holds for that command: the same options, defaults and help."""
    import argparse

    from robkin.cli import COMMANDS, build_parser

    def subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
        return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices

    full = subparsers(build_parser())
    assert list(full) == list(COMMANDS)
    for name in COMMANDS:
        one = subparsers(build_parser(name))
        assert list(one) == [name]
        assert one[name].format_help() == full[name].format_help()
        assert one[name].get_default("_run") is full[name].get_default("_run")


def test_fk_json_matches_library(capsys):
    assert main(["fk", RRPR, "--q", "3*pi/4,-pi/4,0.3,-3*pi/4", "--json"]) == 0
    T = np.array(json.loads(capsys.readouterr().out)["T"])
    expected = read_document(RRPR).fk([3 * math.pi / 4, -math.pi / 4, 0.3, -3 * math.pi / 4])
    np.testing.assert_allclose(T, expected, atol=1e-15)


def test_fk_accepts_negative_first_value(capsys):
    assert main(["fk", RRPR, "--q", "-0.5,0,0,0"]) == 0
    assert "position:" in capsys.readouterr().out


@pytest.mark.parametrize("fmt, needle", [("dh", "alpha"), ("mdh", "a(i-1)"), ("poe", "wx"),
                                         ("poe-body", "body frame"), ("rpy-xyz", "world->base"),
                                         ("gjd", "J5 (tool)")])
def test_convert_tables(capsys, fmt, needle):
    assert main(["convert", RRPR, "--to", fmt]) == 0
    assert needle in capsys.readouterr().out


def test_convert_paper_layout_shows_base_row(capsys):
    assert main(["convert", RRPR, "--to", "dh", "--layout", "paper"]) == 0
    assert "(base)" in capsys.readouterr().out


# The 3-decimal example is projected on every read (test_document checks those warnings once).
@pytest.mark.filterwarnings("ignore::robkin.ProjectionWarning")
@pytest.mark.parametrize("fmt", ["dh", "mdh", "poe", "poe-body", "rpy-xyz", "gjd", "json", "yaml"])
def test_convert_to_file_reads_back_same_robot(tmp_path, fmt):
    out = tmp_path / ("out.json" if fmt == "json" else "out.yaml")
    assert main(["convert", THREE_R, "--to", fmt, "-o", str(out)]) == 0
    original, back = read_document(THREE_R), read_document(out)
    Q = original.random_q(20, rng=3)
    np.testing.assert_allclose(back.fk(Q), original.fk(Q), atol=1e-12)


def test_convert_json_has_all_sections(capsys):
    assert main(["convert", RRPR, "--to", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"joints", "dh", "mdh", "poe", "poe_body", "rpy_xyz", "gjd"} <= set(doc)


def test_batch_convert(tmp_path):
    a = tmp_path / "a.yaml"
    a.write_text(open(RRPR).read())
    assert main(["convert", str(a), THREE_R, "--to", "yaml", "-o", str(tmp_path)]) == 0
    assert read_document(tmp_path / "arbitrary_3r.yaml").n == 3


def test_bad_input_exit_2_one_line_nothing_written(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("joints: [revolute]\ndh: {rows: [[0, 0, nan, 0]]}\n")
    out = tmp_path / "out.yaml"
    out.write_text("precious")
    assert main(["convert", str(bad), "--to", "dh", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bad.yaml" in err and "Traceback" not in err
    assert out.read_text() == "precious"


def test_batch_with_one_bad_input_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("joints: [revolute]\n")
    assert main(["convert", RRPR, str(bad), "--to", "yaml", "-o", str(tmp_path)]) == 2
    assert not (tmp_path / "rrpr.yaml").exists()
    assert "no representation section" in capsys.readouterr().err


def test_unwritable_output(tmp_path, capsys):
    assert main(["convert", RRPR, "--to", "dh", "-o", str(tmp_path / "missing" / "x.yaml")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert not any(name.endswith(".tmp") for name in os.listdir(tmp_path))


def test_wrong_q_count(capsys):
    assert main(["fk", RRPR, "--q", "1,2"]) == 2
    assert "4 joints, got 2" in capsys.readouterr().err


def test_usage_error_is_exit_2(capsys):
    with pytest.raises(SystemExit) as info:
        main(["convert", RRPR, "--to", "pdf"])
    assert info.value.code == 2


def test_demo_reports_agreement(capsys):
    assert main(["demo"]) == 0
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if ln.startswith("FK at q")]
    assert len(lines) == 2
    for ln in lines:
        assert float(ln.rsplit(" ", 1)[1]) < 1e-12


def test_batch_refuses_two_inputs_that_would_write_the_same_file(tmp_path, capsys):
    (tmp_path / "x").mkdir()
    for p in (tmp_path / "a.yaml", tmp_path / "x" / "a.yaml"):
        p.write_text(open(RRPR).read())
    out = tmp_path / "out"
    assert main(["convert", str(tmp_path / "a.yaml"), str(tmp_path / "x" / "a.yaml"), "--to", "yaml",
                 "-o", str(out) + "/"]) == 2
    assert "would write the same file(s)" in capsys.readouterr().err
    assert not out.exists()  # nothing written, not even the folder
