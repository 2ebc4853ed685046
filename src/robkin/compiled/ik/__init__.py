"""Compiled inverse kinematics: the closed-form kernels (``closed_form_*``, on the base class of
``closed_form_kernel``), Levenberg-Marquardt (``lm``), Newton polish of branches (``polish_branches``),
the bookkeeping of solutions (``solutions``) and joint limits (``limits``), and the ``cdef inline``
helpers they share (``subproblems``, ``elimination``, ``newton``, ``nearest``, ``pose_check``)."""
