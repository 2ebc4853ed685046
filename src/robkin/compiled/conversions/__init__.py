"""Compiled conversions between representations: the DH / MDH frame placement and the stages of the
table conversions (``frames``), and rigid transforms as twelve plain floats for the robot-file readers
(``pose_rows``)."""
