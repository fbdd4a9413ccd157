"""An explicit opt-in for links without inertial information (``--default-inertial sdf``, a
scenario's ``default_inertial = "sdf"``): give them the mass properties SDFormat gives a
link whose ``<inertial>`` (or part of it) is left out, so that the kinematic tree has
equations of motion as the simulator that loads the SDF has.

SDFormat's specification (``sdf/1.6/inertial.sdf`` of gazebosim/sdformat, installed with
libsdformat as ``/usr/share/sdformat12/1.6/inertial.sdf``): ``<mass>`` defaults to 1.0,
``<inertia>``'s ``ixx``, ``iyy``, ``izz`` to 1.0 and ``ixy``, ``ixz``, ``iyz`` to 0.0, and the
inertial frame's ``<pose>`` to the link frame (``0 0 0 0 0 0``). Gazebo loads a link
without ``<inertial>`` with these values (1 kg, 1 kg·m² about each axis, centre of mass at
the link's origin).

Without the opt-in nothing changes: a link without mass moved by a joint stays an
``E-DYNAMICS`` error. With it, each link given the defaults gets a warning: 1 kg and
1 kg·m² are placeholders, rarely the robot's values.
"""

from __future__ import annotations

from cyphy import codes
from cyphy.diagnostics import Report
from cyphy.model.elements import ElaboratedModel
from cyphy.model.inertia import Inertial
from cyphy.model.poses import Pose

DEFAULT_INERTIAL = codes.code("W-DEFAULT-INERTIAL", codes.W,
                              "a link without inertial information gets SDF's defaults")

CHOICES = ("sdf",)
"""The values ``--default-inertial`` accepts."""

SDF_DEFAULT = Inertial(1.0, Pose.identity(), (1.0, 0.0, 0.0, 1.0, 0.0, 1.0))
"""SDFormat's ``<inertial>`` defaults: mass 1 kg, inertia the identity (kg·m²) about the
link frame's origin, in its axes."""


def apply_default_inertial(model: ElaboratedModel, report: Report, kind: str) -> None:
    """Give every link of ``model`` that has no mass (no inertial information of its own
    nor from its bodies) the defaults of ``kind`` (``"sdf"``), with a warning per link."""
    if kind not in CHOICES:
        raise ValueError(f"unknown default inertial '{kind}' (choose {', '.join(CHOICES)})")
    for link in model.links:
        if link.inertial is not None and link.inertial.mass is not None:
            continue
        link.inertial, link.inertial_source = SDF_DEFAULT, "sdf-default"
        report.report(DEFAULT_INERTIAL,
                      f"link {link.name} has no inertial information: SDF's defaults apply "
                      "(mass 1 kg, inertia 1 kg m² about each axis at the link's origin), as "
                      "Gazebo loads a link without <inertial>", link.span,
                      "give the link 'inertial information' (or its bodies masses) to model "
                      "its real mass properties")
