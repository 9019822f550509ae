"""The ``massline`` command: each subcommand parses its options, calls one library pipeline, prints and writes.

No science lives here (the pipelines are the stages' own, re-exported by :mod:`massline`); no command imports
another (``tests/test_layout.py``). :mod:`.app` builds the parser and maps library errors to the flags that caused
them; the entry point is :mod:`massline.__main__`.
"""
