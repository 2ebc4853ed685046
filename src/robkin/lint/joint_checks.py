"""Joint checks of a URDF: type, limits (order, range, effort, velocity), mimic targets, axes."""

from __future__ import annotations

import numpy as np

from .findings import ERROR, WARNING, Finding
from .urdf_source import JOINT_TYPES, RawUrdf, numbers

__all__ = ["joint_findings", "AXIS_TOL"]

#: an axis whose length differs from 1 by more than this is "not unit" (the tools normalise it silently;
#: 1e-6 is far above the rounding of an axis written with 7+ digits, far below a typo)
AXIS_TOL = 1e-6
#: below this length an axis has no direction (MuJoCo's compiler refuses axes shorter than mjMINVAL)
AXIS_ZERO = 1e-12


def joint_findings(u: RawUrdf) -> list[Finding]:
    f: list[Finding] = []
    names = {j.name for j in u.joints}
    mimic_of: dict[str, str] = {}
    for j in u.joints:
        el = f"joint '{j.name}'"

        def add(sev, code, line, message, fix):
            f.append(Finding(sev, code, u.file, line, el, message, fix))

        if j.type not in JOINT_TYPES:
            add(ERROR, "joint-type", j.line, f"type '{j.type}' is not a URDF joint type",
                "use one of " + ", ".join(JOINT_TYPES))
            continue
        bounded = j.type in ("revolute", "prismatic")
        lim = j.limit_text
        urdf = u.fmt == "urdf"  # urdfdom's own rules: a revolute or prismatic joint's <limit effort velocity>
        if bounded and lim is None and urdf:
            add(ERROR, "limit-missing", j.line, f"a {j.type} joint without <limit> (urdfdom and pinocchio refuse it)",
                '<limit lower="..." upper="..." effort="..." velocity="..."/>')
        if lim is not None:
            lline = j.limit_line or j.line
            lo, hi = numbers(lim.get("lower"), 1), numbers(lim.get("upper"), 1)
            if bounded and lo and hi:
                if lo[0] > hi[0]:
                    add(ERROR, "limits-reversed", lline,
                        f"lower {lo[0]:g} > upper {hi[0]:g}: no position is allowed (MuJoCo silently drops "
                        f"the limit: the joint turns freely; pinocchio keeps an empty range)", f'swap them: lower="{hi[0]:g}" upper="{lo[0]:g}"')
                elif lo[0] == hi[0]:
                    add(WARNING, "limits-zero-range", lline,
                        f"lower = upper = {lo[0]:g}: the joint cannot move, yet MuJoCo ignores the limit "
                        f"(with a warning) and lets it turn freely", 'make it type="fixed", or give it its real range')
            for key in ("effort", "velocity"):
                text = lim.get(key)
                v = numbers(text, 1)
                if text is None and bounded and urdf:
                    add(ERROR, f"{key}-missing", lline, f"<limit> has no {key} (urdfdom refuses the file)",
                        f'add {key}="..." from the datasheet')
                elif text is not None and v is None:
                    add(ERROR, f"{key}-malformed", lline, f"{key}='{text}' is not a number", f"write {key} as a number")
                elif v and v[0] <= 0 and j.type != "fixed":
                    add(WARNING, f"{key}-zero", lline,
                        f"{key} = {v[0]:g}: a simulator that enforces this limit cannot move the joint "
                        f"(pinocchio's {key}Limit is then 0)", f"set {key} from the datasheet")
        if j.mimic_target is not None:
            target = j.mimic_target
            mline = j.mimic_line or j.line
            if not target or target not in names:
                add(WARNING, "mimic-missing", mline, f"mimics joint '{target}', which is not in the file: MuJoCo "
                    f"ignores the <mimic> (with a warning) and pinocchio silently, so the joint moves on its own",
                    "remove the <mimic> or name an existing joint")
            elif target == j.name:
                add(ERROR, "mimic-cycle", mline, "the joint mimics itself (MuJoCo refuses it: 'repeated in equality "
                    "constraint')", "remove the <mimic>")
            else:
                mimic_of[j.name] = target
        if j.type in ("revolute", "continuous", "prismatic", "planar"):
            axis = numbers(j.axis_text, 3) if j.axis_text is not None else (1.0, 0.0, 0.0)
            aline = j.axis_line or j.line
            if axis is None:
                add(ERROR, "axis-malformed", aline, f"axis '{j.axis_text}' is not three numbers",
                    "write " + _axis_text(u.fmt, "x y z"))
            else:
                n = float(np.linalg.norm(axis))
                if n < AXIS_ZERO:
                    add(ERROR, "axis-zero", aline, "axis has zero length: the joint has no direction (MuJoCo refuses "
                        "it; pinocchio divides by zero)", "give the axis its direction, e.g. " + _axis_text(u.fmt, "0 0 1"))
                elif abs(n - 1) > AXIS_TOL:
                    u_ = np.asarray(axis) / n
                    add(WARNING, "axis-not-unit", aline,
                        f"axis has length {n:.6g}, not 1 (MuJoCo and pinocchio normalise it silently)",
                        _axis_text(u.fmt, " ".join(f"{x:.9g}" for x in u_)))
    # mimic chains that come back to themselves
    done: set[str] = set()
    for start in mimic_of:
        path, name = [], start
        while name in mimic_of and name not in path:
            path.append(name)
            name = mimic_of[name]
        if name in path and name not in done:
            cyc = path[path.index(name):]
            done |= set(cyc)
            j = next(x for x in u.joints if x.name == cyc[0])
            f.append(Finding(ERROR, "mimic-cycle", u.file, j.mimic_line or j.line, f"joint '{j.name}'",
                             "mimic joints form a cycle: " + " -> ".join(cyc + [cyc[0]]),
                             "make one joint of the cycle independent (remove its <mimic>)"))
    return f




def _axis_text(fmt: str, xyz: str) -> str:
    """An axis as the format writes it."""
    return {"mjcf": f'axis="{xyz}"', "sdf": f"<xyz>{xyz}</xyz>"}.get(fmt, f'xyz="{xyz}"')
