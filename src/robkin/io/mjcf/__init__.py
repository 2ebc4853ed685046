"""MJCF (MuJoCo's XML) in and out.

In: ``source`` (one XML tree, includes and defaults resolved), ``reader`` (the body tree as a Robot), with
``poses``, ``geoms`` and ``equality``. Out: ``format`` (the entry point ``mjcf_from_robot`` and MuJoCo's
quaternions), ``tree`` (which link becomes which body), ``writer``, ``geoms_write``, ``inertial``,
``actuators``, and the meshes beside the model (``files``, ``meshes``, ``mesh_parts``).
"""
