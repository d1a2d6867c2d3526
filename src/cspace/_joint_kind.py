"""What a joint is, as reported: the vocabulary every layer shares (the report's ``kind``)."""

from __future__ import annotations

from enum import Enum


class JointKind(str, Enum):
    """What a joint is, as reported (the report's ``kind`` field)."""

    REVOLUTE = "revolute"
    CONTINUOUS = "continuous"
    PRISMATIC = "prismatic"
    HELICAL = "helical"
    PLANAR = "planar"
    SPHERICAL = "spherical"
    FLOATING = "floating"
    TRANSLATION = "translation"
    UNIVERSAL = "universal"
    FIXED = "fixed"
    MIMIC = "mimic"
