"""Computing with a robot: Jacobians and manipulability, inverse kinematics.

- ``jacobian``: space, body and base-frame geometric Jacobians; Yoshikawa manipulability, inverse
  condition number, minimum singular value (one configuration or a batch).
- ``ik``: ``ik(robot, T)`` (also ``Robot.ik``) - closed form where the geometry allows, else the
  vectorised Levenberg-Marquardt solver of ``lm``; every answer checked by forward kinematics;
  ``ik_text``: its result as text (``str(result)``, ``robkin ik``).
- ``scara``, ``analytic6r``: the closed forms (SCARA-type arms; 6R arms with a spherical wrist or
  of the Universal Robots type), found by ``closed_form.closed_form_solver`` from the joint axes and
  solved by the compiled kernels ``robkin.compiled.ik.closed_form_6r`` / ``closed_form_scara``.
- ``lm``, ``pose_error``, ``limits``: the pieces they are built from.

Submodules are imported on use, so ``import robkin`` stays light.
"""
