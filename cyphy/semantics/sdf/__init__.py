"""The paper's SDF rules (section 5): the XML tree as data (``tree``), the names
(``names``), the annotations' templates (``annotations``), the rules (``rules``), and the
model as trees of links for URDF and MJCF (``robot_tree``)."""
