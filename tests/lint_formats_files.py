"""Hand-written MJCF and SDF arms for the lint tests (the URDF arm of ``lint_files``, in each format): sound,
and each with one planted defect by replacing one piece."""

from __future__ import annotations

MJ_L2_INERTIAL = '<inertial pos="0 0 0.15" mass="2" diaginertia="0.016 0.016 0.003"/>'
MJ_L2_GEOM = '<geom type="box" size="0.04 0.04 0.15" pos="0 0 0.15"/>'


def mjcf_arm(compiler: str = "", asset: str = "", j1_axis: str = "0 0 1", j2_range: str = "-1.5 1.5",
             l2_inertial: str = MJ_L2_INERTIAL, l2_geom: str = MJ_L2_GEOM, l2_name: str = "link2", extra: str = "") -> str:
    return f"""<mujoco model="arm">
  <compiler angle="radian" {compiler}/>
  {asset}
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.05" mass="2"/>
      <body name="link1" pos="0 0 0.05">
        <joint name="joint1" type="hinge" axis="{j1_axis}" range="-2 2"/>
        <inertial pos="0 0 0.15" mass="3" diaginertia="0.025 0.025 0.005"/>
        <geom type="box" size="0.05 0.05 0.15" pos="0 0 0.15"/>
        <body name="{l2_name}" pos="0 0 0.3">
          <joint name="joint2" type="hinge" axis="0 1 0" range="{j2_range}"/>
          {l2_inertial}
          {l2_geom}
          <site name="tool" pos="0 0 0.3"/>
          {extra}
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


SDF_L2_INERTIAL = ("<inertial><pose>0 0 0.15 0 0 0</pose><mass>2</mass><inertia><ixx>0.016</ixx><iyy>0.016</iyy>"
                   "<izz>0.003</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>")
SDF_L2_GEOM = "<box><size>0.08 0.08 0.3</size></box>"
SDF_J2_LIMIT = "<limit><lower>-1.5</lower><upper>1.5</upper><effort>30</effort><velocity>2</velocity></limit>"


def sdf_arm(l2_inertial: str = SDF_L2_INERTIAL, l2_geom: str = SDF_L2_GEOM, j2_axis: str = "0 1 0",
            j2_limit: str = SDF_J2_LIMIT, j2_child: str = "link2") -> str:
    return f"""<?xml version="1.0"?>
<sdf version="1.9">
  <model name="arm">
    <link name="base">
      <inertial><mass>2</mass><inertia><ixx>0.0083</ixx><iyy>0.0083</iyy><izz>0.0133</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
      <collision name="base_c"><geometry><box><size>0.2 0.2 0.1</size></box></geometry></collision>
    </link>
    <link name="link1">
      <pose>0 0 0.05 0 0 0</pose>
      <inertial><pose>0 0 0.15 0 0 0</pose><mass>3</mass><inertia><ixx>0.025</ixx><iyy>0.025</iyy><izz>0.005</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
      <collision name="link1_c"><pose>0 0 0.15 0 0 0</pose><geometry><box><size>0.1 0.1 0.3</size></box></geometry></collision>
    </link>
    <link name="link2">
      <pose>0 0 0.35 0 0 0</pose>
      {l2_inertial}
      <collision name="link2_c"><pose>0 0 0.15 0 0 0</pose><geometry>{l2_geom}</geometry></collision>
    </link>
    <joint name="joint1" type="revolute">
      <parent>base</parent><child>link1</child>
      <axis><xyz>0 0 1</xyz><limit><lower>-2</lower><upper>2</upper><effort>50</effort><velocity>2</velocity></limit></axis>
    </joint>
    <joint name="joint2" type="revolute">
      <parent>link1</parent><child>{j2_child}</child>
      <axis>
        <xyz>{j2_axis}</xyz>
        {j2_limit}
      </axis>
    </joint>
  </model>
</sdf>
"""
