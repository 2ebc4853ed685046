"""Robots as code and parameters for other toolboxes (``robkin convert --to rtb|matlab|eaik|opw``).

``rtb`` (Peter Corke's Robotics Toolbox for Python), ``matlab`` (MATLAB / GNU Octave), ``eaik`` (EAIK's H and
P), ``opw`` (the OPW parameters of an industrial arm, found by ``representations.opw``, as a document); ``tables`` is the DH table they share and
``code_literals`` writes input text and numbers as literals of the programs, never as code.
"""
