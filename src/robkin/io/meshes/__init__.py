"""The mesh files a robot file names: found on disk, checked, and copied beside an output (``files``)."""
