"""Robot trees as the XML readers (URDF, MJCF, SDF) give them: one joint of a tree (``tree_joint``), the
path of a chain through it (``chain_path``), locked joints (``joint_limits``) and XML parsed safely
(``xml_parse``)."""
