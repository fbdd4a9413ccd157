"""The CyPhyCircus semantics of a platform mapping (the paper's rules): its AST (``ast``), the
rules (``rules``), names (``names``), walking actions (``walk``), values (``values``), and
the composition for one mapping (``build``)."""
