"""Links, bodies and devices: L1-L8, B1-B3, J1-J3, SE1-SE3, AC1-AC3, JSA1."""

from __future__ import annotations
