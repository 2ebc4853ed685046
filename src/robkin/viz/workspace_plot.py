"""The picture of a workspace map (``robkin workspace --plot``): three projections and a 3-D view.

Three slices through the map, each one voxel thick, show how many orientation bins each voxel reaches
(a darker colour: fewer approach directions; blank: unreachable): the x-y slice at the height of the
reachable voxels' centroid, and the x-z and y-z slices through the base's z axis. The 3-D panel is a scatter of the
reachable voxel centres, coloured alike, thinned to at most ``MAX_POINTS`` points (every k-th voxel).
matplotlib is imported only here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..workspace.maps import WorkspaceMap

__all__ = ["plot_workspace", "MAX_POINTS"]

#: Most voxels drawn in the 3-D panel (a denser scatter is slow to draw and no clearer).
MAX_POINTS = 20000


def plot_workspace(wmap: "WorkspaceMap", title: str | None = None) -> "Figure":
    """A figure of ``wmap`` (with ``title`` above it when given): x-y, x-z and y-z slices of ``reachable`` and a 3-D scatter (see the module)."""
    from matplotlib.figure import Figure

    reach = wmap.reachable
    k = len(wmap.directions)
    fig = Figure(figsize=(12, 10), layout="constrained")
    lo = wmap.origin
    hi = wmap.origin + wmap.voxel * np.array(wmap.shape)
    views = (("x", "y", 2), ("x", "z", 1), ("y", "z", 0))
    idx = np.argwhere(reach > 0)
    centroid = wmap.origin + wmap.voxel * (idx.mean(axis=0) + 0.5)
    at, _ = wmap.voxel_index(np.array([0.0, 0.0, centroid[2]]))  # the base's z axis, the centroid's height
    cut = np.clip(at[0], 0, np.array(wmap.shape) - 1)
    image = None
    for n, (a, b, axis) in enumerate(views):
        ax = fig.add_subplot(2, 2, n + 1)
        ia, ib = "xyz".index(a), "xyz".index(b)
        proj = np.take(reach, cut[axis], axis=axis).astype(float)
        level = wmap.origin[axis] + wmap.voxel * (cut[axis] + 0.5)
        proj[proj == 0] = np.nan
        image = ax.imshow(proj.T, origin="lower", extent=(lo[ia], hi[ia], lo[ib], hi[ib]), cmap="viridis",
                          vmin=1, vmax=k, interpolation="nearest")
        ax.set_xlabel(f"{a} (m)")
        ax.set_ylabel(f"{b} (m)")
        ax.set_title(f"{a}-{b} slice at {'xyz'[axis]} = {level:.3g} m")
        ax.plot([0], [0], marker="+", color="red", markersize=12)  # the base origin
    ax3 = fig.add_subplot(2, 2, 4, projection="3d")
    stride = max(1, -(-len(idx) // MAX_POINTS))
    idx = idx[::stride]
    pts = wmap.origin + wmap.voxel * (idx + 0.5)
    ax3.scatter(pts[:, 0], pts[:, 1], pts[:, 2], c=reach[tuple(idx.T)], cmap="viridis", vmin=1, vmax=k, s=2,
                depthshade=False)
    ax3.set_xlabel("x (m)")
    ax3.set_ylabel("y (m)")
    ax3.set_zlabel("z (m)")
    ax3.set_box_aspect((1, 1, 1))
    ax3.set_title("reachable voxels" + (f" (1 in {stride})" if stride > 1 else ""))
    if image is not None:
        fig.colorbar(image, ax=fig.axes, shrink=0.6, label=f"approach directions reached (of {k})")
    volume = float((reach > 0).sum()) * wmap.voxel ** 3
    fig.suptitle(title or f"{wmap.name or 'robot'}: workspace, {wmap.voxel * 100:g} cm voxels, {k} directions, "
                          f"{wmap.samples:,} samples; {volume:.3g} m^3 reachable")
    return fig
