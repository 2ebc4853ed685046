"""Compiled robot-file scans: one pass of the standard library's expat over a URDF (``urdf_scan``) or an
SDF (``sdf_scan``), through its C capsule (``expat_capi.pxd``), and the numbers of XML attributes for
every reader (``attribute_numbers``)."""
