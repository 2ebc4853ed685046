"""The parts of ``robkin convert``: its help text, the output text per format, the MJCF and URDF outputs
with their meshes, the toolbox code formats, and the check of what it wrote against its source."""
