"""What the browser GUI's page needs to know of the registered representations (``GET /api/representations``).

The page builds its tables, overlay checkboxes and download buttons from this answer, so that a
representation registered with ``robkin.representations.registry.register`` (of an existing layout)
shows in the GUI without any change to ``static/``. Read from the registry on each request (a few
microseconds: nothing is imported).

The answer::

    {"representations": [        # every representation, in registration order (the order of the tables)
        {"name": "mdh", "section": "mdh", "layout": "link-table", "title": "Modified DH  A = ...",
         "columns": [{"key": "alpha", "label": "α(i-1)", "angle": true}, ...],
         "mass_frame": "frame {i} (on joint i's axis, where link i starts)"}, ...],
     "overlays": [{"name": "dh", "label": "DH"}, ...],      # the checkboxes, in the registry's overlay order
     "downloads": [{"name": "dh", "label": "DH"}, ...]}     # the buttons after YAML, JSON and URDF
"""

from __future__ import annotations

from typing import Any

__all__ = ["gui_representations"]


def gui_representations() -> dict[str, Any]:
    """The registry as the GUI's page shows it (see the module)."""
    from ..representations.registry import overlays, representations
    from .gui_api import EXPORTS

    reps = representations()
    return {
        "representations": [
            {"name": r.name, "section": r.section, "layout": r.layout, "title": r.gui_title or r.title,
             "columns": [{"key": c.key, "label": c.label, "angle": c.angle} for c in r.columns],
             "mass_frame": r.gui_mass_frame or r.mass_frame}
            for r in reps],
        "overlays": [{"name": r.name, "label": r.gui_overlay or r.overlay_label}
                     for r in overlays() if r.gui_overlay is not None],
        "downloads": [{"name": r.name, "label": r.download_label or r.name}
                      for r in sorted(reps, key=lambda r: r.download_rank) if r.name in EXPORTS],
    }
