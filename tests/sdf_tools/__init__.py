"""Validation tools for generated SDF: libsdformat 12 (``sdfcheck``) and PyBullet."""

from .validate import SdfToolsMissing, build_checker, check_sdf, pybullet_load, pybullet_load_many

__all__ = ["SdfToolsMissing", "build_checker", "check_sdf", "pybullet_load", "pybullet_load_many"]
