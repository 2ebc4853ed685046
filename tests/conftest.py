"""Test-suite settings shared by every module.

Hypothesis profile ``ci`` (``pytest --hypothesis-profile=ci``, which ``.ci/run`` selects): the property
tests draw the same examples on every run, so whether a submission lands does not depend on the luck of
the draw. A developer's ``make test`` keeps hypothesis's random search (and its example database), which
is where new counter-examples are found; each one found becomes a named regression test.
"""

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
