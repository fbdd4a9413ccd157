"""Checkers of generated artefacts with external tools: ``flowstar/`` (scenarios, the Flow*
export, runs, verdicts and witnesses). Built on :mod:`cyphy.pipeline`, never on the API."""
