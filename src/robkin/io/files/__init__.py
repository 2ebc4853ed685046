"""What every reader and writer shares: files read with a byte cap (``input_files``), written all-or-nothing
(``atomic``), untrusted YAML (``safe_yaml``), numbers read as people type them (``numbers``) and written as
text (``float_text``), the one JSON style (``jsontext``) and XML attribute quoting (``xmltext``)."""
