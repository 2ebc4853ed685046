"""The help text of ``robkin convert``: its formats, options explained, and examples (run as printed
by ``tests/test_examples.py``). The representations' lines come from the registry
(``robkin.representations.registry``: each one's ``help``)."""

from __future__ import annotations

__all__ = ["epilog", "formats_text"]

_TEMPLATE = """\
formats:
{representations}  json/yaml a robot document with every section             urdf      a URDF file (a URDF input's whole file)
  mjcf      a MuJoCo model (MJCF) that simulates: bodies, geoms, meshes, inertials, actuators
  usd       a UsdPhysics articulation for Isaac Sim, Isaac Lab and Newton (.usda text, .usd/.usdc
            binary; needs usd-core: pip install 'robkin[usd]'): rigid bodies with mass, centre of mass
            and principal inertia, revolute/prismatic joints with limits and drives (effort as
            maxForce), fixed joints, colliders and visual meshes inline; read back and checked (USD
            holds joint frames and masses as float32: FK and masses agree to ~1e-7 of the robot's size)
code for other toolboxes (need no robkin; names and numbers from the input are data in them, never code):
  rtb       a Python file defining `robot`, a Robotics Toolbox DHRobot (--convention mdh: modified DH)
            with base, tool, offsets, limits and each link's mass, centre of mass and inertia in its
            DH frame: robot.fkine, robot.rne and robot.gravload equal robkin's
  matlab    a MATLAB/Octave script (.m) defining the struct `robot` (DH or --convention mdh table,
            base, tool, limits, mass properties) and `robot_fk`: T = robot_fk(q)
  eaik      the joint axes H and offsets P that EAIK's IK takes: JSON, or a Python file (-o x.py)
  opw       the seven OPW parameters (a1 a2 b c1 c2 c3 c4) with joint offsets and sign corrections
            of an industrial 6R arm (ortho-parallel base, spherical wrist), as moveit_opw_kinematics
            reads them (YAML, or JSON); other arms are refused with the condition they fail

Without -o a readable table (or the document/URDF/MJCF text) goes to stdout; --json prints the
robot document with the chosen section as JSON instead of a table. With -o FILE a robot document
(.yaml/.yml/.json) holding the joints and the chosen section is written (or the whole document for
json/yaml, or the URDF/MJCF). Several inputs need -o DIR; every input is read and converted first,
and files are written only if all of them succeed. Output goes to a temporary file renamed into
place, so a failed run never leaves a partial or clobbered file.

Angles are in radians unless --degrees is given: then the table on stdout shows degrees, and a
written robot document holds its angles in degrees and says 'angles: degrees'. Tables note where an
offset had to go into the base or tool transform, and warn (with the FK error measured) where a DH
or modified DH table cannot be exact (nearly parallel axes: use --to hayati). The table on stdout shows
values closer to 0 than 1e-9 (lengths: times the robot's size) as 0 and says so in a note; files
and --json carry more digits (see 'Numbers in files').

Tables as input: a CSV table written with --format csv reads back as INPUT (its header says which
table it is, except a PoE's frame: --from poe or poe-body), and so do bare rows as pasted from a paper
('a d alpha theta [R|P]' per line, .txt/.csv/.tsv) with --from dh or mdh (poe: screw rows then 'M ...';
rpy-xyz: n + 2 rows).

Tables for papers and spreadsheets: --format csv|markdown|latex with a table --to (dh, mdh, hayati, poe,
poe-body, rpy-xyz, gjd) writes the table as CSV (reads back: the fixed transforms follow the rows
after an empty line), Markdown or LaTeX (a table environment; matrices use amsmath); -o names a .csv,
.md or .tex file.

Numbers in files: tables and YAML documents write each value as the shortest decimal that keeps the
table's FK within 1e-12 of the robot's size (0.3839999999999999 is written 0.384, -4.16e-18 is 0);
--digits N writes N significant digits, and --exact every digit, so that the file reads back to the
very same floats (JSON documents always keep every digit). --to opw writes its seven lengths the same
way (0.365, not 0.36500000000000005; --exact: every digit). --pi writes angles that are exactly k*pi/m as
such (-pi/2, 3*pi/4).

Mass properties: when the input has them (URDF/MJCF/SDF inertials, or m, r, I on a document's rows),
every table carries each link's mass m (kg), centre of mass r (m) and inertia about it I (kg m^2:
Ixx, Iyy, Izz, Ixy, Iyz, Ixz) in that table's own link frame i (DH, Hayati: frame {i} after joint i;
modified DH: frame {i} on joint i's axis; RPY-XYZ: joint i's frame; PoE: its reference frame at q = 0),
everything rigidly attached to a link (fixed links, the tool) merged in: a block under the table on
stdout, m/r/I on the rows of a document, ten more columns in CSV/Markdown/LaTeX. The base body's (frame
{0}) is on a row 0 '(base)' with the kinematic cells empty (DH, MDH, Hayati, PoE) or on RPY-XYZ's world
row, and reads back from CSV, so 'robkin check t.csv robot.urdf' compares the whole robot; LaTeX puts
the mass columns in tabulars of their own (an A4 page holds a 7-joint arm). A table with them
converts back (--to urdf: <inertial>s) with the same mass matrix and gravity torques.

Chains: --base-link / --tip-link given once apply to every robot file among the inputs; given once
per input, in input order, the k-th belongs to the k-th input ('-' = that file's default, and what a
robot document takes). A base or tip may be any link rigidly attached to the chain's end (UR's
'base', 'tool0'). A folder given with -o (several inputs, or a name ending in '/') that does not exist
is created in an existing one, once every input has been converted; so is the folder of
--to mjcf -o FOLDER/robot.xml (the model and its meshes).

Joint variables are the same in every output: q_i means the same configuration in the DH table, the
PoE and the URDF it came from (same sign, same zero); a note on stderr says so for URDF input.

{mjcf}
examples:
  robkin convert rrpr.yaml --to poe
  robkin convert rrpr.yaml --to dh --layout paper
  robkin convert ur5.urdf --tip-link tool0 --to dh -o ur5_dh.yaml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to mdh --json
  robkin convert ur5.urdf --tip-link tool0 --to dh --degrees
  robkin convert ur5.urdf --tip-link tool0 --to hayati -o ur5_hayati.yaml
  robkin convert robot.yaml --to urdf -o robot.urdf
  robkin convert robot.yaml --to mjcf -o robot.xml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to mjcf -o panda_mjcf/panda.xml
  robkin convert ur5.urdf --tip-link tool0 --to mjcf --scene -o ur5/ur5.xml   # then: python -m mujoco.viewer --mjcf=ur5/scene.xml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to mjcf --home 0,-0.785,0,-2.356,0,1.571,0.785 --kp 500 --kv 50 -o p/p.xml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to usd -o panda.usda
  robkin convert ur5.urdf --tip-link tool0 --to mjcf --collision decompose -o ur5/ur5.xml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to rtb -o panda_rtb.py
  robkin convert ur5.urdf --tip-link tool0 --to rtb --convention mdh -o ur5_mdh.py
  robkin convert ur5.urdf --tip-link tool0 --to matlab -o ur5.m
  robkin convert ur5.urdf --tip-link tool0 --to eaik -o ur5_eaik.py
  robkin convert kr6_r700.yaml --to opw -o kr6_opw.yaml
  robkin convert a.yaml b.yaml c.urdf --to yaml -o converted/
  robkin convert ur5.urdf --base-link base --tip-link tool0 --to dh --format latex --pi
  robkin convert ur5.urdf --base-link base --tip-link tool0 --to dh --format csv -o ur5_dh.csv
  robkin convert ur5_dh.yaml --to urdf -o ur5_again.urdf     # the DH rows' m, r, I become inertials
  robkin convert ur5_dh.csv --to mdh
  robkin convert ur5_rows.txt --from dh --to urdf -o ur5_from_rows.urdf
  robkin convert ur5.urdf panda.urdf a.yaml --tip-link tool0 --tip-link panda_hand_tcp --tip-link - --to mdh -o out/
"""


def formats_text() -> str:
    """The registered representations as the help lists them: two short entries a line, a long one
    (several lines, or too wide to share one) on its own."""
    from ...representations.registry import representations

    lines: list[str] = []
    pending: tuple[str, str] | None = None
    for rep in representations():
        if "\n" in rep.help or len(rep.help) > 46:
            if pending:
                lines.append(f"  {pending[0]:<10}{pending[1]}")
                pending = None
            lines.append(f"  {rep.name:<10}{rep.help}")
        elif pending:
            lines.append(f"  {pending[0]:<10}{pending[1]:<48}{rep.name:<10}{rep.help}")
            pending = None
        else:
            pending = (rep.name, rep.help)
    if pending:
        lines.append(f"  {pending[0]:<10}{pending[1]}")
    return "\n".join(lines) + "\n"


def epilog() -> str:
    """The help's epilog with the registered representations in it ({mjcf} left for the MJCF options)."""
    return _TEMPLATE.replace("{representations}", formats_text())
