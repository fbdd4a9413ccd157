"""The RoboSim language: grammar and parser (``parser``, ``robosim.lark``, ``parse_cache``),
the syntax tree with spans (``ast``), name resolution and scopes (``resolve``, ``scopes``,
``placement``), typing (``typing``), the files read together (``workspace``), and the built-in
``library/physmod``. Imports only the foundation."""
