"""What ``cyphy show`` and ``cyphy view`` print: the p-model as text or JSON (``pmodel``), the
d-model (``dmodel``), the kinematic graph for Graphviz (``graph``), a picture (``view``)."""
