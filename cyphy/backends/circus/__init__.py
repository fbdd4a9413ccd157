"""CyPhyCircus printers: Unicode text (``text``), LaTeX for the CZT tools (``latex``, typeset
by ``pdf``), what they share (``actions``: binding powers), and the reader of the text form
(``reader``), which reads it back into the AST."""
