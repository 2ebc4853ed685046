"""Library errors in the caller's vocabulary (see ``robkin.messages``): ``overlay=`` / ``host=`` / ``port=`` /
``allow_xacro=True`` from Python, ``--overlay`` / ``--host`` / ``--port`` / ``--allow-xacro`` from the command
line."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

import robkin
from robkin.cli import main
from robkin.messages import render_options
from robkin.viz.assets import missing_assets

RRPR = Path(robkin.__file__).parent / "examples" / "rrpr.yaml"


def test_overlay_error_names_the_keyword_in_python():
    pytest.importorskip("matplotlib")
    from robkin.viz.plot import plot_robot

    with pytest.raises(robkin.InputError) as info:
        plot_robot(robkin.load(RRPR), overlay=["dh", "xyz"])
    message = str(info.value)
    assert "unknown representation 'xyz' in overlay=" in message and "--" not in message


def test_gui_host_error_names_the_keyword_in_python_and_the_flag_on_the_cli(capsys):
    from robkin.viz.gui import make_server

    with pytest.raises(robkin.InputError) as info:
        make_server(host="0.0.0.0", port=0)
    assert str(info.value).startswith("host='0.0.0.0': not a loopback address")
    assert main(["gui", "--host", "0.0.0.0", "--port", "0"]) == 2
    assert capsys.readouterr().err.startswith("robkin: error: --host '0.0.0.0': not a loopback address")


@pytest.mark.skipif(bool(missing_assets()), reason="three.js not installed (make assets)")
def test_gui_port_in_use_names_the_keyword_in_python_and_the_flag_on_the_cli(capsys):
    from robkin.viz.gui import make_server

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        with pytest.raises(robkin.InputError) as info:
            make_server(port=port)
        message = str(info.value)
        assert message.startswith(f"port={port}: cannot listen") and message.endswith("port=0")
        assert "--" not in message
        assert main(["gui", str(RRPR), "--port", str(port)]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"robkin: error: --port {port}: cannot listen") and err.endswith("--port 0")


def test_a_switch_turned_on_is_rendered_as_the_bare_flag():
    names = {"allow_xacro": "--allow-xacro", "tip_link": "--tip-link"}
    assert render_options("pass allow_xacro=True, or expand it", names) == "pass --allow-xacro, or expand it"
    # only the word True, and only for the names given
    assert render_options("allow_xacro=Truer; other=True", names) == "--allow-xacro Truer; other=True"


def test_xacro_refusal_names_the_keyword_in_python_and_the_flag_on_the_cli(tmp_path, capsys):
    xacro = tmp_path / "arm.xacro"
    xacro.write_text('<robot name="arm"><link name="base"/></robot>')
    with pytest.raises(robkin.InputError) as info:
        robkin.load(xacro)
    assert "pass allow_xacro=True or expand it" in str(info.value) and "--" not in str(info.value)
    assert main(["info", str(xacro)]) == 2
    err = capsys.readouterr().err
    assert "pass --allow-xacro or expand it" in err and "True" not in err
