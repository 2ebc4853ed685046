"""Where the floor of a written scene goes: under the lowest point of the model's geoms at home.

``robkin convert --to mjcf --scene`` puts a floor under the robot. The robot's link origins are not
enough: at home a stretched arm's wrist meshes hang below its base (the UR5's by 43 mm), and a floor
through them is a penetrating contact that kicks the arm on the first step. So the floor goes under the
lowest point of every geom's bounding box (MuJoCo's ``geom_aabb``, in the geom's frame, placed by
``mj_forward`` at the keyframe ``home``): a box corner is never above the geom, so the floor never cuts
a geom (it may lie a little lower than the geom's true lowest point).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["lowest_point"]

#: the eight corners of a unit box, as signs
_CORNERS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)


def lowest_point(text: str, folder: str | Path | None = None) -> float | None:
    """The lowest z (world frame, the model's length unit) of any geom's bounding box at home (the
    keyframe ``home``: ``robkin.collision.exclusions.home_qpos``); None without MuJoCo, without geoms, or
    when MuJoCo cannot compile ``text`` (the model's own check says why).

    Parameters
    ----------
    text : str
        MJCF text of the model.
    folder : path, optional
        Where the model's mesh files are named from (its folder).
    """
    try:
        import mujoco
    except ImportError:
        return None
    from ..collision.exclusions import compile_draft, home_qpos

    try:
        model = compile_draft(text, folder)
    except Exception:  # noqa: BLE001 - MuJoCo's refusal is reported by the simulation check
        return None
    if model.ngeom == 0:
        return None
    data = mujoco.MjData(model)
    data.qpos[:] = home_qpos(model)
    mujoco.mj_forward(model, data)
    aabb = np.asarray(model.geom_aabb).reshape(model.ngeom, 6)
    centre, half = aabb[:, :3], aabb[:, 3:]
    local = centre[:, None, :] + _CORNERS[None, :, :] * half[:, None, :]          # (ngeom, 8, 3)
    R = np.asarray(data.geom_xmat).reshape(model.ngeom, 3, 3)
    world_z = np.einsum("gj,gcj->gc", R[:, 2, :], local) + np.asarray(data.geom_xpos)[:, 2:3]
    return float(world_z.min())
