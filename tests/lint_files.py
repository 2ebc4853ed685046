"""Hand-written URDFs for the lint tests: a sound two-joint arm, and the same arm with one planted defect."""

from __future__ import annotations

from pathlib import Path

#: a sound arm: box links of aluminium-like density (~1000-3000 kg/m^3), inertias of solid boxes
BASE_INERTIAL = ('<inertial><mass value="2"/><inertia ixx="0.0083" iyy="0.0083" izz="0.0133" ixy="0" ixz="0" iyz="0"/>'
                 '</inertial>')
L1_INERTIAL = ('<inertial><origin xyz="0 0 0.15"/><mass value="3"/>'
               '<inertia ixx="0.0250" iyy="0.0250" izz="0.0050" ixy="0" ixz="0" iyz="0"/></inertial>')
L2_INERTIAL = ('<inertial><origin xyz="0 0 0.15"/><mass value="2"/>'
               '<inertia ixx="0.0160" iyy="0.0160" izz="0.0030" ixy="0" ixz="0" iyz="0"/></inertial>')
J1_LIMIT = '<limit lower="-2" upper="2" effort="50" velocity="2"/>'
J2_LIMIT = '<limit lower="-1.5" upper="1.5" effort="30" velocity="2"/>'


def arm(base_inertial: str = BASE_INERTIAL, l1_inertial: str = L1_INERTIAL, l2_inertial: str = L2_INERTIAL,
        j1_limit: str = J1_LIMIT, j2_limit: str = J2_LIMIT, j1_axis: str = "0 0 1", j2_axis: str = "0 1 0",
        l2_geometry: str = '<box size="0.08 0.08 0.3"/>', extra: str = "", j2_extra: str = "",
        l2_name: str = "link2") -> str:
    """URDF text of a base, two revolute joints and a tool frame (each piece replaceable)."""
    return f"""<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    {base_inertial}
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="joint1" type="revolute">
    <parent link="base"/>
    <child link="link1"/>
    <origin xyz="0 0 0.05"/>
    <axis xyz="{j1_axis}"/>
    {j1_limit}
  </joint>
  <link name="link1">
    {l1_inertial}
    <collision><origin xyz="0 0 0.15"/><geometry><box size="0.1 0.1 0.3"/></geometry></collision>
  </link>
  <joint name="joint2" type="revolute">
    <parent link="link1"/>
    <child link="{l2_name}"/>
    <origin xyz="0 0 0.3"/>
    <axis xyz="{j2_axis}"/>
    {j2_limit}
    {j2_extra}
  </joint>
  <link name="{l2_name}">
    {l2_inertial}
    <collision><origin xyz="0 0 0.15"/><geometry>{l2_geometry}</geometry></collision>
  </link>
  <joint name="tool_joint" type="fixed">
    <parent link="{l2_name}"/>
    <child link="tool"/>
    <origin xyz="0 0 0.3"/>
  </joint>
  <link name="tool"/>
  {extra}
</robot>
"""


def write(tmp_path: Path, text: str, name: str = "arm.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def line_of(text: str, needle: str, nth: int = 0) -> int:
    """1-based line of the ``nth`` line holding ``needle``."""
    hits = [k + 1 for k, line in enumerate(text.splitlines()) if needle in line]
    return hits[nth]
