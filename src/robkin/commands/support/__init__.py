"""What several commands share: the input and option helpers (``common``), the chain options
(``chains``), the printed and JSON output (``output``), the batch files of ``fk``/``ik`` (``batches``),
the gravity torques of ``fk`` (``gravity``) and ``check MODEL MEASUREMENTS`` (``check_measurements``).

Not commands themselves: ``cli.COMMANDS`` names only the modules beside this package."""
