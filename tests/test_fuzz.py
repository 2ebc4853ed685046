"""Fuzzing the readers: whatever the bytes, the robot document and URDF readers either return a valid
Robot or raise InputError with a one-line message. Any other exception (or a RuntimeWarning, which the
test configuration turns into an error) is a bug.

Two kinds of input: mutations of valid files (byte flips, truncation, splices of fragments that
commonly break parsers) and structurally generated URDF trees with random attributes. Example counts
are kept modest so the suite stays fast; the seeds vary from run to run (hypothesis' database keeps
any failure for replay).
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robkin.examples import EXAMPLES_DIR
from robkin.errors import InputError, unprintable
from robkin.io.documents.reader import parse_document
from robkin.io.urdf import parse_urdf_text, robot_from_model
from robkin.robot import Robot
from test_bad_inputs import ALIAS_BOMB, BOMB
from test_urdf import TILTED_SILENT

#: ROBKIN_FUZZ_EXAMPLES=5000 for a longer hunt; 150 keeps the suite fast (~1 s per test)
FUZZ = settings(max_examples=int(os.environ.get("ROBKIN_FUZZ_EXAMPLES", "150")), deadline=None,
                suppress_health_check=[HealthCheck.too_slow])

SEEDS_YAML = [(EXAMPLES_DIR / name).read_text() for name in ("rrpr.yaml", "arbitrary_3r.yaml")]
SEED_URDF = TILTED_SILENT()
#: Fragments that tend to break parsers and validators when spliced in anywhere.
NASTY = ["nan", "-inf", "1e400", "1e-400", "[", "]", "{", "}", ":", "- ", "&a", "*a", "!!python/object:os.system",
         "\x00", "\ufeff", "<", ">", "&lt;", "&amp;", "<!DOCTYPE r [<!ENTITY e 'x'>]>", "&e;", "]]>", "<![CDATA[",
         '"', "'", "0 0 0", "1 2", "revolute", "prismatic", "floating", "mimic", "-1e300", "  ", "\n", "\t",
         "pi/0", "1/0", "0x10", "1_000", "9" * 400, "9" * 5000, "&a [1, 2]", "*a", "*b", "<<: *a", "\x1b[31m",
         "\\ud800", "\\u202e", "&#10;", "&#0;", "9**9**9", "'1e300*1e300'", "1e100", "-1e101"]


def _mutate(text: str, data) -> str:
    ops = data.draw(st.lists(st.sampled_from(["flip", "cut", "splice", "dup", "delete"]), min_size=1, max_size=4))
    for op in ops:
        if not text:
            break
        i = data.draw(st.integers(0, len(text) - 1))
        if op == "flip":
            text = text[:i] + chr(data.draw(st.integers(0, 0x7F))) + text[i + 1:]
        elif op == "cut":
            text = text[:i]
        elif op == "splice":
            text = text[:i] + data.draw(st.sampled_from(NASTY)) + text[i:]
        elif op == "dup":
            j = data.draw(st.integers(i, min(len(text), i + 200)))
            text = text[:j] + text[i:j] + text[j:]
        else:
            j = data.draw(st.integers(i, min(len(text), i + 50)))
            text = text[:i] + text[j:]
    return text


def _reads_or_input_error(read) -> Robot | None:
    try:
        robot = read()
    except InputError as exc:
        msg = str(exc)
        assert msg and "\n" not in msg.strip(), f"multi-line message: {msg!r}"
        return None
    assert isinstance(robot, Robot)
    assert np.all(np.isfinite(robot.frames)) and np.all(np.isfinite(robot.world))
    return robot


@pytest.mark.filterwarnings("ignore::robkin.ProjectionWarning")  # near-valid mutations are projected
@FUZZ
@given(st.data(), st.sampled_from(range(len(SEEDS_YAML))), st.sampled_from(["yaml", "json"]))
def test_document_reader_fuzz(data, seed_index, fmt):
    text = SEEDS_YAML[seed_index]
    if fmt == "json":
        import json

        import yaml

        text = json.dumps(yaml.safe_load(text))
    text = _mutate(text, data)
    _reads_or_input_error(lambda: parse_document(text, fmt, source="fuzz." + fmt))


@FUZZ
@given(st.data())
def test_urdf_reader_fuzz_mutations(data):
    text = _mutate(SEED_URDF, data)
    _reads_or_input_error(lambda: robot_from_model(parse_urdf_text(text, "fuzz.urdf")))


_names = st.sampled_from(["a", "b", "c", "d", "e", "world", ""])
_num = st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr),
                 st.sampled_from(["0", "1", "-1", "x", "", "1e999", "3.14159"]))
_triple = st.one_of(st.lists(_num, min_size=0, max_size=4).map(" ".join), st.none())


@st.composite
def urdf_trees(draw) -> str:
    links = draw(st.lists(_names, min_size=0, max_size=5))
    parts = [f'<link name="{n}"/>' for n in links]
    for k in range(draw(st.integers(0, 5))):
        jtype = draw(st.sampled_from(["revolute", "continuous", "prismatic", "fixed", "floating", "planar",
                                      "ball", ""]))
        body = [f'<parent link="{draw(_names)}"/>', f'<child link="{draw(_names)}"/>']
        for tag, attr in (("origin", "xyz"), ("origin", "rpy"), ("axis", "xyz")):
            value = draw(_triple)
            if value is not None:
                body.append(f'<{tag} {attr}="{value}"/>')
        if draw(st.booleans()):
            body.append(f'<limit lower="{draw(_num)}" upper="{draw(_num)}" effort="1" velocity="1"/>')
        if draw(st.booleans()) and k:
            body.append('<mimic joint="j0"/>')
        parts.append(f'<joint name="j{k}" type="{jtype}">{"".join(body)}</joint>')
    return f'<robot name="fuzz">{"".join(parts)}</robot>'


@FUZZ
@given(urdf_trees(), st.one_of(st.none(), _names), st.one_of(st.none(), _names))
def test_urdf_reader_fuzz_trees(text, base, tip):
    _reads_or_input_error(lambda: robot_from_model(parse_urdf_text(text, "tree.urdf"), base or None, tip or None))


@FUZZ
@given(st.text(max_size=12), st.sampled_from(["yaml", "json"]))
def test_any_joint_name_reads_back_or_is_refused(name, fmt):
    # Names end up in terminals, messages and written URDF/MJCF: whatever the text, it is either
    # refused on input with one line, or read back as exactly the name given, which is printable.
    import json

    import yaml

    doc = {"robkin": 1, "name": name, "joints": [{"name": name, "type": "revolute"}],
           "dh": {"rows": [[0, 0.1, 0, 0]]}}
    text = json.dumps(doc) if fmt == "json" else yaml.safe_dump(doc, allow_unicode=True)
    given = (json.loads if fmt == "json" else yaml.safe_load)(text)["name"]  # YAML folds e.g. U+0085 to ' '
    robot = _reads_or_input_error(lambda: parse_document(text, fmt, source="names." + fmt))
    if robot is None:
        assert any(unprintable(c) for c in given)
    else:
        assert robot.joints[0].name == given == robot.name
        assert not any(unprintable(c) for c in given)


def test_fuzz_seeds_are_valid():
    # the mutations start from valid inputs, so the fuzz explores near-valid files
    assert parse_document(SEEDS_YAML[0], "yaml").n == 4
    assert robot_from_model(parse_urdf_text(SEED_URDF)).n == 3


@pytest.mark.parametrize("text", ["", " ", "<", "<robot>", "<robot/>", "<?xml version='1.0'?>", "\x00<robot/>"])
def test_tiny_urdf_inputs(text):
    _reads_or_input_error(lambda: robot_from_model(parse_urdf_text(text)))


#: Hostile inputs of under 1 kB each: every one must be refused with exit status 2 within 5 s of CPU
#: and 500 MB of address space (the promise for any input under 1 kB).
HOSTILE_SMALL = {
    "bomb.yaml": ALIAS_BOMB,
    "merge_bomb.yaml": "a: &a {x: 1, y: 2}\n" + "".join(
        f"{k}: &{k} {{{', '.join(f'<<: *{p}' if i == 0 else f'k{i}: *{p}' for i in range(10))}}}\n"
        for p, k in zip("abcdefgh", "bcdefghi")) + "robkin: 1\njoints: *i\n",
    "deep.yaml": "robkin: 1\njoints: " + "[" * 990,
    "deep.json": '{"robkin": 1, "joints": ' + "[" * 990,
    "digits.json": '{"robkin": 1, "joints": [' + "9" * 900 + "]}",
    "power.yaml": "robkin: 1\njoints: [revolute]\ndh: {rows: [['9**9**9**9', 0, 0, 0]]}\n",
    "parens.yaml": "robkin: 1\njoints: [revolute]\ndh: {rows: [['" + "(" * 95 + "1/0" + ")" * 95 + "', 0, 0, 0]]}\n",
    "entities.urdf": BOMB,
    "deep.urdf": '<robot name="r">' + "<link>" * 140 + "</robot>",
}


@pytest.mark.skipif(sys.platform != "linux", reason="resource limits as on Linux")
def test_hostile_small_inputs_under_memory_and_time_limits(tmp_path):
    for name, text in HOSTILE_SMALL.items():
        assert len(text.encode()) < 1024, name
        (tmp_path / name).write_text(text)
    script = f"""
import resource, sys, time
resource.setrlimit(resource.RLIMIT_AS, ({500 << 20}, {500 << 20}))
resource.setrlimit(resource.RLIMIT_CPU, ({5 * len(HOSTILE_SMALL) + 5}, {5 * len(HOSTILE_SMALL) + 5}))
from robkin.cli import main
for name in {sorted(HOSTILE_SMALL)!r}:
    t = time.process_time()
    status = main(["convert", {str(tmp_path)!r} + "/" + name, "--to", "dh"])
    print("RESULT", name, status, round(time.process_time() - t, 3), flush=True)
"""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    results = [line.split()[1:] for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert [r[0] for r in results] == sorted(HOSTILE_SMALL)
    for name, status, seconds in results:
        assert status == "2" and float(seconds) < 5.0, (name, status, seconds)
    errors = [line for line in proc.stderr.splitlines() if line.startswith("robkin: error:")]
    assert len(errors) == len(HOSTILE_SMALL), proc.stderr
