"""The "nothing written" half of the bad-input promise: output files appear whole or not at all, even
when a signal arrives mid-write or a later file of a batch fails, and standard output on a full disk
or a closed pipe gives one line instead of a traceback."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from robkin.cli import main
from robkin.examples import EXAMPLES_DIR
from robkin.errors import InputError
from robkin.io.files import atomic

RRPR = str(EXAMPLES_DIR / "rrpr.yaml")
SRC = str(Path(atomic.__file__).resolve().parents[2])


CLI = "import sys; from robkin.cli import main; sys.exit(main())"
ENV = {**os.environ, "PYTHONPATH": SRC}


def _run(code: str, args: list[str] = (), stdout: object = subprocess.PIPE) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code, *args], stdout=stdout, stderr=subprocess.PIPE, text=True,
                          env=ENV, timeout=120)


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT", "SIGHUP"])
def test_a_signal_between_write_and_rename_leaves_no_temporary_file(tmp_path, sig):
    target = tmp_path / "out.yaml"
    target.write_text("precious")
    code = f"""
import os, signal, time
from robkin.io.files.atomic import atomic_file
# the disposition a process started from a terminal has: under nohup (SIGHUP) or as a background job
# without job control (SIGINT) the signal arrives ignored, and atomic_file rightly leaves an ignored
# signal ignored (the process would not die)
if signal.getsignal(signal.{sig}) == signal.SIG_IGN:
    signal.signal(signal.{sig}, signal.default_int_handler if signal.{sig} == signal.SIGINT else signal.SIG_DFL)
with atomic_file({str(target)!r}) as fh:
    fh.write("half of a document")
    os.kill(os.getpid(), signal.{sig})
    time.sleep(5)  # the signal arrives here, before the rename
    fh.write(" and the rest")
"""
    proc = _run(code)
    assert proc.returncode != 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.yaml"]  # no hidden .out.yaml.*.tmp
    assert target.read_text() == "precious"


def test_a_batch_whose_later_file_fails_writes_nothing(tmp_path, monkeypatch):
    (tmp_path / "a.yaml").write_text("precious")
    opened = []
    real_open = atomic._open

    def failing_open(fd, binary):
        opened.append(fd)
        if len(opened) == 2:
            os.close(fd)
            raise OSError(errno.ENOSPC, "No space left on device")
        return real_open(fd, binary)

    monkeypatch.setattr(atomic, "_open", failing_open)
    with pytest.raises(InputError, match=r"b.yaml: cannot write \(No space left on device\); no file was written"):
        atomic.write_texts_atomic([(tmp_path / "a.yaml", "new a"), (tmp_path / "b.yaml", "new b")])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.yaml"]
    assert (tmp_path / "a.yaml").read_text() == "precious"


def test_signal_handlers_are_restored_after_writing(tmp_path):
    before = signal.getsignal(signal.SIGTERM)
    atomic.write_text_atomic(tmp_path / "x.yaml", "x")
    assert signal.getsignal(signal.SIGTERM) is before


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("argv", [["convert", RRPR, "--to", "json"], ["convert", RRPR, "--to", "dh"],
                                  ["fk", RRPR, "--q", "0,0,0,0", "--json"]])
def test_standard_output_on_a_full_disk_is_one_line(argv):
    with open("/dev/full", "w") as full:
        proc = _run(CLI, stdout=full, args=argv)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr == "robkin: error: cannot write to standard output (No space left on device)\n"


def test_a_closed_pipe_stops_quietly():
    proc = subprocess.Popen([sys.executable, "-c", CLI, "convert", RRPR, "--to", "json"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=ENV)
    proc.stdout.close()  # the reader goes away before robkin writes
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 0 and err == "", err


@pytest.mark.parametrize("argv", [["ik", RRPR, "--pose", "0.5,0,0.5,0,0,0", "--seed", "-1"],
                                  ["estimate", "--pose", "0.5,0,0.5,0,0,0", "--joints", "3", "--seed=-5"],
                                  ["ik", RRPR, "--pose", "0.5,0,0.5,0,0,0", "--seed", "99999999999999999999999"]])
def test_a_seed_out_of_range_is_a_usage_error(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and len(err.splitlines()) == 1 and "--seed" in err and "is not a seed" in err, err
