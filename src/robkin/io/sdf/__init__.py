"""SDF (SDFormat 1.4+, Gazebo's XML) input: ``reader`` (a model's links and joints as a Robot), with
``axes``, ``shapes`` and ``trees`` (models whose links form several trees)."""
