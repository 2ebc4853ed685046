"""Robot documents (YAML/JSON, the contract of ``robkin convert --to yaml|json``).

- ``reader``: reading, validating and cross-checking a document; ``sections``: one section by its
  representation's layout (``robkin.representations.registry``);
- ``writer``: a Robot or one table as a document, and its YAML/JSON text;
- ``vocabulary``: the section and column names both share; ``masses``: the rows' optional ``m``, ``r``, ``I``;
- ``rounding``: documents without rounding noise (every value the shortest decimal within the FK budget).
"""
