"""Robot description formats written from the semantics' trees: SDF as XML (``sdf_xml``),
URDF (``urdf``) and MuJoCo's MJCF (``mjcf``)."""
