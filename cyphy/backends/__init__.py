"""Back ends: printers and solvers of what the semantics built. ``circus/`` (CyPhyCircus text,
LaTeX, PDF), ``isabelle/`` (Isabelle/UTP and Ax_CyPhyCircus sessions), ``robot_formats/`` (SDF
XML, URDF, MJCF), ``show/`` (the model as text, JSON, Graphviz, a picture), ``odes.py`` (the
reduced ODEs printed) and ``simulate.py`` (integration with SciPy). Imports only the layers
below (foundation, lang, model, translate, wellformed, semantics)."""
